/* lod_target.c - a mesh that levels of detail are measured against (lod_target.h): the
 * distance from a point to a triangle, the nearest triangle through the mesh's hierarchy,
 * walks across edges, and the edges' pairing. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "core/lod_target.h"
#include "core/pages.h"

#define STACK_MAX 64
#define WALK_MAX 64             /* steps of a walk over the surface */

/* Squared distance from p to the segment ab; *t (where not NULL) the nearest point's place
 * along it, from a (0) to b (1). */
static inline double seg_nearest(const double p[3], const double a[3], const double b[3],
                                 double *at)
{
    double ab[3], ap[3];
    limen__sub3(b, a, ab);
    limen__sub3(p, a, ap);
    double len2 = limen__dot3(ab, ab), t = len2 > 0 ? limen__dot3(ap, ab) / len2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = ap[k] - t * ab[k];
        d2 += e * e;
    }
    if (at)
        *at = t;
    return d2;
}

double limen__seg_d2(const double p[3], const double a[3], const double b[3])
{
    return seg_nearest(p, a, b, NULL);
}

/* Sets the weights of b and c (*u, *v) where they are asked for (u not NULL). */
static inline void weights(double *u, double *v, double wb, double wc)
{
    if (u) {
        *u = wb;
        *v = wc;
    }
}

/* Squared distance from p to the triangle abc, and (u not NULL) the nearest point's weights
 * of b and c: the nearest point found by the region of the triangle's plane that p projects
 * into (corner, edge or face; Ericson, Real-Time Collision Detection 5.1.5), with the edges
 * as a fallback for a triangle of no area. */
static inline double tri_nearest(const double p[3], const double a[3], const double b[3],
                                 const double c[3], double *u, double *v)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3], t = 0;
    limen__sub3(b, a, ab);
    limen__sub3(c, a, ac);
    limen__sub3(p, a, ap);
    limen__sub3(ap, ab, bp);
    limen__sub3(ap, ac, cp);
    double d1 = limen__dot3(ab, ap), d2 = limen__dot3(ac, ap), d3 = limen__dot3(ab, bp),
           d4 = limen__dot3(ac, bp), d5 = limen__dot3(ab, cp), d6 = limen__dot3(ac, cp);
    /* the regions are disjoint but for their borders, so the order of the tests is free */
    if (d1 <= 0 && d2 <= 0) {
        weights(u, v, 0, 0);
        return limen__dot3(ap, ap);
    }
    if (d3 >= 0 && d4 <= d3) {
        weights(u, v, 1, 0);
        return limen__dot3(bp, bp);
    }
    if (d6 >= 0 && d5 <= d6) {
        weights(u, v, 0, 1);
        return limen__dot3(cp, cp);
    }
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double e = seg_nearest(p, a, b, u ? &t : NULL);
        weights(u, v, t, 0);
        return e;
    }
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double e = seg_nearest(p, a, c, u ? &t : NULL);
        weights(u, v, 0, t);
        return e;
    }
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double e = seg_nearest(p, b, c, u ? &t : NULL);
        weights(u, v, 1 - t, t);
        return e;
    }
    double sum = va + vb + vc;
    if (!(sum > 0)) {
        double tab = 0, tbc = 0, tca = 0;
        double ab2 = seg_nearest(p, a, b, u ? &tab : NULL),
               bc2 = seg_nearest(p, b, c, u ? &tbc : NULL),
               ca2 = seg_nearest(p, c, a, u ? &tca : NULL);
        double m = ab2 < bc2 ? ab2 : bc2;
        if (m < ca2) {
            if (ab2 < bc2)
                weights(u, v, tab, 0);
            else
                weights(u, v, 1 - tbc, tbc);
            return m;
        }
        weights(u, v, 0, 1 - tca);
        return ca2;
    }
    double w1 = vb / sum, w2 = vc / sum, d2q = 0;
    for (int k = 0; k < 3; k++) {
        q[k] = ap[k] - ab[k] * w1 - ac[k] * w2;
        d2q += q[k] * q[k];
    }
    weights(u, v, w1, w2);
    return d2q;
}

double limen__tri_d2(const double p[3], const double a[3], const double b[3], const double c[3])
{
    return tri_nearest(p, a, b, c, NULL, NULL);
}

double limen__tri_nearest(const double p[3], const double a[3], const double b[3],
                          const double c[3], double *u, double *v)
{
    return tri_nearest(p, a, b, c, u, v);
}

