/* lod_target.h - a mesh that levels of detail are measured against (core/lod.c): its
 * triangles in double (read from the mesh's own arrays), the distance from a point to them (the nearest through the mesh's
 * hierarchy, or a walk across edges), and each triangle's neighbours. Not part of the
 * public API. */
#ifndef LIMEN_CORE_LOD_TARGET_H
#define LIMEN_CORE_LOD_TARGET_H

#include <stdbool.h>
#include <stdint.h>

#include "core/mesh.h"

typedef struct limen__lod_target {
    const limen__mesh *m;       /* its corners read through m->idx and m->pos (no copy) */
    float (*ball)[4];           /* per triangle: a sphere around it (centre, radius) */
    uint32_t *at_vertex;        /* per vertex: a triangle with a corner there, or UINT32_MAX */
    uint32_t (*across)[3];      /* per triangle and edge (corners k, k + 1): the triangle on
                                 * its other side, or UINT32_MAX */
    float *reach;               /* where not NULL, per vertex: how far a point of a triangle
                                 * with a corner there may lie from its nearest corner, at
                                 * most (made by core/lod.c for the full mesh; freed with t) */
    uint32_t *vweld;            /* where not NULL, per vertex: its welded vertex (the full
                                 * mesh's, made by core/lod.c; freed with t) */
    uint64_t *used;             /* where not NULL, a bit per vertex its triangles name (the
                                 * same) */
    double mean_area;           /* of its triangles */
    uint64_t probes;            /* slots the edges' pairing looked at (a measure of its work) */
} limen__lod_target;

/* the lesser and the greater of two numbers known not to be NaN (b may be: then a), where
 * the library's fmin and fmax are calls */
static inline double limen__lesser(double a, double b)
{
    return b < a ? b : a;
}

static inline double limen__greater(double a, double b)
{
    return b > a ? b : a;
}

static inline float limen__lesserf(float a, float b)
{
    return b < a ? b : a;
}

static inline float limen__greaterf(float a, float b)
{
    return b > a ? b : a;
}

static inline void limen__sub3(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}

static inline double limen__dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* out (not a nor b) = a x b */
static inline void limen__cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* A Morton code: the low 10 bits of x, y and z interleaved, x's the lowest of each three. */
static inline uint32_t limen__morton3(uint32_t x, uint32_t y, uint32_t z)
{
    uint32_t q[3] = { x, y, z }, code = 0;
    for (int a = 0; a < 3; a++) {
        uint32_t v = q[a] & 0x3ff;      /* spread to every third bit */
        v = (v | v << 16) & 0x030000ff;
        v = (v | v << 8) & 0x0300f00f;
        v = (v | v << 4) & 0x030c30c3;
        v = (v | v << 2) & 0x09249249;
        code |= v << a;
    }
    return code;
}

/* Squared distance from p to the segment ab. */
double limen__seg_d2(const double p[3], const double a[3], const double b[3]);
/* Squared distance from p to the triangle abc. */
double limen__tri_d2(const double p[3], const double a[3], const double b[3], const double c[3]);
/* The same, and the nearest point's weights of b and c (*u, *v: it is a + u (b - a) +
 * v (c - a)). */
double limen__tri_nearest(const double p[3], const double a[3], const double b[3],
                          const double c[3], double *u, double *v);
/* f(first), and f(second) on a thread of its own where beside (and a thread starts), else
 * after it: work split in two halves whose results are their own. */
void limen__lod_both(void *(*f)(void *), void *first, void *second, bool beside);
/* t over m's triangles and hierarchy (which it must outlive); weld, where not NULL: per
 * corner of m, another vertex at the corner's position, through which corners meet (at
 * a vertex, across an edge). False when out of memory (t freed). */
bool limen__lod_target_make(limen__lod_target *t, const limen__mesh *m, const uint32_t *weld);
void limen__lod_target_free(limen__lod_target *t);
/* The nearest triangle of t to p: returns the squared distance, *tri the triangle. hint: a
 * triangle likely near (its distance starts the search). */
