/* bvh.h - a bounding volume hierarchy of axis-aligned boxes in double precision: the
 * scene's spatial index (planner, straddlers) and the ray tracer's acceleration structure.
 * Items are small integers chosen by the caller (node slots, prim indices). Built in one go,
 * then kept: items move (refit), come (insert) and go (remove) in O(depth) each. */
#ifndef LIMEN_BVH_H
#define LIMEN_BVH_H

#include <stdbool.h>

typedef struct limen__box {
    double lo[3], hi[3];
} limen__box;

typedef struct limen__bvh_node {
    limen__box box;
    int parent;             /* node index, -1 for the root */
    int first;              /* leaf: first position in `order`; inner: left child */
    int count;              /* leaf: items (> 0); inner: 0, right child = first + 1 */
    int height;             /* leaf: 0; inner: 1 + the taller child's */
} limen__bvh_node;

typedef struct limen__bvh {
    limen__bvh_node *nodes;
    int nnodes, nodes_cap;
    int *order;             /* items in leaf order; -1 where a removed item was */
    int norder, order_cap;  /* positions used in order (items and holes) */
    int nitems;             /* items in the tree */
    int free_pair;          /* 1 + the first of a pair of unused nodes, chained; 0: none */
    limen__box *boxes;      /* per item id */
    int *leaf;              /* per item id: its leaf, or -1 when not in the tree */
    int id_cap;             /* entries in boxes and leaf */
} limen__bvh;

/* Builds over items ids[0..n) with boxes[ids[i]] (boxes indexed by id, ids < id_count);
 * median splits on the longest axis of the centres. False when out of memory. */
bool limen__bvh_build(limen__bvh *b, const int *ids, int n, const limen__box *boxes,
                      int id_count);
void limen__bvh_free(limen__bvh *b);
/* Replaces item id's box and widens (or narrows) its ancestors: a refit, O(depth). */
void limen__bvh_update(limen__bvh *b, int id, const limen__box *box);
/* Adds item id (any id >= 0; one already held is updated) as a leaf beside the node whose
 * box it enlarges least, by the surface area heuristic, walking down from the root: O(depth).
 * False when out of memory or when the tree grew too deep for the traversals' stacks: the
 * caller must then rebuild it before using it. */
bool limen__bvh_insert(limen__bvh *b, int id, const limen__box *box);
/* Takes item id out (a leaf emptied gives its place to its sibling); nothing when not held. */
void limen__bvh_remove(limen__bvh *b, int id);

static inline bool limen__bvh_holds(const limen__bvh *b, int id)
{
    return id >= 0 && id < b->id_cap && b->leaf[id] >= 0;
}

/* Box tests a query made (for the tests' cost counters). */
typedef struct limen__bvh_stats {
    long boxes;             /* tree nodes tested */
    long items;             /* items returned */
} limen__bvh_stats;

/* The items whose boxes are not wholly on the negative side of any of the planes
 * (a . p + d >= -slack for some corner). Appends to *out (grown as needed); returns the
 * new count, or -1 when out of memory. */
int limen__bvh_query_planes(const limen__bvh *b, const double (*planes)[4], int nplanes,
                            double slack, int **out, int *count, int *cap,
                            limen__bvh_stats *stats);
/* The items whose boxes overlap box q. Same conventions. */
int limen__bvh_query_box(const limen__bvh *b, const limen__box *q, int **out, int *count,
                         int *cap, limen__bvh_stats *stats);

/* Calls hit(ctx, item, &tmax) for every item whose box the segment o + t d, t in
 * [tmin, tmax], meets, nearest boxes first; hit may lower tmax. */
typedef void (*limen__bvh_hit_fn)(void *ctx, int item, double *tmax);
void limen__bvh_ray(const limen__bvh *b, const double o[3], const double d[3], double tmin,
                    double tmax, limen__bvh_hit_fn hit, void *ctx);

static inline void limen__box_empty(limen__box *b)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = 1e300;
        b->hi[k] = -1e300;
    }
}

static inline void limen__box_add(limen__box *b, const limen__box *a)
{
    for (int k = 0; k < 3; k++) {
        if (a->lo[k] < b->lo[k])
            b->lo[k] = a->lo[k];
        if (a->hi[k] > b->hi[k])
            b->hi[k] = a->hi[k];
    }
}

static inline void limen__box_sphere(limen__box *b, const double c[3], double r)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = c[k] - r;
        b->hi[k] = c[k] + r;
    }
}

/* Whether box bx lies wholly on the negative side of one of the planes (its corner furthest
 * along the normal at a . p + d < -slack): what the plane query leaves out. */
static inline bool limen__box_outside(const limen__box *bx, const double (*planes)[4],
                                      int nplanes, double slack)
{
    for (int i = 0; i < nplanes; i++) {
        const double *p = planes[i];
        double d = p[3];
        for (int k = 0; k < 3; k++)
            d += p[k] * (p[k] >= 0 ? bx->hi[k] : bx->lo[k]);
        if (d < -slack)
            return true;
    }
    return false;
}

/* Whether two boxes overlap (touching counts): what the box query keeps. */
static inline bool limen__box_meets(const limen__box *a, const limen__box *q)
{
    for (int k = 0; k < 3; k++)
        if (a->hi[k] < q->lo[k] || a->lo[k] > q->hi[k])
            return false;
    return true;
}

#endif