void limen__lod_target_free(limen__lod_target *t)
{
    free(t->ball);
    free(t->at_vertex);
    free(t->across);
    free(t->reach);
    free(t->vweld);
    free(t->used);
    /* freed twice is harmless: a failed making frees, and its caller may free again */
    t->ball = NULL;
    t->at_vertex = NULL;
    t->across = NULL;
    t->reach = NULL;
    t->vweld = NULL;
    t->used = NULL;
}

/* The vertex at corner i of t's mesh, welded where weld is given. */
static uint32_t corner_vertex(const limen__lod_target *t, const uint32_t *weld, size_t i)
{
    return weld ? weld[i] : t->m->idx[i];
}

/* The directed edge half-edge h runs (its corner and the next, welded), as a key. */
static uint64_t edge_key(const limen__lod_target *t, const uint32_t *weld, size_t h)
{
    size_t base = h - h % 3;
    return (uint64_t)corner_vertex(t, weld, h) << 32 | corner_vertex(t, weld, base + (h + 1) % 3);
}

#define SLOT_FREE UINT32_MAX    /* a slot of pair_edges' table no key has taken */
#define SLOT_EMPTY 0x80000000u  /* with a half-edge: its key's slot, none of it waiting */

/* The slot of pair_edges' table (mask + 1 slots) that holds key, or the free one where it
 * would go; each slot looked at counted in *probes. */
static size_t key_slot(const limen__lod_target *t, const uint32_t *weld, const uint32_t *head,
                       size_t mask, uint64_t key, uint64_t *probes)
{
    size_t at = (size_t)((key * 0x9e3779b97f4a7c15ull) >> 20) & mask;
    for (;; at = (at + 1) & mask) {
        (*probes)++;
        if (head[at] == SLOT_FREE || edge_key(t, weld, head[at] & ~SLOT_EMPTY) == key)
            return at;
    }
}

#define PAIR_THREAD_EDGES 196608 /* pair_edges pairs this many half-edges on two threads */
#define PART_EDGES 16384        /* half-edges a part of pair_edges' work holds, about: its
                                 * table (1.5 to 3 slots each) stays in the core's cache */

/* edge_parts' work over the half-edges [h0, h1). */
typedef struct part_run {
    const limen__lod_target *t;
    const uint32_t *weld;
    size_t h0, h1;              /* the half-edges [h0, h1) */
    uint32_t parts;
    size_t *at;                 /* parts + 1: counted, then where each part's next one goes */
    uint32_t *order;
    bool ok;
} part_run;

/* Counts r's half-edges by part (into r->at), or where scatter lays them out in order (at
 * r->at's places, moved on); one from a vertex to itself is in none. r->ok false where one
 * names no vertex of the mesh. */
static void part_count(part_run *r, bool scatter)
{
    const limen__lod_target *t = r->t;
    uint32_t nv = t->m->nverts;
    for (size_t h = r->h0; h < r->h1; h++) {
        size_t base = h - h % 3;
        uint32_t a = corner_vertex(t, r->weld, h), b = corner_vertex(t, r->weld, base + (h + 1) % 3);
        if (a == b)
            continue;
        if (a >= nv || b >= nv) {
            r->ok = false;      /* not a vertex of the mesh */
            return;
        }
        uint32_t p = (uint32_t)((uint64_t)(a < b ? a : b) * r->parts / nv);
        if (scatter)
            r->order[r->at[p]++] = (uint32_t)h;
        else
            r->at[p]++;
    }
}

static void *part_count_run(void *arg)
{
    part_count(arg, false);
    return NULL;
}

static void *part_scatter_run(void *arg)
{
    part_count(arg, true);
    return NULL;
}

void limen__lod_both(void *(*f)(void *), void *first, void *second, bool beside)
{
    pthread_t th;
    beside = beside && pthread_create(&th, NULL, f, second) == 0;
    f(first);
    if (beside)
        pthread_join(th, NULL);
    else
        f(second);
}

/* The half-edges of t's mesh [0, n) that pair_edges pairs in one part, of `parts`, each a
 * range of vertices: those whose lesser vertex lies in part p are order[first[p],
 * first[p + 1]), in their own order. false when out of memory. */
