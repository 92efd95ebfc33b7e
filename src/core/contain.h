/* contain.h - running a callback in a child process under limits (address space, processor
 * time), with a block of bytes handed back through a pipe: what a crash, an endless loop or a
 * memory bomb in an importer takes down is the child, never the host. Not part of the public
 * API. */
#ifndef LIMEN_CORE_CONTAIN_H
#define LIMEN_CORE_CONTAIN_H

#include <stdbool.h>
#include <stddef.h>

/* A growing block of bytes (malloc'd); failed is set, and nothing more kept, once a growth
 * fails. */
typedef struct limen__block {
    unsigned char *data;
    size_t len, cap, at;        /* at: where limen__block_get reads next */
    bool failed;
} limen__block;

bool limen__block_put(limen__block *b, const void *p, size_t n);
/* Copies the next n bytes into p; false, copying nothing, if fewer are left. */
bool limen__block_get(limen__block *b, void *p, size_t n);
/* The next n bytes in place (NULL if fewer are left). */
const void *limen__block_take(limen__block *b, size_t n);
void limen__block_free(limen__block *b);

/* Runs in the child: fills out (with limen__block_put, or by handing it a malloc'd buffer as
 * data, len and cap: nothing is copied), or returns nonzero (a code for the caller) with
 * why. */
typedef int (*limen__contained_fn)(void *arg, limen__block *out, char *why, size_t why_size);

typedef struct limen__contain_limits {
    size_t mem_bytes;           /* memory the child may take beyond what the host has mapped
                                 * (an allowance for the importer's own is added); 0: none */
    double cpu_seconds;         /* processor time; 0: none */
    size_t answer_bytes;        /* the most the child may hand back; 0: mem_bytes (+ 64 KiB) */
} limen__contain_limits;

enum {
    LIMEN__CONTAIN_OK,
    LIMEN__CONTAIN_FAILED,      /* the callback said no: why is its reason */
    LIMEN__CONTAIN_CRASHED,     /* a signal (a fault, an abort, the memory limit's) */
    LIMEN__CONTAIN_TIME,        /* out of processor time (or wall time: 4x, plus 5 s) */
    LIMEN__CONTAIN_MEMORY,      /* handed back more than the memory limit */
    LIMEN__CONTAIN_SYSTEM       /* no child could be made (fork, pipe): why says */
};

/* Runs fn(arg) in a child under lim and hands back its block (the caller frees it; its data
 * is one malloc'd buffer of exactly len bytes, read straight from the pipe). Returns
 * LIMEN__CONTAIN_*; *cpu_spent gets the child's processor time, whatever the outcome. */
int limen__contain_run(limen__contained_fn fn, void *arg, const limen__contain_limits *lim,
                       limen__block *out, char *why, size_t why_size, double *cpu_spent);
/* The code the callback returned in the last LIMEN__CONTAIN_FAILED of this thread. */
int limen__contain_code(void);

/* ---- the import worker: one process kept for the next jobs ----
 *
 * A job is fn run over a block of bytes (the job's own copy of what it needs: the worker was
 * forked before the job existed) and at most one descriptor (the folder it reads beneath,
 * passed over a unix socket), under lim. One worker per process, started by the first job;
 * a job that finds it busy (another thread's) runs in a child of its own, as
 * limen__contain_run does, and so does one where no worker can start. A crash, a limit, a
 * timeout or a failed job (fn returned nonzero) ends the worker: the next job starts a fresh
 * one. Returns LIMEN__CONTAIN_* as limen__contain_run does. */
typedef int (*limen__job_fn)(limen__block *job, int fd, limen__block *out, char *why,
                             size_t why_size);
int limen__contain_job(limen__job_fn fn, const limen__block *job, int fd,
                       const limen__contain_limits *lim, limen__block *out, char *why,
                       size_t why_size, double *cpu_spent);
/* tests: the worker's process id (0: none running); 1 forces the fork-per-job path */
int limen__contain_worker_pid(void);
extern int limen__contain_no_worker;

#endif
