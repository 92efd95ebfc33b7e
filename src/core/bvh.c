/* bvh.c - a bounding volume hierarchy over axis-aligned boxes (see bvh.h).
 *
 * Built top down by median splits of the item centres along the longest axis of their
 * spread: O(n log n), balanced (depth log2(n / LEAF_MAX) + 1), which bounds the traversal
 * stacks below. Moving items are refitted in place (limen__bvh_update): the tree keeps its
 * shape and its ancestors' boxes follow, so a scene whose objects move stays indexed at
 * O(depth) per moved object; the caller rebuilds when items come or go. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/bvh.h"

#define LEAF_MAX 4
#define STACK_MAX 128       /* > 2 x depth of a median-split tree of 2^31 items */

static bool grow(void **p, int *cap, int need, size_t size)
{
    if (need <= *cap)
        return true;
    int n = *cap ? *cap : 16;
    while (n < need)
        n *= 2;
    void *q = realloc(*p, size * (size_t)n);
    if (!q)
        return false;
    *p = q;
    *cap = n;
    return true;
}

void limen__bvh_free(limen__bvh *b)
{
    free(b->nodes);
    free(b->order);
    free(b->boxes);
    free(b->leaf);
    memset(b, 0, sizeof *b);
}

/* ------------------------------------------------------------------ build */

static double centre(const limen__bvh *b, int id, int axis)
{
    return b->boxes[id].lo[axis] + b->boxes[id].hi[axis];
}

/* Reorders order[lo..hi) so that position k holds the item of rank k along the axis, the
 * ones before it no greater and the ones after no smaller (Hoare's selection). */
