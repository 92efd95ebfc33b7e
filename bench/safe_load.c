/* safe_load.c - what containing an import costs (core/contain.c): a scene script loading a
 * mesh in safe mode (the import and the texture decoding in the import worker, a child
 * process kept between loads, the arrays handed back through a socket) against the same
 * script trusted (imported in the process).
 * The bunny (scenes/data/bunny.glb, and as an OBJ: assimp's OBJ reader takes and fills a
 * 16 MiB buffer whatever the file's size) and a binary PLY of 100,000 triangles made here; wall
 * and processor time (the process's and its children's, the live import worker's included),
 * medians of runs that alternate the two modes after one load of each, and the ratio
 * measured in this one run; beside them the fallback (a child forked per import), timed
 * after the interleaved pairs (each fork leaves the host's heap copy-on-write, a cost that
 * would land on the next load). Last, what a host with a 256 MiB heap pays for a worker
 * forked from it (big_host).
 *
 *   safe_load [--out DIR] [--runs N]
 *
 * Writes DIR/safe_load.csv and DIR/safe_load.txt; a line per mesh on stderr. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/contain.h"
#include "limen.h"
#include "timing.h"

static void die(const char *what)
{
    fprintf(stderr, "safe_load: %s\n", what);
    exit(1);
}

/* Processor time of the live children of this process (the import worker), from /proc:
 * schedstat's time on a processor, in nanoseconds (stat's ticks are 10 ms, too coarse for a
 * load of a few), in milliseconds. */
static double live_children_ms(void)
{
    double ms = 0;
    DIR *d = opendir("/proc");
    struct dirent *e;
    while (d && (e = readdir(d))) {
        if (e->d_name[0] < '1' || e->d_name[0] > '9')
            continue;
        char path[300], buf[1024];
        snprintf(path, sizeof path, "/proc/%s/stat", e->d_name);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
        buf[n] = '\0';
        char *p = strrchr(buf, ')');     /* the name may hold spaces */
        int ppid;
        if (!p || sscanf(p + 2, "%*c %d", &ppid) != 1 || ppid != (int)getpid())
            continue;
        snprintf(path, sizeof path, "/proc/%s/schedstat", e->d_name);
        unsigned long long ns = 0;
        if ((f = fopen(path, "r"))) {
            if (fscanf(f, "%llu", &ns) == 1)
                ms += (double)ns * 1e-6;
            fclose(f);
        }
    }
    if (d)
        closedir(d);
    return ms;
}

/* Processor time of this process, its reaped children and its live ones (the persistent
 * import worker is never reaped between loads), in milliseconds. */
static double all_cpu_ms(void)
{
    struct rusage self, kids;
    getrusage(RUSAGE_SELF, &self);
    getrusage(RUSAGE_CHILDREN, &kids);
    return (self.ru_utime.tv_sec + self.ru_stime.tv_sec + kids.ru_utime.tv_sec +
            kids.ru_stime.tv_sec) * 1e3 +
           (self.ru_utime.tv_usec + self.ru_stime.tv_usec + kids.ru_utime.tv_usec +
            kids.ru_stime.tv_usec) * 1e-3 + live_children_ms();
}

static void copy_file(const char *from, const char *to)
{
    FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
    if (!a || !b)
        die("cannot copy a mesh");
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, a)) > 0)
        fwrite(buf, 1, n, b);
    fclose(a);
    fclose(b);
}

/* A strip of nt triangles as a binary PLY. */
static void write_ply(const char *path, int nt)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        die("cannot write the PLY");
    int nv = nt + 2;
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n", nv, nt);
    for (int i = 0; i < nv; i++) {
        float v[3] = { (float)(i / 2), (float)(i % 2), (float)((i * 7) % 13) * 0.01f };
        fwrite(v, sizeof v, 1, f);
    }
    for (int i = 0; i < nt; i++) {
        unsigned char three = 3;
        int ix[3] = { i, i + 1 + (i % 2), i + 2 - (i % 2) };
        fwrite(&three, 1, 1, f);
        fwrite(ix, sizeof ix, 1, f);
    }
    fclose(f);
}

