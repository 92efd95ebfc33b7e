/* bvh.c - a bounding volume hierarchy over axis-aligned boxes (see bvh.h).
 *
 * Built top down by median splits of the item centres along the longest axis of their
 * spread: O(n log n), balanced (depth log2(n / LEAF_MAX) + 1), which bounds the traversal
 * stacks below. Moving items are refitted in place (limen__bvh_update): the tree keeps its
 * shape and its ancestors' boxes follow, so a scene whose objects move stays indexed at
 * O(depth) per moved object. Items that come are inserted as leaves where the surface area
 * heuristic's cost grows least (found walking down from the root, as dynamic AABB trees do)
 * and items that go leave their leaf's place to its sibling, O(depth) each: the tree stays
 * good while such changes are few against what it holds, and the caller rebuilds when they
 * are many (or when an insertion made it deeper than HEIGHT_MAX). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/bvh.h"
#include "core/reserve.h"

#define LEAF_MIN 2           /* leaves of up to this many items always */
#define LEAF_MAX 8          /* and of up to this many where a split would not pay */
#define COST_NODE 1.0       /* a box test against an item test, in the heuristic */
#define DEPTH_SAH 48        /* deeper than this, median splits: depth <= 48 + 31 */
#define HEIGHT_MAX 100      /* insertions deeper than this ask for a rebuild */
#define STACK_MAX 128       /* > that height + 1, a depth-first walk's most */

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