static bool edge_parts(const limen__lod_target *t, const uint32_t *weld, size_t n,
                       uint32_t parts, size_t *first, uint32_t *order)
{
    /* counted and laid out in two halves of the half-edges (the first half's of a part
     * before the second's, so each part's are in their own order, whichever way it ran) */
    size_t *at = calloc(2 * ((size_t)parts + 1), sizeof *at);
    if (!at)
        return false;
    part_run r[2] = { { .t = t, .weld = weld, .h0 = 0, .h1 = n / 2, .parts = parts, .at = at,
                        .order = order, .ok = true },
                      { .t = t, .weld = weld, .h0 = n / 2, .h1 = n, .parts = parts,
                        .at = at + parts + 1, .order = order, .ok = true } };
    bool beside = n >= PAIR_THREAD_EDGES;
    limen__lod_both(part_count_run, &r[0], &r[1], beside);
    bool ok = r[0].ok && r[1].ok;
    size_t sum = 0;
    for (uint32_t p = 0; ok && p < parts; p++) {
        size_t c0 = r[0].at[p], c1 = r[1].at[p];
        first[p] = sum;
        r[0].at[p] = sum;
        r[1].at[p] = sum + c0;
        sum += c0 + c1;
    }
    first[parts] = sum;
    if (ok)
        limen__lod_both(part_scatter_run, &r[0], &r[1], beside);
    free(at);
    return ok;
}

/* pair_edges' work over the parts [p0, p1): each part's half-edges paired through its own
 * table (at most `size` slots). */
typedef struct pair_run {
    limen__lod_target *t;
    const uint32_t *weld, *order;
    const size_t *first;
    uint32_t *next;
    uint32_t p0, p1;
    size_t size;
    uint64_t probes;
    bool ok;
} pair_run;

static void *pair_parts(void *arg)
{
    pair_run *r = arg;
    limen__lod_target *t = r->t;
    const uint32_t *weld = r->weld, *order = r->order;
    const size_t *first = r->first;
    uint32_t *next = r->next;
    uint32_t *head = limen__malloc_populated(sizeof *head * r->size);
    r->ok = head != NULL;
    for (uint32_t p = r->p0; head && p < r->p1; p++) {
        size_t count = first[p + 1] - first[p], mask = 16;
        while (mask < count + count / 2)
            mask *= 2;
        mask--;
        memset(head, 0xff, sizeof *head * (mask + 1));
        for (size_t i = first[p]; i < first[p + 1]; i++) {
            size_t h = order[i], base = h - h % 3;
            uint32_t a = corner_vertex(t, weld, h), b = corner_vertex(t, weld, base + (h + 1) % 3);
            /* the opposite direction first: a half-edge waiting there pairs with this one */
            size_t at = key_slot(t, weld, head, mask, (uint64_t)b << 32 | a, &r->probes);
            if (head[at] != SLOT_FREE && !(head[at] & SLOT_EMPTY)) {
                uint32_t o = head[at];
                head[at] = next[o] == UINT32_MAX ? o | SLOT_EMPTY : next[o];
                t->across[o / 3][o % 3] = (uint32_t)(h / 3);
                t->across[h / 3][h % 3] = o / 3;
                continue;
            }
            /* else it waits under its own direction (a slot emptied by pairing keeps a
             * half-edge of its key, flagged, so the probes past it still find theirs) */
            at = key_slot(t, weld, head, mask, (uint64_t)a << 32 | b, &r->probes);
            next[h] = head[at] == SLOT_FREE || (head[at] & SLOT_EMPTY) ? UINT32_MAX : head[at];
            head[at] = (uint32_t)h;
        }
    }
    free(head);
    return NULL;
}

/* t->across: edges paired through a table keyed on directed edges (two welded vertices, in
 * the order a triangle runs them), each holding the half-edges of its key not yet paired.
 * A half-edge a->b pairs with the last one waiting under b->a (where the two run the edge
 * opposite ways, their windings agree), else waits under a->b. The table holds each
 * directed edge once, however many triangles repeat it, so its probes stay near one a
 * half-edge (t->probes counts them): repeated and zero-area triangles cost what others do. A
 * slot holds a half-edge, not its key (read from the mesh where a probe asks). The edges are
 * paired part by part, each part the edges of a range of vertices (by the lesser), with a
 * table of its own: an edge's two ways meet in one part, so the pairs are those of one
 * table over all of them, while a part's table, and the vertices it reads, stay near
 * (a mesh whose neighbours are numbered near each other) instead of a table of 32 MB at
 * 1.6M triangles read at random. An edge of more than two triangles pairs some of them;
 * what a pairing misses, the walks over the surface below do without (they only ever find
 * less). order: room for the half-edges' numbers (3 a triangle), the caller's. False when out
 * of memory. */