static void one_load(const char *script, int trusted, double *wall, double *cpu)
{
    limen_script *sc = NULL;
    double w0 = now_ms(), c0 = all_cpu_ms();
    limen_status st = limen_script_load(script, &(limen_script_desc){ .trusted = trusted,
                                                                      .memory_cap = -1,
                                                                      .instruction_budget = -1 },
                                        &sc);
    *wall = now_ms() - w0;
    *cpu = all_cpu_ms() - c0;
    if (st) {
        fprintf(stderr, "%s\n", limen_script_error(sc));
        die("the load failed");
    }
    limen_script_destroy(sc);
}

/* Resident memory of process pid, in MB (0 if unknown). */
static long rss_mb(int pid)
{
    char path[64], line[256];
    snprintf(path, sizeof path, "/proc/%d/status", pid);
    FILE *f = fopen(path, "r");
    long kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmRSS: %ld", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return kb / 1024;
}

/* What a host with a big heap pays for a worker forked from it: heap_mb of heap written
 * once, then rewritten before and after a safe load from a folder the worker has not seen
 * (which forks a fresh worker from the host as it is now). Wall time of the rewrites, the
 * faults of the second, the worker's resident memory after it; a line into ft and stderr. */
static void big_host(const char *dir, int heap_mb, FILE *ft)
{
    char sub[300], script[400];
    snprintf(sub, sizeof sub, "%s/big_host", dir);
    mkdir(sub, 0755);
    snprintf(script, sizeof script, "%s/bunny.glb", sub);
    copy_file("scenes/data/bunny.glb", script);
    snprintf(script, sizeof script, "%s/big_host.lua", sub);
    FILE *f = fopen(script, "w");
    if (!f)
        die("cannot write the script");
    fputs("local limen = require 'limen' local s = limen.scene{}\n"
          "s:mesh{ file = 'bunny.glb' }\nreturn s\n", f);
    fclose(f);
    size_t n = (size_t)heap_mb << 20;
    unsigned char *heap = malloc(n);
    if (!heap)
        die("no memory for the big host");
    /* the barriers keep the writes (the compiler would drop stores to memory freed after) */
    memset(heap, 1, n);
    __asm__ volatile("" : : "r"(heap) : "memory");
    double t0 = now_ms();
    memset(heap, 2, n);
    __asm__ volatile("" : : "r"(heap) : "memory");
    double before = now_ms() - t0, w, c;
    one_load(script, 0, &w, &c);
    struct rusage r0, r1;
    getrusage(RUSAGE_SELF, &r0);
    t0 = now_ms();
    memset(heap, 3, n);
    __asm__ volatile("" : : "r"(heap) : "memory");
    double after = now_ms() - t0;
    getrusage(RUSAGE_SELF, &r1);
    int pid = limen__contain_worker_pid();
    long worker = pid ? rss_mb(pid) : 0;
    free(heap);
    char line[512];
    snprintf(line, sizeof line, "a host of %d MiB heap: rewriting it %.1f ms before a safe load "
             "that forks the worker, %.1f ms after (x%.1f, %ld faults); the worker then holds "
             "%ld MB (the host's old pages)\n", heap_mb, before, after, after / before,
             r1.ru_minflt - r0.ru_minflt, worker);
    fputs(line, ft);
    fputs(line, stderr);
    unlink(script);
    snprintf(script, sizeof script, "%s/bunny.glb", sub);
    unlink(script);
    rmdir(sub);
}