static double area(const limen__box *x)
{
    double e[3];
    for (int k = 0; k < 3; k++)
        e[k] = x->hi[k] > x->lo[k] ? x->hi[k] - x->lo[k] : 0;
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

/* Where to split order[lo..hi) along `axis` (centres spread over [c0, c1]): the surface area
 * heuristic over BINS bins, which keeps the boxes of a ray's path small where objects
 * cluster; -1 when no split beats the median. Returns the position of the split after
 * partitioning. */
static int split_sah(limen__bvh *b, int lo, int hi, int axis, double c0, double c1,
                     double node_area)
{
    enum { BINS = 16 };
    limen__box bins[BINS];
    int counts[BINS] = { 0 };
    for (int i = 0; i < BINS; i++)
        limen__box_empty(&bins[i]);
    double scale = BINS / (c1 - c0);
    for (int i = lo; i < hi; i++) {
        int id = b->order[i];
        int k = (int)((centre(b, id, axis) - c0) * scale);
        k = k < 0 ? 0 : k >= BINS ? BINS - 1 : k;
        counts[k]++;
        limen__box_add(&bins[k], &b->boxes[id]);
    }
    /* cost of each split: area x count of each side, swept from both ends */
    double right_cost[BINS];
    limen__box acc;
    limen__box_empty(&acc);
    int n = 0;
    for (int k = BINS - 1; k > 0; k--) {
        limen__box_add(&acc, &bins[k]);
        n += counts[k];
        right_cost[k] = n ? area(&acc) * n : 0;
    }
    limen__box_empty(&acc);
    n = 0;
    int best = -1;
    double best_cost = INFINITY;
    for (int k = 0; k < BINS - 1; k++) {
        limen__box_add(&acc, &bins[k]);
        n += counts[k];
        if (!n || n == hi - lo)
            continue;
        double c = area(&acc) * n + right_cost[k + 1];
        if (c < best_cost) {
            best_cost = c;
            best = k;
        }
    }
    if (best < 0)
        return -1;
    if (hi - lo <= LEAF_MAX && node_area > 0 &&
        COST_NODE + best_cost / node_area >= (double)(hi - lo))
        return -2;  /* a leaf costs less */
    /* partition: bins 0..best to the left */
    int i = lo, j = hi - 1;
    while (i <= j) {
        int k = (int)((centre(b, b->order[i], axis) - c0) * scale);
        k = k < 0 ? 0 : k >= BINS ? BINS - 1 : k;
        if (k <= best) {
            i++;
        } else {
            int t = b->order[i];
            b->order[i] = b->order[j];
            b->order[j--] = t;
        }
    }
    return i > lo && i < hi ? i : -1;
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

static void build_node(limen__bvh *b, int at, int lo, int hi, int parent, int depth)
{
    limen__bvh_node *nd = &b->nodes[at];
    nd->parent = parent;
    limen__box_empty(&nd->box);
    double c0[3] = { INFINITY, INFINITY, INFINITY }, c1[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (int i = lo; i < hi; i++) {
        const limen__box *ib = &b->boxes[b->order[i]];
        limen__box_add(&nd->box, ib);
        for (int k = 0; k < 3; k++) {
            double c = ib->lo[k] + ib->hi[k];
            c0[k] = c < c0[k] ? c : c0[k];
            c1[k] = c > c1[k] ? c : c1[k];
        }
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (c1[k] - c0[k] > c1[axis] - c0[axis])
            axis = k;
    /* the heuristic while the tree is shallow enough that any split keeps the stacks
     * bounded, the median below that (and where all centres coincide) */
    int mid = hi - lo <= LEAF_MIN ? -2 : -1;
    if (mid == -1 && depth < DEPTH_SAH && c1[axis] > c0[axis])
        mid = split_sah(b, lo, hi, axis, c0[axis], c1[axis], area(&nd->box));
    if (mid == -2) {
        nd->first = lo;
        nd->count = hi - lo;
        nd->height = 0;
        for (int i = lo; i < hi; i++)
            b->leaf[b->order[i]] = at;
        return;
    }
    if (mid < 0) {
        mid = lo + (hi - lo) / 2;
        select_rank(b, lo, hi, mid, axis);
    }
    int left = b->nnodes;
    b->nnodes += 2;
    nd->first = left;
    nd->count = 0;
    build_node(b, left, lo, mid, at, depth + 1);
    build_node(b, left + 1, mid, hi, at, depth + 1);
    int hl = b->nodes[left].height, hr = b->nodes[left + 1].height;
    b->nodes[at].height = 1 + (hl > hr ? hl : hr);
}

/* Room for item ids below `need` in boxes and leaf (new ones not in the tree). */
static bool grow_ids(limen__bvh *b, int need)
{
    if (need <= b->id_cap)
        return true;
    /* the two arrays grow alike from id_cap; id_cap moves only when both have */
    int box_cap = b->id_cap, leaf_cap = b->id_cap;
    if (!limen__reserve((void **)&b->boxes, &box_cap, need, sizeof *b->boxes) ||
        !limen__reserve((void **)&b->leaf, &leaf_cap, need, sizeof *b->leaf))
        return false;
    for (int i = b->id_cap; i < leaf_cap; i++)
        b->leaf[i] = -1;
    b->id_cap = leaf_cap;
    return true;
}

bool limen__bvh_build(limen__bvh *b, const int *ids, int n, const limen__box *boxes,
                      int id_count)
{
    if (!limen__reserve((void **)&b->order, &b->order_cap, n > 0 ? n : 1, sizeof *b->order) ||
        !limen__reserve((void **)&b->nodes, &b->nodes_cap, n > 0 ? 2 * n : 1, sizeof *b->nodes))
        return false;
    if (!grow_ids(b, id_count))
        return false;
    if (id_count > 0)
        memcpy(b->boxes, boxes, sizeof *boxes * (size_t)id_count);
    for (int i = 0; i < b->id_cap; i++)
        b->leaf[i] = -1;
    if (n > 0)
        memcpy(b->order, ids, sizeof *ids * (size_t)n);
    b->nitems = b->norder = n;
    b->nnodes = 0;
    b->free_pair = 0;
    if (n == 0)
        return true;
    b->nnodes = 1;
    build_node(b, 0, 0, n, -1, 0);
    return true;
}

/* Recomputes the boxes and heights of node `at` and its ancestors from their contents. */
static void refit(limen__bvh *b, int at)
{
    for (; at >= 0; at = b->nodes[at].parent) {
        limen__bvh_node *nd = &b->nodes[at];
        limen__box_empty(&nd->box);
        if (nd->count) {
            for (int i = 0; i < nd->count; i++)
                limen__box_add(&nd->box, &b->boxes[b->order[nd->first + i]]);
            nd->height = 0;
        } else {
            const limen__bvh_node *l = &b->nodes[nd->first], *r = l + 1;
            limen__box_add(&nd->box, &l->box);
            limen__box_add(&nd->box, &r->box);
            nd->height = 1 + (l->height > r->height ? l->height : r->height);
        }
    }
}

void limen__bvh_update(limen__bvh *b, int id, const limen__box *box)
{
    if (!limen__bvh_holds(b, id))
        return;
    b->boxes[id] = *box;
    refit(b, b->leaf[id]);
}

/* ------------------------------------------------------------------ changes */

/* Copies node `from` into slot `to` under `parent`, pointing its children (or its items)
 * at the new slot. */
static void place(limen__bvh *b, int to, int from, int parent)
{
    b->nodes[to] = b->nodes[from];
    limen__bvh_node *nd = &b->nodes[to];
    nd->parent = parent;
    if (nd->count) {
        for (int i = 0; i < nd->count; i++)
            b->leaf[b->order[nd->first + i]] = to;
    } else {
        b->nodes[nd->first].parent = to;
        b->nodes[nd->first + 1].parent = to;
    }
}

/* The node to pair a new box with: walking down from the root, stop where a new parent over
 * this node costs less (twice the area of their union: the parent and the growth it brings
 * to its ancestors) than the least either child could cost, which is the growth of this
 * node passed on down plus the child's own growth (its whole union when a leaf, which gets
 * a parent). The greedy descent of dynamic AABB trees (Box2D's b2DynamicTree). */
static int best_sibling(const limen__bvh *b, const limen__box *box)
{
    int at = 0;
    while (!b->nodes[at].count) {
        const limen__bvh_node *nd = &b->nodes[at];
        limen__box u = nd->box;
        limen__box_add(&u, box);
        double joined = area(&u), here = 2 * joined, passed = 2 * (joined - area(&nd->box));
        double cost[2];
        for (int c = 0; c < 2; c++) {
            const limen__bvh_node *ch = &b->nodes[nd->first + c];
            limen__box cu = ch->box;
            limen__box_add(&cu, box);
            cost[c] = passed + area(&cu) - (ch->count ? 0 : area(&ch->box));
        }
        if (here < cost[0] && here < cost[1])
            break;
        at = nd->first + (cost[1] < cost[0]);
    }
    return at;
}

bool limen__bvh_insert(limen__bvh *b, int id, const limen__box *box)
{
    if (id < 0 || !grow_ids(b, id + 1))
        return false;
    if (b->leaf[id] >= 0) {
        limen__bvh_update(b, id, box);
        return true;
    }
    if (!limen__reserve((void **)&b->order, &b->order_cap, b->norder + 1, sizeof *b->order) ||
        !limen__reserve((void **)&b->nodes, &b->nodes_cap, b->nnodes + 2, sizeof *b->nodes))
        return false;
    b->boxes[id] = *box;
    limen__bvh_node fresh = { .box = *box, .parent = -1, .first = b->norder, .count = 1 };
    b->order[b->norder++] = id;
    b->nitems++;
    if (!b->nnodes) {
        b->nodes[0] = fresh;
        b->nnodes = 1;
        b->leaf[id] = 0;
        return true;
    }
    /* the sibling moves down into a pair of nodes beside the new leaf; its slot becomes
     * their parent */
    int at = best_sibling(b, box), pair = b->free_pair - 1;
    if (pair >= 0)
        b->free_pair = b->nodes[pair].first;
    else {
        pair = b->nnodes;
        b->nnodes += 2;
    }
    place(b, pair, at, at);
    fresh.parent = at;
    b->nodes[pair + 1] = fresh;
    b->leaf[id] = pair + 1;
    b->nodes[at].first = pair;
    b->nodes[at].count = 0;
    refit(b, at);
    return b->nodes[0].height <= HEIGHT_MAX;
}

void limen__bvh_remove(limen__bvh *b, int id)
{
    if (!limen__bvh_holds(b, id))
        return;
    int at = b->leaf[id];
    limen__bvh_node *nd = &b->nodes[at];
    int p = nd->first, last = nd->first + nd->count - 1;
    while (b->order[p] != id)
        p++;
    /* the leaf's last item takes the place; the range shrinks from its end */
    b->order[p] = b->order[last];
    b->order[last] = -1;
    while (b->norder > 0 && b->order[b->norder - 1] < 0)
        b->norder--;
    b->leaf[id] = -1;
    b->nitems--;
    if (--nd->count > 0) {
        refit(b, at);
        return;
    }
    int parent = nd->parent;
    if (parent < 0) {   /* the last item */
        b->nnodes = 0;
        b->norder = 0;
        b->free_pair = 0;
        return;
    }
    /* the sibling takes the parent's slot; the pair they were is free */
    int pair = b->nodes[parent].first;
    place(b, parent, pair + (pair == at), b->nodes[parent].parent);
    b->nodes[pair].first = b->free_pair;
    b->nodes[pair].count = -1;
    b->free_pair = pair + 1;
    refit(b, b->nodes[parent].parent);
}

/* ------------------------------------------------------------------ queries */

static bool push_item(int id, int **out, int *count, int *cap)
{
    if (!limen__reserve((void **)out, cap, *count + 1, sizeof **out))
        return false;
    (*out)[(*count)++] = id;
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
        if (q ? !limen__box_meets(&nd->box, q)
              : limen__box_outside(&nd->box, planes, nplanes, slack))
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
            if (q ? !limen__box_meets(ib, q) : limen__box_outside(ib, planes, nplanes, slack))
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

/* A ray prepared for slab tests: reciprocal direction, and which face each axis enters. */
typedef struct ray {
    double o[3], inv[3];
    int neg[3];
} ray;

/* Entry distance of the segment into the box, or INFINITY when it misses. A zero direction
 * component gets a reciprocal of +-1e300 rather than infinity: no 0 * inf = NaN where the
 * origin lies on a face, at the price of keeping a box the ray passes beside, never of
 * losing one it meets. */
static double slab(const limen__box *bx, const ray *r, double tmin, double tmax)
{
    for (int k = 0; k < 3; k++) {
        double t0 = ((r->neg[k] ? bx->hi : bx->lo)[k] - r->o[k]) * r->inv[k];
        double t1 = ((r->neg[k] ? bx->lo : bx->hi)[k] - r->o[k]) * r->inv[k];
        tmin = t0 > tmin ? t0 : tmin;
        tmax = t1 < tmax ? t1 : tmax;
    }
    return tmin <= tmax ? tmin : INFINITY;
}

void limen__bvh_ray(const limen__bvh *b, const double o[3], const double d[3], double tmin,
                    double tmax, limen__bvh_hit_fn hit, void *ctx)
{
    if (!b->nnodes)
        return;
    ray r;
    for (int k = 0; k < 3; k++) {
        r.o[k] = o[k];
        r.inv[k] = d[k] != 0 ? 1.0 / d[k] : signbit(d[k]) ? -1e300 : 1e300;
        r.neg[k] = r.inv[k] < 0;
    }
    struct { int node; double t; } stack[STACK_MAX];
    int top = 0;
    double t_root = slab(&b->nodes[0].box, &r, tmin, tmax);
    if (t_root == INFINITY)
        return;
    stack[top].node = 0;
    stack[top++].t = t_root;
    while (top > 0) {
        top--;
        if (stack[top].t > tmax)
            continue;   /* entered beyond a hit found since it was pushed */
        const limen__bvh_node *nd = &b->nodes[stack[top].node];
        if (nd->count) {
            for (int i = 0; i < nd->count; i++)
                hit(ctx, b->order[nd->first + i], &tmax);
            continue;
        }
        int l = nd->first, rt = nd->first + 1;
        double tl = slab(&b->nodes[l].box, &r, tmin, tmax);
        double tr = slab(&b->nodes[rt].box, &r, tmin, tmax);
        /* the nearer child on top */
        int near = tl <= tr ? l : rt, far = tl <= tr ? rt : l;
        double tn = tl <= tr ? tl : tr, tf = tl <= tr ? tr : tl;
        if (tf != INFINITY) {
            stack[top].node = far;
            stack[top++].t = tf;
        }
        if (tn != INFINITY) {
            stack[top].node = near;
            stack[top++].t = tn;
        }
    }
}