static bool pair_edges(limen__lod_target *t, const uint32_t *weld, uint32_t *order)
{
    size_t n = (size_t)t->m->ntris * 3;
    if (n >= SLOT_EMPTY)
        return false;   /* a half-edge's number must leave the slot's flag free */
    uint32_t parts = (uint32_t)(n / PART_EDGES + 1);
    if (parts > t->m->nverts)
        parts = t->m->nverts ? t->m->nverts : 1;
    size_t *first = malloc(sizeof *first * ((size_t)parts + 1));
    uint32_t *next = limen__malloc_populated(sizeof *next * (n ? n : 1));
    t->across = limen__malloc_populated(sizeof *t->across * (t->m->ntris ? t->m->ntris : 1));
    bool ok = first && order && next && t->across && edge_parts(t, weld, n, parts, first, order);
    /* each part's table: at most two thirds full (half, where the edges pair) */
    size_t most = 0, size = 16;
    for (uint32_t p = 0; ok && p < parts; p++)
        most = first[p + 1] - first[p] > most ? first[p + 1] - first[p] : most;
    while (size < most + most / 2)
        size *= 2;
    if (!ok) {
        free(first);
        free(next);
        return false;
    }
    memset(t->across, 0xff, sizeof *t->across * t->m->ntris);
    /* the parts in two runs of about half the half-edges each, the second on a thread of its
     * own where there are many (a part's pairs are its own: the same either way) */
    uint32_t half = 0;
    while (half < parts && first[half] < n / 2)
        half++;
    pair_run run[2] = { { .t = t, .weld = weld, .order = order, .first = first, .next = next,
                          .p0 = 0, .p1 = half, .size = size },
                        { .t = t, .weld = weld, .order = order, .first = first, .next = next,
                          .p0 = half, .p1 = parts, .size = size } };
    limen__lod_both(pair_parts, &run[0], &run[1], n >= PAIR_THREAD_EDGES);
    t->probes = run[0].probes + run[1].probes;
    free(first);
    free(next);
    return run[0].ok && run[1].ok;
}

bool limen__lod_target_make(limen__lod_target *t, const limen__mesh *m, const uint32_t *weld)
{
    t->m = m;
    t->reach = NULL;
    t->vweld = NULL;
    t->used = NULL;
    /* the balls' room (16 bytes a triangle) holds the pairing's order of half-edges (12)
     * until they are made: at 1.6M triangles, 19 MB less for a moment */
    t->ball = limen__malloc_populated(sizeof *t->ball * (m->ntris ? m->ntris : 1));
    t->at_vertex = limen__malloc_populated(sizeof *t->at_vertex * m->nverts);
    if (!t->ball || !t->at_vertex || !pair_edges(t, weld, (uint32_t *)(void *)t->ball)) {
        limen__lod_target_free(t);
        return false;
    }
    for (uint32_t v = 0; v < m->nverts; v++)
        t->at_vertex[v] = UINT32_MAX;
    for (size_t i = 0; i < (size_t)m->ntris * 3; i++) {
        t->at_vertex[m->idx[i]] = (uint32_t)(i / 3);
        if (weld)
            t->at_vertex[weld[i]] = (uint32_t)(i / 3);
    }
    for (uint32_t i = 0; i < m->ntris; i++) {
        double c[3], r2 = 0, tri[9];
        limen__lod_corners(t, i, tri);
        /* the centre rounded to float, the radius measured from it and rounded up: the
         * sphere still holds the triangle */
        for (int a = 0; a < 3; a++) {
            t->ball[i][a] = (float)((tri[a] + tri[3 + a] + tri[6 + a]) / 3);
            c[a] = t->ball[i][a];
        }
        for (int k = 0; k < 3; k++) {
            double e[3];
            limen__sub3(tri + 3 * k, c, e);
            r2 = limen__greater(r2, limen__dot3(e, e));
        }
        double r = sqrt(r2) * (1 + 1e-12);
        t->ball[i][3] = (float)r;
        if ((double)t->ball[i][3] < r)
            t->ball[i][3] = nextafterf(t->ball[i][3], INFINITY);
        double e1[3], e2[3], n[3];
        limen__sub3(tri + 3, tri, e1);
        limen__sub3(tri + 6, tri, e2);
        limen__cross3(e1, e2, n);
        t->mean_area += sqrt(limen__dot3(n, n)) / 2;
    }
    t->mean_area /= m->ntris > 0 ? m->ntris : 1;
    return true;
}