int main(int argc, char **argv)
{
    const char *out = "build/bench";
    int runs = 7;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi(argv[++i]);
    }
    if (runs < 1 || runs > 99)
        die("--runs: 1 to 99");
    char dir[] = "/tmp/limen-safe-load.XXXXXX", path[256];
    if (!mkdtemp(dir))
        die("no temporary folder");
    snprintf(path, sizeof path, "%s/bunny.glb", dir);
    copy_file("scenes/data/bunny.glb", path);
    snprintf(path, sizeof path, "%s/bunny.obj", dir);
    copy_file("scenes/data/bunny.obj", path);
    snprintf(path, sizeof path, "%s/strip.ply", dir);
    write_ply(path, 100000);
    const char *meshes[3][2] = { { "bunny", "bunny.glb" }, { "bunny_obj", "bunny.obj" },
                                 { "100k", "strip.ply" } };
    char csv[512], txt[512];
    snprintf(csv, sizeof csv, "%s/safe_load.csv", out);
    snprintf(txt, sizeof txt, "%s/safe_load.txt", out);
    FILE *fc = fopen(csv, "w"), *ft = fopen(txt, "w");
    if (!fc || !ft)
        die("cannot write the results");
    fprintf(fc, "mesh,trusted_wall_ms,trusted_cpu_ms,safe_wall_ms,safe_cpu_ms,wall_ratio,cpu_ratio,"
            "fork_wall_ms,fork_cpu_ms,fork_wall_ratio,fork_cpu_ratio\n");
    for (int m = 0; m < 3; m++) {
        char script[256], text[256];
        snprintf(script, sizeof script, "%s/%s.lua", dir, meshes[m][0]);
        snprintf(text, sizeof text, "local limen = require 'limen' local s = limen.scene{}\n"
                 "s:mesh{ file = '%s' }\nreturn s\n", meshes[m][1]);
        FILE *f = fopen(script, "w");
        if (!f)
            die("cannot write the script");
        fputs(text, f);
        fclose(f);
        double tw[99], tc[99], sw[99], scpu[99], fw[99], fcpu[99], w, c;
        one_load(script, 1, &w, &c);        /* warm the caches once */
        double first_w, first_c;            /* the first safe load (starts the worker) */
        one_load(script, 0, &first_w, &first_c);
        for (int r = 0; r < runs; r++) {
            one_load(script, 1, &tw[r], &tc[r]);
            one_load(script, 0, &sw[r], &scpu[r]);
        }
        /* the fallback, a child forked per import, after: a fork leaves every page of this
         * process's heap to be faulted in again at its next write (copy on write), which
         * would land on whichever load came next (4,096 faults for the 16 MiB buffer of an
         * OBJ's read, 65 ms here) */
        limen__contain_no_worker = 1;
        for (int r = 0; r < runs; r++)
            one_load(script, 0, &fw[r], &fcpu[r]);
        limen__contain_no_worker = 0;
        double fa = median(fw, runs), fb = median(fcpu, runs);
        double a = median(tw, runs), b = median(tc, runs), x = median(sw, runs),
               y = median(scpu, runs);
        fprintf(fc, "%s,%.2f,%.2f,%.2f,%.2f,%.3f,%.3f,%.2f,%.2f,%.3f,%.3f\n", meshes[m][0], a, b,
                x, y, x / a, y / b, fa, fb, fa / a, fb / b);
        fprintf(ft, "%s: trusted %.1f ms wall %.1f ms cpu, safe (contained) %.1f ms wall %.1f ms "
                "cpu: x%.3f wall, x%.3f cpu\n", meshes[m][0], a, b, x, y, x / a, y / b);
        fprintf(stderr, "%s: trusted %.1f ms wall %.1f ms cpu, safe (contained) %.1f ms wall "
                "%.1f ms cpu: x%.3f wall, x%.3f cpu\n", meshes[m][0], a, b, x, y, x / a, y / b);
        fprintf(ft, "%s: safe, a child forked per import %.1f ms wall %.1f ms cpu: x%.3f wall, "
                "x%.3f cpu\n", meshes[m][0], fa, fb, fa / a, fb / b);
        fprintf(stderr, "%s: safe, a child forked per import %.1f ms wall %.1f ms cpu: x%.3f "
                "wall, x%.3f cpu\n", meshes[m][0], fa, fb, fa / a, fb / b);
        fprintf(ft, "%s: the first safe load of the process %.1f ms wall %.1f ms cpu\n",
                meshes[m][0], first_w, first_c);
        fprintf(stderr, "%s: the first safe load of the process %.1f ms wall %.1f ms cpu\n",
                meshes[m][0], first_w, first_c);
        unlink(script);
    }
    fclose(fc);
    big_host(dir, 256, ft);
    fclose(ft);
    const char *made[3] = { "bunny.glb", "bunny.obj", "strip.ply" };
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, made[i]);
        unlink(path);
    }
    rmdir(dir);
    return 0;
}
