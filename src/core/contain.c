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
#include <sys/socket.h>
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

/* Writes n bytes to a pipe, or to a socket (without SIGPIPE where the reader has gone). */
static bool put_all(int fd, bool sock, const void *p, size_t n)
{
    const unsigned char *c = p;
    while (n) {
        ssize_t w = sock ? send(fd, c, n, MSG_NOSIGNAL) : write(fd, c, n);
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
    bool ok = put_all(fd, false, &rc, sizeof rc) && put_all(fd, false, &wl, sizeof wl) &&
              put_all(fd, false, why, wl) && put_all(fd, false, &len, sizeof len) &&
              put_all(fd, false, out.data, (size_t)len);
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

/* ------------------------------------------------------------------ the import worker
 *
 * One worker per process (not per scene: a scene's folder comes with each job, so one
 * process serves them all, and the host keeps one idle process, not one per scene). It is
 * forked by the first job, from the calling thread, and keeps only its end of a unix socket
 * (moved to descriptor 3) and the standard descriptors pointed at /dev/null; every other
 * descriptor it inherited is closed. A job is [head][bytes] with the folder's descriptor
 * passed beside the head (SCM_RIGHTS), and the worker closes that descriptor when the job
 * ends. Before each job it sets its soft limits: RLIMIT_AS the host's mapping at its start
 * plus the allowance plus twice the memory the job may take, below a hard limit fixed by the
 * first job (a job that needs more gets a fresh worker); RLIMIT_CPU the processor time the
 * worker has used plus the job's (SIGXCPU ends it), its hard limit left open because the
 * count only grows: the host's wall-clock deadline (4x the time, plus 5 s) backs it. It
 * answers [status][why][processor time of the job][length][bytes]. A crash, a limit, a
 * deadline or a failed job ends it (what a hostile file left in its heap serves no other
 * file); it dies with the thread that forked it (PR_SET_PDEATHSIG) and exits when the socket
 * closes. A worker serves one folder in its life: a job of another folder replaces it (jobs
 * without one, image decoding, share any). The host writes with MSG_NOSIGNAL, so a worker gone at any moment is a failed
 * job, never a SIGPIPE. A lock keeps one job at a time in the worker; a job that finds it
 * taken runs in a child of its own (limen__contain_run), as does one where no worker
 * starts. */
#include <pthread.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>

int limen__contain_no_worker;

typedef struct job_head {
    uint64_t fn;                /* the limen__job_fn (the worker is a fork: the same code) */
    uint64_t as;                /* RLIMIT_AS soft for the job; 0: the hard limit */
    double cpu_seconds;         /* 0: none */
    uint64_t len;               /* bytes that follow */
} job_head;

static struct {
    pthread_mutex_t lock;
    pid_t pid, owner, tid;      /* the worker; the process and the thread that forked it */
    int sock;
    uint64_t as_hard;           /* its hard RLIMIT_AS (0: none) */
    size_t base;                /* the host's mapping when it was forked */
    double cpu_told;            /* processor time it has told of */
    bool has_folder;            /* it has been handed a folder: this one */
    dev_t dev;
    ino_t ino;
} wk = { PTHREAD_MUTEX_INITIALIZER, 0, 0, 0, -1, 0, 0, 0, false, 0, 0 };

/* Whether the thread that forked the worker has ended (its PR_SET_PDEATHSIG ends the
 * worker, at once or a moment later). */
static bool forker_gone_at(pid_t tid)
{
    if (tid == (pid_t)syscall(SYS_gettid))
        return false;
    char path[64];
    snprintf(path, sizeof path, "/proc/self/task/%d", (int)tid);
    return access(path, F_OK) != 0;
}

static bool forker_gone(void)
{
    return forker_gone_at(wk.tid);
}

int limen__contain_worker_pid(void)
{
    pthread_mutex_lock(&wk.lock);
    int pid = wk.pid && wk.owner == getpid() ? (int)wk.pid : 0;
    pthread_mutex_unlock(&wk.lock);
    return pid;
}

static double self_cpu(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return seconds(ru.ru_utime) + seconds(ru.ru_stime);
}

static bool send_all(int sock, const void *p, size_t n)
{
    return put_all(sock, true, p, n);
}

/* The head with fd beside it (fd < 0: none). */
static bool send_head(int sock, const job_head *h, int fd)
{
    union {
        struct cmsghdr c;
        char buf[CMSG_SPACE(sizeof(int))];
    } u;
    memset(&u, 0, sizeof u);
    struct iovec iov = { (void *)h, sizeof *h };
    struct msghdr m = { .msg_iov = &iov, .msg_iovlen = 1 };
    if (fd >= 0) {
        m.msg_control = u.buf;
        m.msg_controllen = sizeof u.buf;
        struct cmsghdr *c = CMSG_FIRSTHDR(&m);
        c->cmsg_level = SOL_SOCKET;
        c->cmsg_type = SCM_RIGHTS;
        c->cmsg_len = CMSG_LEN(sizeof(int));
        memcpy(CMSG_DATA(c), &fd, sizeof fd);
    }
    ssize_t w;
    while ((w = sendmsg(sock, &m, MSG_NOSIGNAL)) < 0 && errno == EINTR)
        ;
    if (w < 0)
        return false;
    return (size_t)w == sizeof *h || send_all(sock, (const char *)h + w, sizeof *h - (size_t)w);
}

/* In the worker: the head and the descriptor beside it; false at the socket's end. */
static bool recv_head(int sock, job_head *h, int *fd)
{
    *fd = -1;
    union {
        struct cmsghdr c;
        char buf[CMSG_SPACE(sizeof(int))];
    } u;
    struct iovec iov = { h, sizeof *h };
    struct msghdr m = { .msg_iov = &iov, .msg_iovlen = 1, .msg_control = u.buf,
                        .msg_controllen = sizeof u.buf };
    ssize_t r;
    while ((r = recvmsg(sock, &m, MSG_CMSG_CLOEXEC)) < 0 && errno == EINTR)
        ;
    if (r <= 0)
        return false;
    for (struct cmsghdr *c = CMSG_FIRSTHDR(&m); c; c = CMSG_NXTHDR(&m, c))
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS &&
            c->cmsg_len == CMSG_LEN(sizeof(int)))
            memcpy(fd, CMSG_DATA(c), sizeof *fd);
    if ((size_t)r < sizeof *h && read_exact(sock, (char *)h + r, sizeof *h - (size_t)r, 0))
        return false;
    return true;
}

static void worker_main(int sock, pid_t host, uint64_t as_hard)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != host)
        _exit(0);
    static const int fatal[] = { SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGTRAP, SIGSYS,
                                 SIGXCPU, SIGPIPE };
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        signal(fatal[i], SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    /* the socket to 3 first (it may be 0 to 2 where the host closed those), then the
     * standard descriptors to /dev/null */
    if (sock != 3) {
        if (dup2(sock, 3) != 3)
            _exit(3);
        sock = 3;
    }
    int null = open("/dev/null", O_RDWR | O_CLOEXEC);
    if (null >= 0) {
        dup2(null, 0);
        dup2(null, 1);
        dup2(null, 2);
    }
    /* nothing of the host's but the socket: each job's folder comes with the job */
    if (syscall(SYS_close_range, 4u, ~0u, 0u) != 0)
        for (int fd = 4; fd < 65536; fd++)
            close(fd);
    struct rlimit no_core = { 0, 0 };
    setrlimit(RLIMIT_CORE, &no_core);
    if (as_hard) {
        struct rlimit r = { (rlim_t)as_hard, (rlim_t)as_hard };
        setrlimit(RLIMIT_AS, &r);
    }
    for (;;) {
        job_head h;
        int fd;
        if (!recv_head(sock, &h, &fd))
            _exit(0);
        limen__block job = { 0 };
        if (h.len && (!(job.data = malloc((size_t)h.len)) ||
                      read_exact(sock, job.data, (size_t)h.len, 0)))
            _exit(3);
        job.len = job.cap = (size_t)h.len;
        struct rlimit r;
        getrlimit(RLIMIT_AS, &r);
        r.rlim_cur = h.as && (r.rlim_max == RLIM_INFINITY || h.as < r.rlim_max) ? h.as
                                                                                : r.rlim_max;
        setrlimit(RLIMIT_AS, &r);
        double before = self_cpu();
        getrlimit(RLIMIT_CPU, &r);
        r.rlim_cur = h.cpu_seconds > 0 ? (rlim_t)ceil(before + h.cpu_seconds) : r.rlim_max;
        setrlimit(RLIMIT_CPU, &r);
        limen__block out = { 0 };
        char why[512] = "";
        int32_t rc = ((limen__job_fn)(uintptr_t)h.fn)(&job, fd, &out, why, sizeof why);
        if (fd >= 0)
            close(fd);
        free(job.data);
        if (!rc && out.failed) {
            rc = 1;
            snprintf(why, sizeof why, "out of memory");
        }
        double cpu = self_cpu() - before;
        uint32_t wl = rc ? (uint32_t)strnlen(why, sizeof why - 1) : 0;
        uint64_t len = rc ? 0 : out.len;
        bool ok = send_all(sock, &rc, sizeof rc) && send_all(sock, &wl, sizeof wl) &&
                  send_all(sock, why, wl) && send_all(sock, &cpu, sizeof cpu) &&
                  send_all(sock, &len, sizeof len) && send_all(sock, out.data, (size_t)len);
        free(out.data);
        if (!ok || rc)
            _exit(0);
    }
}