/* ------------------------------------------------------------------ a level's hierarchy */

#define TREE_LEAF 8             /* triangles a leaf of limen__lod_tree holds, at most */

/* The nodes tree_node makes over n and over n + 1 triangles (out[0], out[1]): the halves of
 * both are of n / 2 and n / 2 + 1 triangles, so one step a depth. */
static void tree_nodes(uint32_t n, uint64_t out[2])
{
    if (n + 1 <= TREE_LEAF) {
        out[0] = out[1] = 1;
        return;
    }
    uint64_t half[2];
    tree_nodes(n / 2, half);
    bool odd = n % 2;
    out[0] = n <= TREE_LEAF ? 1 : odd ? 1 + half[0] + half[1] : 1 + 2 * half[0];
    out[1] = odd ? 1 + 2 * half[1] : 1 + half[0] + half[1];
}

/* The node at m->bvh[at] over tri_order[first, first + count): halved in order, a left
 * child in the slot after its parent; its box its triangles' (a leaf) or its children's. */
static void tree_node(limen__mesh *m, uint32_t at, uint32_t first, uint32_t count)
{
    limen__tri_node *n = &m->bvh[at];
    if (count <= TREE_LEAF) {
        for (int a = 0; a < 3; a++) {
            n->lo[a] = INFINITY;
            n->hi[a] = -INFINITY;
        }
        for (uint32_t i = first; i < first + count; i++)
            for (int k = 0; k < 3; k++) {
                const float *p = &m->pos[m->idx[m->tri_order[i] * 3 + k] * 3];
                for (int a = 0; a < 3; a++) {
                    n->lo[a] = limen__lesserf(n->lo[a], p[a]);
                    n->hi[a] = limen__greaterf(n->hi[a], p[a]);
                }
            }
        n->index = first;
        n->count = count;
        return;
    }
    uint32_t half = count / 2, left = m->nbvh++;
    tree_node(m, left, first, half);
    uint32_t right = m->nbvh++;
    tree_node(m, right, first + half, count - half);
    n = &m->bvh[at];
    n->index = right;
    n->count = 0;
    for (int a = 0; a < 3; a++) {
        n->lo[a] = limen__lesserf(m->bvh[left].lo[a], m->bvh[right].lo[a]);
        n->hi[a] = limen__greaterf(m->bvh[left].hi[a], m->bvh[right].hi[a]);
    }
}

uint32_t *limen__lod_tree_alloc(limen__mesh *m)
{
    uint64_t nodes[2];
    tree_nodes(m->ntris, nodes);
    size_t n = m->ntris ? m->ntris : 1;
    m->bvh = limen__malloc_populated(sizeof *m->bvh * (size_t)nodes[0]);
    m->tri_order = limen__malloc_populated(sizeof *m->tri_order * n);
    uint32_t *scratch = limen__malloc_populated(sizeof *scratch * 2 * n);
    if (!m->bvh || !m->tri_order || !scratch) {
        free(m->bvh);
        free(m->tri_order);
        m->bvh = NULL;
        m->tri_order = NULL;
        free(scratch);
        return NULL;
    }
    return scratch;
}

bool limen__lod_tree(limen__mesh *m)
{
    uint32_t *scratch = limen__lod_tree_alloc(m);
    if (!scratch)
        return false;
    limen__lod_tree_fill(m, scratch);
    free(scratch);
    return true;
}

