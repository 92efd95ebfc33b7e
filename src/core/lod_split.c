/* lod_split.c - a big mesh simplified in blocks (limen__lod_simplify_split, declared in
 * core/lod_weld.h). meshoptimizer's simplifier holds tables of about 70 bytes a corner of
 * what it is given (its edges' collapses, their order, the quadrics), a hundred megabytes and
 * more at a million triangles, and runs on one core. Here the triangles are cut into blocks
 * of nearby ones (by the Morton code of their centres: whole regions of the surface), each
 * simplified alone over its own vertices with its border held where it is (the simplifier's
 * lock on borders), so that the blocks still meet without a crack; two blocks at a time, on
 * two threads, each taking the next block when it comes free. The tables are then a
 * block's, and the result depends on the blocks alone, not on which thread made which. A
 * block's held border is simplified by the next level, whose blocks are cut elsewhere, or
 * whose source is small enough to be taken whole. */
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

#include "core/lod_target.h"
#include "core/lod_weld.h"
#include "core/pages.h"

#define SPLIT_WORKERS 2         /* blocks simplified at once (this machine's cores) */
#define MORTON_BITS 10          /* per axis, of a triangle's centre */
_Static_assert(MORTON_BITS == 10, "limen__morton3 interleaves 10 bits an axis");
#define BUCKET_BITS 16          /* the leading bits of the code that choose its block */

typedef struct split {
    const float *pos;           /* per vertex of what is simplified */
    uint32_t nv;
    const uint32_t *in;         /* its corners */
    const uint32_t *tris;       /* the triangles, block after block */
    const size_t *first;        /* per block: its first in tris; first[nblocks] the end */
    uint32_t nblocks;
    const size_t *want;         /* per block: the indices it is simplified towards */
    double target;              /* the simplifier's error to stop at, in the mesh's units
                                 * (INFINITY: none) */
    uint32_t **made;            /* per block: its result, in the vertices of pos */
    size_t *nmade;
    double *err;                /* per block: the simplifier's error, in the mesh's units */
    uint32_t step;              /* workers */
    atomic_uint next;           /* the next block a worker takes */
} split;

typedef struct worker {
    split *s;
    bool ok;
} worker;

/* Simplifies one block over its own vertices (numbered in the order its corners meet
 * them), local: per vertex of the mesh, UINT32_MAX (and left so). */
static bool block_simplify(split *s, uint32_t b, uint32_t *local)
{
    size_t nt = s->first[b + 1] - s->first[b], n = nt * 3;
    const uint32_t *tris = s->tris + s->first[b];
    uint32_t nv = 0;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = s->in[(size_t)tris[t] * 3 + k];
            if (local[v] == UINT32_MAX)
                local[v] = nv++;
        }
    uint32_t *idx = limen__malloc_populated(sizeof *idx * (n ? n : 1)),
             *from = limen__malloc_populated(sizeof *from * (nv ? nv : 1)),
             *out = malloc(sizeof *out * (n ? n : 1));
    float *pos = limen__malloc_populated(sizeof *pos * 3 * (nv ? nv : 1));
    bool ok = idx && from && out && pos;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = s->in[(size_t)tris[t] * 3 + k], l = local[v];
            if (ok) {
                idx[t * 3 + k] = l;
                from[l] = v;
                memcpy(&pos[(size_t)l * 3], &s->pos[(size_t)v * 3], sizeof(float) * 3);
            }
        }
    for (size_t i = 0; i < n; i++)
        local[s->in[(size_t)tris[i / 3] * 3 + i % 3]] = UINT32_MAX;
    size_t made = 0;
    if (ok) {
        /* the simplifier's errors are relative to the extent of what it is given: the
         * block's, not the mesh's */
        double scale = meshopt_simplifyScale(pos, nv, sizeof(float) * 3);
        float target = isinf(s->target) || !(scale > 0) ? FLT_MAX : (float)(s->target / scale);
        float e = 0;
        made = meshopt_simplify(out, idx, n, pos, nv, sizeof(float) * 3, s->want[b], target,
                                meshopt_SimplifyLockBorder, &e);
        for (size_t i = 0; i < made; i++)
            out[i] = from[out[i]];
        s->err[b] = (double)e * scale;
        /* kept until every block is done: no more than it holds */
        uint32_t *fit = realloc(out, sizeof *out * (made ? made : 1));
        if (fit)
            out = fit;
    }
    free(idx);
    free(from);
    free(pos);
    s->made[b] = ok ? out : NULL;
    s->nmade[b] = made;
    if (!ok)
        free(out);
    return ok;
}

static void *work(void *arg)
{
    worker *w = arg;
    split *s = w->s;
    uint32_t *local = limen__malloc_populated(sizeof *local * (s->nv ? s->nv : 1));
    w->ok = local != NULL;
    if (local)
        memset(local, 0xff, sizeof *local * s->nv);
    /* blocks taken as workers come free (a block's result is its own, whichever takes it) */
    while (w->ok) {
        uint32_t b = atomic_fetch_add_explicit(&s->next, 1, memory_order_relaxed);
        if (b >= s->nblocks)
            break;
        w->ok = block_simplify(s, b, local);
    }
    free(local);
    return NULL;
}

/* Each triangle's block: the leading bits of its centre's Morton code (over the box of
 * what is simplified) choose it, the blocks as even in triangles as those bits allow.
 * Into tris (the triangles, block after block) and first (nblocks + 1). */