/* Ends the worker (lock held) and gives the processor time it spent untold. */
static double worker_end(bool kill_it)
{
    double spent = 0;
    if (wk.pid && wk.owner == getpid()) {
        if (kill_it)
            kill(wk.pid, SIGKILL);
        close(wk.sock);
        int status;
        struct rusage ru;
        memset(&ru, 0, sizeof ru);
        while (wait4(wk.pid, &status, 0, &ru) < 0 && errno == EINTR)
            ;
        spent = seconds(ru.ru_utime) + seconds(ru.ru_stime) - wk.cpu_told;
    }
    wk.pid = 0;
    wk.sock = -1;
    wk.cpu_told = 0;
    return spent > 0 ? spent : 0;
}

/* The RLIMIT_AS a job under lim gets, for a worker forked at base. */
static uint64_t job_as(const limen__contain_limits *lim, size_t base)
{
    if (!lim->mem_bytes || !base)
        return 0;
    size_t as = base + ALLOWANCE;
    return lim->mem_bytes > (SIZE_MAX - as) / 2 ? 0 : as + 2 * lim->mem_bytes;
}

/* Starts a worker (lock held) whose hard limit is what lim allows; false if none can. */
static bool worker_start(const limen__contain_limits *lim)
{
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
        return false;
    size_t base = mapped();
    uint64_t hard = job_as(lim, base);
    pid_t host = getpid();
    pid_t pid = fork();
    if (pid < 0) {
        close(sv[0]);
        close(sv[1]);
        return false;
    }
    if (pid == 0) {
        close(sv[0]);
        worker_main(sv[1], host, hard);
    }
    close(sv[1]);
    wk.pid = pid;
    wk.owner = host;
    wk.tid = (pid_t)syscall(SYS_gettid);
    wk.has_folder = false;
    wk.sock = sv[0];
    wk.as_hard = hard;
    wk.base = base;
    wk.cpu_told = 0;
    return true;
}