void limen__lod_tree_fill(limen__mesh *m, uint32_t *scratch)
{
    size_t n = m->ntris;
    uint32_t *key = scratch, *other = scratch + (n ? n : 1);
    /* each triangle's centre on a 1024^3 grid over the centres' box, as a Morton code */
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (size_t t = 0; t < n; t++)
        for (int a = 0; a < 3; a++) {
            double c = ((double)m->pos[m->idx[t * 3] * 3 + a] + m->pos[m->idx[t * 3 + 1] * 3 + a] +
                        m->pos[m->idx[t * 3 + 2] * 3 + a]) / 3;
            lo[a] = limen__lesser(lo[a], c);
            hi[a] = limen__greater(hi[a], c);
        }
    for (size_t t = 0; t < n; t++) {
        uint32_t q[3];
        for (int a = 0; a < 3; a++) {
            double c = ((double)m->pos[m->idx[t * 3] * 3 + a] + m->pos[m->idx[t * 3 + 1] * 3 + a] +
                        m->pos[m->idx[t * 3 + 2] * 3 + a]) / 3;
            double f = hi[a] > lo[a] ? (c - lo[a]) / (hi[a] - lo[a]) * 1023 : 0;
            q[a] = f > 0 ? (uint32_t)f : 0;
        }
        key[t] = limen__morton3(q[0], q[1], q[2]);
        m->tri_order[t] = (uint32_t)t;
    }
    /* sorted by code, 8 bits a pass, the least first (stable); four passes, so tri_order
     * ends in its own array and other in the scratch */
    for (int shift = 0; shift < 32; shift += 8) {
        size_t count[257] = { 0 };
        for (size_t i = 0; i < n; i++)
            count[(key[m->tri_order[i]] >> shift & 0xff) + 1]++;
        for (int b = 0; b < 256; b++)
            count[b + 1] += count[b];
        for (size_t i = 0; i < n; i++)
            other[count[key[m->tri_order[i]] >> shift & 0xff]++] = m->tri_order[i];
        uint32_t *swap = m->tri_order;
        m->tri_order = other;
        other = swap;
    }
    m->nbvh = 1;
    tree_node(m, 0, 0, m->ntris);
}

static double box_d2(const limen__tri_node *n, const double p[3])
{
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double e = n->lo[a] - p[a] > 0 ? n->lo[a] - p[a] : p[a] - n->hi[a] > 0 ? p[a] - n->hi[a] : 0;
        d2 += e * e;
    }
    return d2;
}

double limen__lod_target_nearest(const limen__lod_target *to, const double p[3], uint32_t hint,
                                 uint32_t *tri)
{
    const limen__mesh *m = to->m;
    double best = limen__lod_d2(to, hint, p);
    *tri = hint;
    if (best == 0)
        return 0;               /* on it: nothing is nearer */
    struct { uint32_t node; double d2; } stack[STACK_MAX];
    int top = 0;
    stack[top].node = 0;
    stack[top++].d2 = box_d2(&m->bvh[0], p);
    while (top > 0) {
        top--;
        if (stack[top].d2 >= best)
            continue;
        const limen__tri_node *n = &m->bvh[stack[top].node];
        if (n->count == 0) {
            uint32_t l = (uint32_t)(n - m->bvh) + 1u, r = n->index;
            double dl = box_d2(&m->bvh[l], p), dr = box_d2(&m->bvh[r], p);
            if (top + 2 > STACK_MAX)
                continue;   /* depth is log2(triangles) <= 32: never */
            /* the nearer child on top */
            bool l_near = dl <= dr;
            stack[top].node = l_near ? r : l;
            stack[top++].d2 = l_near ? dr : dl;
            stack[top].node = l_near ? l : r;
            stack[top++].d2 = l_near ? dl : dr;
            continue;
        }
        double reach = sqrt(best);
        for (uint32_t i = n->index; i < n->index + n->count; i++) {
            uint32_t t = m->tri_order[i];
            /* a triangle whose sphere lies beyond the best so far cannot be nearer */
            const float *c = to->ball[t];
            double e[3] = { p[0] - c[0], p[1] - c[1], p[2] - c[2] };
            if (limen__dot3(e, e) > (reach + c[3]) * (reach + c[3]))
                continue;
            double d2 = limen__lod_d2(to, t, p);
            if (d2 < best) {
                best = d2;
                reach = sqrt(best);
                *tri = t;
            }
        }
    }
    return best;
}


double limen__lod_target_walk(const limen__lod_target *to, const double p[3], uint32_t *t,
                              double best)
{
    uint32_t from = UINT32_MAX;     /* the triangle stepped from: farther, not looked at again */
    for (int step = 0; step < WALK_MAX && best > 0; step++) {
        uint32_t next = UINT32_MAX;
        for (int e = 0; e < 3; e++) {
            uint32_t o = to->across[*t][e];
            if (o == UINT32_MAX || o == from)
                continue;
            /* one whose sphere lies beyond the best so far (by far more than rounding) is
             * no nearer: not measured */
            const float *c = to->ball[o];
            double g[3] = { p[0] - c[0], p[1] - c[1], p[2] - c[2] };
            double gap = sqrt(limen__dot3(g, g)) - c[3];
            if (gap > 0 && gap * gap > best * (1 + 1e-9))
                continue;
            double d2 = limen__lod_d2(to, o, p);
            if (d2 < best) {
                best = d2;
                next = o;
            }
        }
        if (next == UINT32_MAX)
            break;
        from = *t;
        *t = next;
    }
    return best;
}