double limen__lod_target_nearest(const limen__lod_target *t, const double p[3], uint32_t hint,
                                 uint32_t *tri);
/* From triangle *tri (d2: p's squared distance to it), steps across edges while a
 * neighbour is nearer to p; returns the squared distance to the last, *tri (an upper bound
 * on the nearest's, which it is where the surface near p is a single sheet). */
double limen__lod_target_walk(const limen__lod_target *t, const double p[3], uint32_t *tri,
                              double d2);

/* Triangle i of t's corners, in double (the mesh's floats, exactly). */
static inline void limen__lod_corners(const limen__lod_target *t, uint32_t i, double c[9])
{
    const uint32_t *v = t->m->idx + (size_t)i * 3;
    const float *pos = t->m->pos;
    for (int k = 0; k < 3; k++) {
        const float *p = pos + (size_t)v[k] * 3;
        c[3 * k] = p[0];
        c[3 * k + 1] = p[1];
        c[3 * k + 2] = p[2];
    }
}

/* Squared distance from p to triangle i of t. */
static inline double limen__lod_d2(const limen__lod_target *t, uint32_t i, const double p[3])
{
    double c[9];
    limen__lod_corners(t, i, c);
    return limen__tri_d2(p, c, c + 3, c + 6);
}

/* m's triangle hierarchy (bvh, tri_order, nbvh) as limen__mesh_bvh lays it out, for a
 * level's nearest searches: the triangles in the order of their centres' Morton codes,
 * halved in that order (no split is searched for: linear but for the sort, which is by
 * radix). False when out of memory (nothing held). */
bool limen__lod_tree(limen__mesh *m);
/* limen__lod_tree in two steps, so that another thread may fill what this one holds: its
 * arrays (bvh, tri_order) and the scratch returned (freed by the caller after the filling),
 * or NULL when out of memory (nothing held); then the filling, which allocates nothing. */
uint32_t *limen__lod_tree_alloc(limen__mesh *m);
void limen__lod_tree_fill(limen__mesh *m, uint32_t *scratch);
/* core/lod.c's bound on the two-sided distance between the surface idx (ntris triangles over
 * m's vertices) and m's (its hierarchy made, its bounds lo and hi set), as a level's error is
 * measured: for tests. NAN when out of memory. */
double limen__lod_measure(const limen__mesh *m, const uint32_t *idx, uint32_t ntris);
/* limen__lod_measure, each piece of the surface idx laid first over the surface via_idx
 * (via_ntris triangles over m's vertices), which lies within via_e of m's: the bound,
 * *settled the pieces that settled (for tests). */
double limen__lod_measure_via(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                              const uint32_t *via_idx, uint32_t via_ntris, double via_e,
                              uint64_t *settled);
/* How many of the full mesh's triangles core/lod.c's measuring has passed by, bounded
 * through their corners' reach alone (side_near), in all so far (for tests). */
uint64_t limen__lod_near_passed(void);
/* How many of a level's pieces core/lod.c's measuring has bounded over a finer level with
 * that level's triangles' own bounds (via_pick), in all (for tests). */
uint64_t limen__lod_local_settled(void);
/* As limen__lod_measure, and each of the level's triangles' own bound into local (ntris of
 * them); its pieces laid first over the level via_idx (where not NULL) with each of its
 * triangles' own bound via_local (for tests). */
double limen__lod_measure_local(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                                const uint32_t *via_idx, uint32_t via_ntris,
                                const float *via_local, float *local);
/* Whether core/lod.c's measuring keeps what it has found for the pieces after (a vertex as
 * a piece sees it, a vertex's distance to a triangle) or finds it again each time: the same
 * bounds, to the bit, either way (for tests; on by default). */
void limen__lod_set_measure_memo(bool on);

#endif