typedef struct job_arg {
    limen__job_fn fn;
    limen__block job;
    int fd;
} job_arg;

static int job_in_child(void *arg, limen__block *out, char *why, size_t why_size)
{
    job_arg *j = arg;
    return j->fn(&j->job, j->fd, out, why, why_size);
}

int limen__contain_job(limen__job_fn fn, const limen__block *job, int fd,
                       const limen__contain_limits *lim, limen__block *out, char *why,
                       size_t why_size, double *cpu_spent)
{
    memset(out, 0, sizeof *out);
    *cpu_spent = 0;
    why[0] = '\0';
    job_arg ja = { fn, { job->data, job->len, job->len, 0, false }, fd };
    if (limen__contain_no_worker || pthread_mutex_trylock(&wk.lock) != 0)
        return limen__contain_run(job_in_child, &ja, lim, out, why, why_size, cpu_spent);
    if (wk.pid && wk.owner != getpid()) {       /* a fork of the host: not its worker */
        close(wk.sock);
        wk.pid = 0;
        wk.sock = -1;
    }
    /* a worker gone while idle (its thread ended), or one whose hard limit is below what
     * this job may take, is replaced */
    bool retried = false;
again:
    if (wk.pid && forker_gone())
        *cpu_spent += worker_end(true);
    /* a worker sees one folder in its life: a job of another folder gets a fresh one, so
     * that whatever a file did to one worker reaches no other scene's files */
    struct stat fst;
    bool folder = fd >= 0 && fstat(fd, &fst) == 0;
    if (wk.pid && folder && wk.has_folder && (fst.st_dev != wk.dev || fst.st_ino != wk.ino))
        *cpu_spent += worker_end(true);
    if (wk.pid) {
        int status;
        uint64_t as = job_as(lim, wk.base);
        if (waitpid(wk.pid, &status, WNOHANG) != 0) {
            wk.pid = 0;
            close(wk.sock);
            wk.sock = -1;
        } else if (wk.as_hard && (!as || as > wk.as_hard))
            *cpu_spent += worker_end(true);
    }
    if (!wk.pid && !worker_start(lim)) {
        pthread_mutex_unlock(&wk.lock);
        return limen__contain_run(job_in_child, &ja, lim, out, why, why_size, cpu_spent);
    }
    if (folder && !wk.has_folder) {
        wk.has_folder = true;
        wk.dev = fst.st_dev;
        wk.ino = fst.st_ino;
    }
    job_head h = { (uint64_t)(uintptr_t)fn, job_as(lim, wk.base), lim->cpu_seconds,
                   (uint64_t)job->len };
    size_t most = lim->answer_bytes ? lim->answer_bytes
                  : lim->mem_bytes && lim->mem_bytes < SIZE_MAX - 65536 ? lim->mem_bytes + 65536
                                                                        : SIZE_MAX;
    double deadline = lim->cpu_seconds > 0 ? now() + 4 * lim->cpu_seconds + 5 : 0;
    int outcome = LIMEN__CONTAIN_OK, got = 1;
    int32_t rc = 0;
    uint32_t wl = 0;
    uint64_t len = 0;
    double cpu = 0;
    char w[4096];
    unsigned char *data = NULL;
    if (send_head(wk.sock, &h, fd) && send_all(wk.sock, job->data, job->len) &&
        (got = read_exact(wk.sock, &rc, sizeof rc, deadline)) == 0 &&
        (got = read_exact(wk.sock, &wl, sizeof wl, deadline)) == 0) {
        if (wl >= sizeof w)
            got = 1;
        else if ((got = read_exact(wk.sock, w, wl, deadline)) == 0 &&
                 (got = read_exact(wk.sock, &cpu, sizeof cpu, deadline)) == 0)
            got = read_exact(wk.sock, &len, sizeof len, deadline);
    }
    if (got == 0 && !rc && len) {
        if (len > most || !(data = malloc((size_t)len)))
            outcome = LIMEN__CONTAIN_MEMORY;
        else
            got = read_exact(wk.sock, data, (size_t)len, deadline);
    }
    if (got == 2)
        outcome = LIMEN__CONTAIN_TIME;
    if (got == 0 && outcome == LIMEN__CONTAIN_OK && !rc) {
        /* told its time, kept for the next job */
        wk.cpu_told += cpu > 0 ? cpu : 0;
        *cpu_spent += cpu > 0 ? cpu : 0;
        pthread_mutex_unlock(&wk.lock);
        *out = (limen__block){ .data = data, .len = (size_t)len, .cap = (size_t)len };
        return outcome;
    }
    /* anything else ends it: a failed job exits by itself, the rest are killed */
    pid_t pid = wk.pid, tid = wk.tid;
    bool failed = got == 0 && outcome == LIMEN__CONTAIN_OK && rc;
    if (failed) {
        wk.cpu_told += cpu > 0 ? cpu : 0;
        *cpu_spent += cpu > 0 ? cpu : 0;
    }
    int status = 0;
    memset(&status, 0, sizeof status);
    if (!failed)
        kill(pid, SIGKILL);
    close(wk.sock);
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR)
        ;
    double total = seconds(ru.ru_utime) + seconds(ru.ru_stime);
    if (!failed && total > wk.cpu_told)
        *cpu_spent += total - wk.cpu_told;
    wk.pid = 0;
    wk.sock = -1;
    wk.cpu_told = 0;
    pthread_mutex_unlock(&wk.lock);
    free(data);
    if (failed) {
        last_code = rc;
        snprintf(why, why_size, "%.*s", (int)wl, w);
        return LIMEN__CONTAIN_FAILED;
    }
    if (outcome != LIMEN__CONTAIN_OK)
        return outcome;
    /* killed with the thread that forked it, which ended meanwhile: once more, in a worker
     * of this thread's */
    if (!retried && got == 1 && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL &&
        forker_gone_at(tid)) {
        retried = true;
        if (pthread_mutex_lock(&wk.lock) == 0)
            goto again;
    }
    /* the worker died under the job: a signal, SIGKILL by its processor time limit too */
    if (WIFSIGNALED(status) && WTERMSIG(status) != SIGKILL) {
        int sig = WTERMSIG(status);
        if (sig == SIGXCPU)
            return LIMEN__CONTAIN_TIME;
        snprintf(why, why_size, "%s", strsignal(sig));
        return LIMEN__CONTAIN_CRASHED;
    }
    snprintf(why, why_size, "it exited without a whole answer");
    return LIMEN__CONTAIN_CRASHED;
}