static void select_rank(limen__bvh *b, int lo, int hi, int k, int axis)
{
    int *o = b->order;
    while (hi - lo > 1) {
        double pivot = centre(b, o[lo + (hi - lo) / 2], axis);
        int i = lo, j = hi - 1;
        while (i <= j) {
            while (centre(b, o[i], axis) < pivot)
                i++;
            while (centre(b, o[j], axis) > pivot)
                j--;
            if (i <= j) {
                int t = o[i];
                o[i++] = o[j];
                o[j--] = t;
            }
        }
        if (k <= j)
            hi = j + 1;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

static void build_node(limen__bvh *b, int at, int lo, int hi, int parent)
{
    limen__bvh_node *nd = &b->nodes[at];
    nd->parent = parent;
    limen__box_empty(&nd->box);
    limen__box spread;
    limen__box_empty(&spread);
    for (int i = lo; i < hi; i++) {
        const limen__box *ib = &b->boxes[b->order[i]];
        limen__box_add(&nd->box, ib);
        limen__box c;
        for (int k = 0; k < 3; k++)
            c.lo[k] = c.hi[k] = 0.5 * (ib->lo[k] + ib->hi[k]);
        limen__box_add(&spread, &c);
    }
    if (hi - lo <= LEAF_MAX) {
        nd->first = lo;
        nd->count = hi - lo;
        for (int i = lo; i < hi; i++)
            b->leaf[b->order[i]] = at;
        return;
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (spread.hi[k] - spread.lo[k] > spread.hi[axis] - spread.lo[axis])
            axis = k;
    int mid = lo + (hi - lo) / 2;
    select_rank(b, lo, hi, mid, axis);
    int left = b->nnodes;
    b->nnodes += 2;
    nd->first = left;
    nd->count = 0;
    build_node(b, left, lo, mid, at);
    build_node(b, left + 1, mid, hi, at);
}

bool limen__bvh_build(limen__bvh *b, const int *ids, int n, const limen__box *boxes,
                      int id_count)
{
    if (!grow((void **)&b->order, &b->order_cap, n > 0 ? n : 1, sizeof *b->order) ||
        !grow((void **)&b->nodes, &b->nodes_cap, n > 0 ? 2 * n : 1, sizeof *b->nodes))
        return false;
    if (id_count > b->id_cap) {
        limen__box *bx = realloc(b->boxes, sizeof *bx * (size_t)id_count);
        if (bx)
            b->boxes = bx;
        int *lf = realloc(b->leaf, sizeof *lf * (size_t)id_count);
        if (lf)
            b->leaf = lf;
        if (!bx || !lf)
            return false;
        b->id_cap = id_count;
    }
    memcpy(b->boxes, boxes, sizeof *boxes * (size_t)id_count);
    for (int i = 0; i < id_count; i++)
        b->leaf[i] = -1;
    memcpy(b->order, ids, sizeof *ids * (size_t)n);
    b->nitems = n;
    b->nnodes = 0;
    if (n == 0)
        return true;
    b->nnodes = 1;
    build_node(b, 0, 0, n, -1);
    return true;
}

void limen__bvh_update(limen__bvh *b, int id, const limen__box *box)
{
    if (id < 0 || id >= b->id_cap || b->leaf[id] < 0)
        return;
    b->boxes[id] = *box;
    for (int at = b->leaf[id]; at >= 0; at = b->nodes[at].parent) {
        limen__bvh_node *nd = &b->nodes[at];
        limen__box_empty(&nd->box);
        if (nd->count) {
            for (int i = 0; i < nd->count; i++)
                limen__box_add(&nd->box, &b->boxes[b->order[nd->first + i]]);
        } else {
            limen__box_add(&nd->box, &b->nodes[nd->first].box);
            limen__box_add(&nd->box, &b->nodes[nd->first + 1].box);
        }
    }
}

/* ------------------------------------------------------------------ queries */

static bool push_item(int id, int **out, int *count, int *cap)
{
    if (!grow((void **)out, cap, *count + 1, sizeof **out))
        return false;
    (*out)[(*count)++] = id;
    return true;
}

static bool outside_planes(const limen__box *bx, const double (*planes)[4], int nplanes,
                           double slack)
{
    for (int i = 0; i < nplanes; i++) {
        const double *p = planes[i];
        /* the corner furthest along the plane's normal */
        double d = p[3];
        for (int k = 0; k < 3; k++)
            d += p[k] * (p[k] >= 0 ? bx->hi[k] : bx->lo[k]);
        if (d < -slack)
            return true;
    }
    return false;
}

static bool boxes_meet(const limen__box *a, const limen__box *q)
{
    for (int k = 0; k < 3; k++)
        if (a->hi[k] < q->lo[k] || a->lo[k] > q->hi[k])
            return false;
    return true;
}

/* One walk for both queries: planes when q is NULL, else the box. */
static int query(const limen__bvh *b, const double (*planes)[4], int nplanes, double slack,
                 const limen__box *q, int **out, int *count, int *cap, limen__bvh_stats *stats)
{
    if (!b->nnodes)
        return *count;
    int stack[STACK_MAX], top = 0;
    stack[top++] = 0;
    long tested = 0;
    int first = *count;
    while (top > 0) {
        const limen__bvh_node *nd = &b->nodes[stack[--top]];
        tested++;
        if (q ? !boxes_meet(&nd->box, q) : outside_planes(&nd->box, planes, nplanes, slack))
            continue;
        if (!nd->count) {
            stack[top++] = nd->first + 1;
            stack[top++] = nd->first;
            continue;
        }
        for (int i = 0; i < nd->count; i++) {
            int id = b->order[nd->first + i];
            const limen__box *ib = &b->boxes[id];
            tested++;
            if (q ? !boxes_meet(ib, q) : outside_planes(ib, planes, nplanes, slack))
                continue;
            if (!push_item(id, out, count, cap))
                return -1;
        }
    }
    if (stats) {
        stats->boxes += tested;
        stats->items += *count - first;
    }
    return *count;
}

int limen__bvh_query_planes(const limen__bvh *b, const double (*planes)[4], int nplanes,
                            double slack, int **out, int *count, int *cap,
                            limen__bvh_stats *stats)
{
    return query(b, planes, nplanes, slack, NULL, out, count, cap, stats);
}

int limen__bvh_query_box(const limen__bvh *b, const limen__box *q, int **out, int *count,
                         int *cap, limen__bvh_stats *stats)
{
    return query(b, NULL, 0, 0, q, out, count, cap, stats);
}

/* Entry distance of the segment into the box, or INFINITY when it misses. A zero direction
 * component makes 0 * inf = NaN where the origin lies on a face: fmin/fmax drop the NaN,
 * leaving that axis unconstrained, which can only keep a box, never lose one. */
static double slab(const limen__box *bx, const double o[3], const double inv[3], double tmin,
                   double tmax)
{
    for (int k = 0; k < 3; k++) {
        double t0 = (bx->lo[k] - o[k]) * inv[k], t1 = (bx->hi[k] - o[k]) * inv[k];
        tmin = fmax(tmin, fmin(t0, t1));
        tmax = fmin(tmax, fmax(t0, t1));
    }
    return tmin <= tmax ? tmin : INFINITY;
}

void limen__bvh_ray(const limen__bvh *b, const double o[3], const double d[3], double tmin,
                    double tmax, limen__bvh_hit_fn hit, void *ctx)
{
    if (!b->nnodes)
        return;
    double inv[3];
    for (int k = 0; k < 3; k++)
        inv[k] = 1.0 / d[k];
    int stack[STACK_MAX], top = 0;
    if (slab(&b->nodes[0].box, o, inv, tmin, tmax) == INFINITY)
        return;
    stack[top++] = 0;
    while (top > 0) {
        const limen__bvh_node *nd = &b->nodes[stack[--top]];
        if (nd->count) {
            for (int i = 0; i < nd->count; i++)
                hit(ctx, b->order[nd->first + i], &tmax);
            continue;
        }
        int l = nd->first, r = nd->first + 1;
        double tl = slab(&b->nodes[l].box, o, inv, tmin, tmax);
        double tr = slab(&b->nodes[r].box, o, inv, tmin, tmax);
        /* nearer child on top; a popped box is tested again only through its items, whose
         * callers bound their own work by tmax */
        if (tl <= tr) {
            if (tr != INFINITY)
                stack[top++] = r;
            if (tl != INFINITY)
                stack[top++] = l;
        } else {
            if (tl != INFINITY)
                stack[top++] = l;
            stack[top++] = r;
        }
    }
}
