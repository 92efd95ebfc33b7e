/* contain.c - a callback run in a child process under limits (core/contain.h).
 *
 * The child is forked from the calling thread and gets setrlimit limits before it runs the
 * callback: RLIMIT_AS the address space already mapped plus twice the memory allowed plus a
 * fixed allowance (256 MiB) for the importer's own code, stacks and heap slack, RLIMIT_CPU the processor time allowed,
 * RLIMIT_CORE 0 (a crash leaves no core file). It writes [status][why][length][bytes] into a
 * pipe and exits with _exit, running no handler of the host's. The parent reads the pipe to
 * its end, kills the child if it hands back more than allowed or runs past four times its
 * processor time in wall time (it cannot block on a file: every file opens without
 * blocking, core/confine.c), and reaps it with wait4 to learn its processor time. Nothing the
 * child allocated outlives it. */
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/contain.h"

#define ALLOWANCE ((size_t)256 << 20)   /* the importer's code, stacks, heap slack and tables */

bool limen__block_put(limen__block *b, const void *p, size_t n)
{
    if (b->failed)
        return false;
    if (n > SIZE_MAX / 2 - b->len) {
        b->failed = true;
        return false;
    }
    if (b->len + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n)
            cap *= 2;
        unsigned char *more = realloc(b->data, cap);
        if (!more) {
            b->failed = true;
            return false;
        }
        b->data = more;
        b->cap = cap;
    }
    if (n)
        memcpy(b->data + b->len, p, n);
    b->len += n;
    return true;
}

const void *limen__block_take(limen__block *b, size_t n)
{
    if (b->at > b->len || n > b->len - b->at)
        return NULL;
    const void *p = b->data + b->at;
    b->at += n;
    return p;
}

bool limen__block_get(limen__block *b, void *p, size_t n)
{
    const void *q = limen__block_take(b, n);
    if (q && n)
        memcpy(p, q, n);
    return q != NULL;
}

void limen__block_free(limen__block *b)
{
    free(b->data);
    memset(b, 0, sizeof *b);
}

static _Thread_local int last_code;

int limen__contain_code(void)
{
    return last_code;
}