static bool cut_blocks(const float *pos, const uint32_t *in, size_t nt, uint32_t nblocks,
                       uint32_t *tris, size_t *first)
{
    enum { NBUCKETS = 1 << BUCKET_BITS };
    uint32_t *bucket = limen__malloc_populated(sizeof *bucket * (nt ? nt : 1));
    size_t *count = calloc(NBUCKETS, sizeof *count);
    uint32_t *block_of = malloc(sizeof *block_of * NBUCKETS);
    if (!bucket || !count || !block_of) {
        free(bucket);
        free(count);
        free(block_of);
        return false;
    }
    float lo[3] = { FLT_MAX, FLT_MAX, FLT_MAX }, hi[3] = { -FLT_MAX, -FLT_MAX, -FLT_MAX };
    for (size_t i = 0; i < nt * 3; i++)
        for (int a = 0; a < 3; a++) {
            lo[a] = limen__lesserf(lo[a], pos[(size_t)in[i] * 3 + a]);
            hi[a] = limen__greaterf(hi[a], pos[(size_t)in[i] * 3 + a]);
        }
    for (size_t t = 0; t < nt; t++) {
        uint32_t q[3];
        for (int a = 0; a < 3; a++) {
            double c = ((double)pos[(size_t)in[t * 3] * 3 + a] + pos[(size_t)in[t * 3 + 1] * 3 + a] +
                        pos[(size_t)in[t * 3 + 2] * 3 + a]) / 3;
            double f = hi[a] > lo[a] ? (c - lo[a]) / ((double)hi[a] - lo[a]) : 0;
            /* NaN (none comes: positions are finite) to 0, as fmax would */
            q[a] = (uint32_t)limen__lesser((1 << MORTON_BITS) - 1,
                                           limen__greater(0, f * (1 << MORTON_BITS)));
        }
        /* the first axis's bit the highest of each three */
        uint32_t code = limen__morton3(q[2], q[1], q[0]);
        bucket[t] = code >> (3 * MORTON_BITS - BUCKET_BITS);
        count[bucket[t]]++;
    }
    /* a bucket's block: where the triangles before it put it among nblocks even shares */
    size_t before = 0;
    for (uint32_t k = 0; k < NBUCKETS; k++) {
        uint64_t b = (uint64_t)before * nblocks / nt;
        block_of[k] = b < nblocks ? (uint32_t)b : nblocks - 1;
        before += count[k];
    }
    memset(first, 0, sizeof *first * (nblocks + 1));
    for (size_t t = 0; t < nt; t++)
        first[block_of[bucket[t]] + 1]++;
    for (uint32_t b = 0; b < nblocks; b++)
        first[b + 1] += first[b];
    /* placed in the triangles' order within each block */
    size_t *at = count;         /* reused: per block, where its next goes */
    for (uint32_t b = 0; b < nblocks; b++)
        at[b] = first[b];
    for (size_t t = 0; t < nt; t++)
        tris[at[block_of[bucket[t]]]++] = (uint32_t)t;
    free(bucket);
    free(count);
    free(block_of);
    return true;
}

size_t limen__lod_simplify_split(const float *pos, uint32_t nv, const uint32_t *in, size_t n,
                                 size_t want, float target_error, float *err, uint32_t *out,
                                 size_t block_tris, bool threads, bool *ok)
{
    size_t nt = n / 3;
    if (block_tris < 1)
        block_tris = 1;
    uint32_t nblocks = (uint32_t)((nt + block_tris - 1) / block_tris);
    if (nblocks < 1)
        nblocks = 1;
    uint32_t *tris = limen__malloc_populated(sizeof *tris * (nt ? nt : 1));
    size_t *first = malloc(sizeof *first * (nblocks + 1)), *want_of = malloc(sizeof *want_of * nblocks),
           *nmade = calloc(nblocks, sizeof *nmade);
    uint32_t **made = calloc(nblocks, sizeof *made);
    double *errs = calloc(nblocks, sizeof *errs);
    *ok = tris && first && want_of && nmade && made && errs &&
          cut_blocks(pos, in, nt, nblocks, tris, first);
    size_t total = 0;
    if (*ok) {
        double scale = meshopt_simplifyScale(pos, nv, sizeof(float) * 3);
        /* each block towards its share of want */
        for (uint32_t b = 0; b < nblocks; b++)
            want_of[b] = (size_t)((double)want * (double)(first[b + 1] - first[b]) / (double)nt) / 3 * 3;
        split s = { .pos = pos, .nv = nv, .in = in, .tris = tris, .first = first,
                    .nblocks = nblocks, .want = want_of,
                    .target = target_error >= FLT_MAX ? INFINITY : (double)target_error * scale,
                    .made = made, .nmade = nmade, .err = errs,
                    .step = threads ? SPLIT_WORKERS : 1 };
        worker w[SPLIT_WORKERS];
        pthread_t th[SPLIT_WORKERS];
        bool started[SPLIT_WORKERS] = { false };
        for (uint32_t i = 0; i < s.step; i++) {
            w[i] = (worker){ .s = &s };
            if (i > 0 && !(started[i] = pthread_create(&th[i], NULL, work, &w[i]) == 0))
                w[i].ok = false;
        }
        work(&w[0]);
        for (uint32_t i = 1; i < s.step; i++) {
            if (started[i])
                pthread_join(th[i], NULL);
            else
                work(&w[i]);    /* no thread: its blocks here */
            *ok = *ok && w[i].ok;
        }
        *ok = *ok && w[0].ok;
        double e = 0;
        for (uint32_t b = 0; *ok && b < nblocks; b++) {
            memcpy(out + total, made[b], sizeof *out * nmade[b]);
            total += nmade[b];
            e = fmax(e, errs[b]);
        }
        if (err)
            *err = scale > 0 ? (float)(e / scale) : 0;
    }
    for (uint32_t b = 0; made && b < nblocks; b++)
        free(made[b]);
    free(tris);
    free(first);
    free(want_of);
    free(nmade);
    free(made);
    free(errs);
    return *ok ? total : 0;
}