static double seconds(struct timeval t)
{
    return (double)t.tv_sec + (double)t.tv_usec * 1e-6;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Reads n bytes: 0, or 1 at the end of the pipe (the child gone), 2 past the deadline. */
static int read_exact(int fd, void *p, size_t n, double deadline)
{
    unsigned char *c = p;
    while (n) {
        if (deadline) {
            double left = deadline - now();
            struct pollfd pf = { .fd = fd, .events = POLLIN };
            int r = left > 0 ? poll(&pf, 1, (int)(left * 1000) + 1) : 0;
            if (r < 0 && errno == EINTR)
                continue;
            if (r == 0)
                return 2;
        }
        ssize_t got = read(fd, c, n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            return 1;
        c += got;
        n -= (size_t)got;
    }
    return 0;
}

static bool write_all(int fd, const void *p, size_t n)
{
    const unsigned char *c = p;
    while (n) {
        ssize_t w = write(fd, c, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        c += w;
        n -= (size_t)w;
    }
    return true;
}

/* The address space mapped now (bytes), from /proc/self/statm; 0 if unknown. */
static size_t mapped(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (f) {
        if (fscanf(f, "%lu", &pages) != 1)
            pages = 0;
        fclose(f);
    }
    return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

static void child(int fd, limen__contained_fn fn, void *arg, const limen__contain_limits *lim,
                  size_t base)
{
    /* the host's handlers (a crash reporter, a fuzzer's) are not the child's: a fault here
     * ends the child, which the parent reads as a crash */
    static const int fatal[] = { SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGTRAP, SIGSYS,
                                 SIGXCPU };
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        signal(fatal[i], SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    /* the library never prints: what the importer says on its way down goes nowhere */
    int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null >= 0) {
        dup2(null, 1);
        dup2(null, 2);
        close(null);
    }
    struct rlimit no_core = { 0, 0 };
    setrlimit(RLIMIT_CORE, &no_core);
    if (lim->cpu_seconds > 0) {
        rlim_t s = (rlim_t)ceil(lim->cpu_seconds);  /* whole seconds, rounded up */
        struct rlimit cpu = { s, s + 1 };           /* SIGXCPU, then SIGKILL a second later */
        setrlimit(RLIMIT_CPU, &cpu);
    }
    /* relative to what is mapped already: under a sanitizer that includes its shadow
     * reservations, so the limit still holds what the child maps anew */
    if (lim->mem_bytes && base) {
        /* twice what is allowed: an importer holds its own scene and the copy it hands
         * back at once */
        size_t as = base + ALLOWANCE;
        as = lim->mem_bytes > (SIZE_MAX - as) / 2 ? SIZE_MAX : as + 2 * lim->mem_bytes;
        struct rlimit r = { (rlim_t)as, (rlim_t)as };
        setrlimit(RLIMIT_AS, &r);
    }
    limen__block out = { 0 };
    char why[512] = "";
    int32_t rc = fn(arg, &out, why, sizeof why);
    if (!rc && out.failed) {
        rc = 1;
        snprintf(why, sizeof why, "out of memory");
    }
    uint32_t wl = rc ? (uint32_t)strnlen(why, sizeof why - 1) : 0;
    uint64_t len = rc ? 0 : out.len;
    bool ok = write_all(fd, &rc, sizeof rc) && write_all(fd, &wl, sizeof wl) &&
              write_all(fd, why, wl) && write_all(fd, &len, sizeof len) &&
              write_all(fd, out.data, (size_t)len);
    _exit(ok ? 0 : 3);
}

int limen__contain_run(limen__contained_fn fn, void *arg, const limen__contain_limits *lim,
                       limen__block *out, char *why, size_t why_size, double *cpu_spent)
{
    memset(out, 0, sizeof *out);
    *cpu_spent = 0;
    why[0] = '\0';
    int p[2];
    if (pipe2(p, O_CLOEXEC) != 0) {
        snprintf(why, why_size, "cannot make a pipe: %s", strerror(errno));
        return LIMEN__CONTAIN_SYSTEM;
    }
    size_t base = lim->mem_bytes ? mapped() : 0;
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(why, why_size, "cannot start a process: %s", strerror(errno));
        close(p[0]);
        close(p[1]);
        return LIMEN__CONTAIN_SYSTEM;
    }
    if (pid == 0) {
        close(p[0]);
        child(p[1], fn, arg, lim, base);
    }
    close(p[1]);
    /* what the child may hand back: at most the memory allowed (or answer_bytes) */
    size_t most = lim->answer_bytes ? lim->answer_bytes
                  : lim->mem_bytes && lim->mem_bytes < SIZE_MAX - 65536 ? lim->mem_bytes + 65536
                                                                        : SIZE_MAX;
    double deadline = lim->cpu_seconds > 0 ? now() + 4 * lim->cpu_seconds + 5 : 0;
    int outcome = LIMEN__CONTAIN_OK, got;
    int32_t rc = 0;
    uint32_t wl = 0;
    uint64_t len = 0;
    char w[4096];
    unsigned char *data = NULL;
    /* header, reason, length, then the answer straight into a buffer of its size */
    if ((got = read_exact(p[0], &rc, sizeof rc, deadline)) == 0 &&
        (got = read_exact(p[0], &wl, sizeof wl, deadline)) == 0) {
        if (wl >= sizeof w)
            got = 1;
        else if ((got = read_exact(p[0], w, wl, deadline)) == 0)
            got = read_exact(p[0], &len, sizeof len, deadline);
    }
    if (got == 0 && !rc && len) {
        if (len > most || !(data = malloc((size_t)len)))
            outcome = LIMEN__CONTAIN_MEMORY;
        else
            got = read_exact(p[0], data, (size_t)len, deadline);
    }
    if (got == 2)
        outcome = LIMEN__CONTAIN_TIME;
    close(p[0]);
    if (outcome != LIMEN__CONTAIN_OK)
        kill(pid, SIGKILL);
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR)
        ;
    *cpu_spent = seconds(ru.ru_utime) + seconds(ru.ru_stime);
    if (outcome == LIMEN__CONTAIN_OK && WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        outcome = sig == SIGXCPU || (sig == SIGKILL && lim->cpu_seconds > 0 &&
                                     *cpu_spent >= lim->cpu_seconds)
                      ? LIMEN__CONTAIN_TIME : LIMEN__CONTAIN_CRASHED;
        if (outcome == LIMEN__CONTAIN_CRASHED)
            snprintf(why, why_size, "%s", strsignal(sig));
    }
    if (outcome == LIMEN__CONTAIN_OK && got == 1) {
        outcome = LIMEN__CONTAIN_CRASHED;
        snprintf(why, why_size, "it exited without a whole answer");
    }
    if (outcome == LIMEN__CONTAIN_OK && rc) {
        outcome = LIMEN__CONTAIN_FAILED;
        last_code = rc;
        snprintf(why, why_size, "%.*s", (int)wl, w);
    }
    if (outcome == LIMEN__CONTAIN_OK) {
        *out = (limen__block){ .data = data, .len = (size_t)len, .cap = (size_t)len };
        return outcome;
    }
    free(data);
    return outcome;
}
