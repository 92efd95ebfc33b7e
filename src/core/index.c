/* index.c - what makes a scene's cost follow what moved and what is seen: world matrices
 * recomputed only for the nodes that changed and their descendants, and a spatial index
 * (two bounding volume hierarchies, core/bvh.h) over the world bounds of the shapes and of
 * the surfaces, refitted for the nodes that moved, with leaves inserted and removed for the
 * nodes that come and go (O(log n) each), and rebuilt whole only when those changes since
 * the last build are many against what it holds (CHURN_SHARE): a scene made from nothing, or
 * one that loses half its nodes at once, costs one build, not a change per node.
 *
 * Every change to a node's transform, parent or size goes through limen__node_touch, which
 * puts the node on the scene's stale list. limen__scene_refresh recomputes the stale nodes;
 * when one of them has children, it walks the pool once, recomputing each node below a stale
 * one (a flag test per node, a matrix product only where needed). The index learns which
 * world matrices changed from the refresh and refits those leaves. */
#include <stdlib.h>
#include <string.h>

#include "core/bvh.h"
#include "core/dmath.h"
#include "core/index.h"
#include "core/internal.h"
#include "core/kinds.h"
#include "core/mesh.h"
#include "core/reserve.h"
#include "core/rtc.h"

/* Rebuild when the nodes created and destroyed since the last build outnumber this share of
 * those it holds (plus CHURN_MIN): the inserted leaves, placed one by one, make a tree whose
 * queries cost more than a built one's, and this bounds by how much; the build's
 * O(n log n) spread over n / 4 changes keeps each at O(log n) amortized. */
#define CHURN_SHARE 4
#define CHURN_MIN 32

struct limen__spatial {
    limen__bvh shapes, surfaces;
    bool built;                 /* false: rebuild on the next use */
    int *moved, nmoved, moved_cap;
    int *changed, nchanged, changed_cap;    /* slots created or destroyed since the last use */
    int churn;                  /* leaves inserted and removed since the last build */
    long builds;                /* full builds, for the tests */
    int *portals, nportals, portals_cap;    /* live portal slots, ascending */
    int *surf_slots, nsurf_slots, surf_slots_cap;   /* live mirror and portal slots, ascending */
    limen__box *boxes;          /* per slot, for building */
    int boxes_cap;
    int *ids, ids_cap;
    int *slots, slots_cap;      /* the live slots, ascending, for building */
    int *hits, hits_cap;
    limen__rtc *rtc;            /* the tracer's Embree copy of the trees (core/rtc.c) */
    bool rtc_current, rtc_failed;
};

void limen__index_free(limen_scene *s)
{
    limen__spatial *x = s->index;
    if (!x)
        return;
    limen__bvh_free(&x->shapes);
    limen__bvh_free(&x->surfaces);
    free(x->moved);
    free(x->changed);
    free(x->portals);
    free(x->surf_slots);
    free(x->boxes);
    free(x->ids);
    free(x->slots);
    free(x->hits);
    limen__rtc_free(x->rtc);
    free(x);
    s->index = NULL;
}

/* ------------------------------------------------------------------ stale nodes */

void limen__node_touch(limen_scene *s, limen__node *node)
{
    s->dirty = true;
    if (node->stale || s->all_stale)
        return;
    if (!limen__reserve((void **)&s->stale_list, &s->stale_cap, s->nstale + 1,
                        sizeof *s->stale_list)) {
        s->all_stale = true;    /* out of memory: recompute everything next time */
        return;
    }
    node->stale = true;
    s->stale_list[s->nstale++] = (uint32_t)limen__index(s, node);
}

static int churn_limit(const limen__spatial *x)
{
    return (x->shapes.nitems + x->surfaces.nitems) / CHURN_SHARE + CHURN_MIN;
}

void limen__scene_restructure(limen_scene *s, int slot)
{
    limen__spatial *x = s->index;
    if (!x || !x->built)
        return;
    /* past the share that rebuilds anyway, stop listing (thousands created at once) */
    if (x->churn + x->nchanged >= churn_limit(x) ||
        !limen__reserve((void **)&x->changed, &x->changed_cap, x->nchanged + 1,
                        sizeof *x->changed)) {
        x->built = false;
        x->nchanged = 0;
        return;
    }
    x->changed[x->nchanged++] = slot;
}

static void note_moved(limen_scene *s, int k)
{
    limen__spatial *x = s->index;
    if (!x || !x->built)
        return;
    if (!limen__reserve((void **)&x->moved, &x->moved_cap, x->nmoved + 1, sizeof *x->moved))
        x->built = false;
    else
        x->moved[x->nmoved++] = k;
}

void limen__node_compose_local(limen__node *node)
{
    if (node->explicit_local)
        return;
    mat4 r, f;
    /* R = Rz * Ry * Rx: X applied first (cglm's glm_euler_xyz composes the other way) */
    glm_rotate_make(r, node->euler[2], GLM_ZUP);
    glm_rotate(r, node->euler[1], GLM_YUP);
    glm_rotate(r, node->euler[0], GLM_XUP);
    glm_mat4_identity(f);
    glm_mat4_ins3(node->facing, f);
    glm_mat4_mul(r, f, node->local);
    glm_scale(node->local, node->scale);
    node->local[3][0] = node->pos[0];
    node->local[3][1] = node->pos[1];
    node->local[3][2] = node->pos[2];
}

static void recompute(limen_scene *s, uint32_t k)
{
    limen__node *node = &s->nodes[k];
    limen__node_compose_local(node);
    if (node->parent)
        glm_mat4_mul(s->nodes[node->parent - 1].world, node->local, node->world);
    else
        glm_mat4_copy(node->local, node->world);
    bool bad = false;
    for (int e = 0; e < 16; e++)
        bad |= !isfinite(node->world[e / 4][e % 4]);
    if (bad != node->bad_world)
        s->nbad += bad ? 1 : -1;
    node->bad_world = bad;
    note_moved(s, (int)k);
}

/* Every node below a stale one (or every node), each after its ancestors: `mark` holds
 * 1 = resolved and unchanged, 2 = resolved and recomputed; chains are acyclic by
 * construction (set_parent refuses cycles). */
static bool refresh_walk(limen_scene *s, bool all)
{
    unsigned char *mark = calloc((size_t)s->cap, 1);
    uint32_t *stack = malloc(sizeof *stack * (size_t)(s->cap ? s->cap : 1));
    if (!mark || !stack) {
        free(mark);
        free(stack);
        return false;
    }
    for (int l = 0; l < s->live_len; l++) {
        int i = s->live[l];
        if (i < 0 || mark[i])
            continue;
        int top = 0;
        uint32_t at = (uint32_t)i;
        for (;;) {  /* climb to the first resolved ancestor */
            stack[top++] = at;
            uint32_t p = s->nodes[at].parent;
            if (!p || mark[p - 1])
                break;
            at = p - 1;
        }
        while (top > 0) {
            uint32_t k = stack[--top];
            limen__node *node = &s->nodes[k];
            bool redo = all || node->stale || (node->parent && mark[node->parent - 1] == 2);
            if (redo)
                recompute(s, k);
            mark[k] = redo ? 2 : 1;
        }
    }
    free(mark);
    free(stack);
    return true;
}

void limen__scene_refresh(limen_scene *s)
{
    limen__meshes_settle(s, false);     /* levels of detail made on another thread */
    if (!s->dirty)
        return;
    bool all = s->all_stale || !s->world_valid, deep = all;
    for (int i = 0; i < s->nstale && !deep; i++)
        deep = s->nodes[s->stale_list[i]].nchildren > 0;
    if (all && s->index)
        s->index->built = false;
    if (deep) {
        if (!refresh_walk(s, all))
            return;     /* keep the old matrices; dirty stays set and the next call retries */
    } else {
        /* leaves only: no stale node lies below another, so each one's parent is current */
        for (int i = 0; i < s->nstale; i++)
            if (limen__alive(&s->nodes[s->stale_list[i]]))
                recompute(s, s->stale_list[i]);
    }
    for (int i = 0; i < s->nstale; i++)
        s->nodes[s->stale_list[i]].stale = false;
    s->nstale = 0;
    s->all_stale = false;
    s->world_valid = true;
    s->dirty = false;
}

int limen__scene_bad_world(const limen_scene *s)
{
    if (!s->nbad)
        return -1;
    for (int l = 0; l < s->live_len; l++) {
        if (s->live[l] < 0)
            continue;
        const limen__node *n = &s->nodes[s->live[l]];
        if (!n->bad_world)
            continue;
        /* the highest bad ancestor: where the overflow starts */
        while (n->parent && s->nodes[n->parent - 1].bad_world)
            n = &s->nodes[n->parent - 1];
        return limen__index(s, n);
    }
    return -1;
}

/* ------------------------------------------------------------------ spatial index */

static bool is_shape(const limen__node *n)
{
    return limen_kind_get(n->kind)->shape;
}

void limen__node_box(const limen__node *n, limen__box *b)
{
    /* the node's extent in its own space ... */
    double lo[3], hi[3];
    limen__node_extent(n, lo, hi);
    /* ... carried to the world exactly: centre by M, half-extents by |M| */
    double w[16];
    limen__d_from_f(&n->world[0][0], w);
    for (int r = 0; r < 3; r++) {
        double c = w[12 + r], e = 0;
        for (int k = 0; k < 3; k++) {
            c += w[k * 4 + r] * 0.5 * (lo[k] + hi[k]);
            e += fabs(w[k * 4 + r]) * 0.5 * (hi[k] - lo[k]);
        }
        b->lo[r] = c - e;
        b->hi[r] = c + e;
    }
    if (!limen__is_surface(n)) {
        /* and the bounding sphere the straddling test uses, which a shear may push out */
        double c[3], r;
        limen__box sb;
        limen__node_bounds(n, c, &r);
        limen__box_sphere(&sb, c, r);
        limen__box_add(b, &sb);
    }
    /* widened by far more than the rounding of the tests that use it (plane distances,
     * straddling, ray hits), so that the index only ever keeps too much */
    for (int k = 0; k < 3; k++) {
        double e = 1e-9 * (1.0 + fabs(b->lo[k]) + fabs(b->hi[k]));
        b->lo[k] -= e;
        b->hi[k] += e;
    }
}

static int by_slot(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static bool rebuild(limen_scene *s, limen__spatial *x)
{
    if (!limen__reserve((void **)&x->boxes, &x->boxes_cap, s->cap, sizeof *x->boxes) ||
        !limen__reserve((void **)&x->ids, &x->ids_cap, s->cap, sizeof *x->ids) ||
        !limen__reserve((void **)&x->slots, &x->slots_cap, s->count + 1, sizeof *x->slots))
        return false;
    /* the live nodes, not the pool; in ascending slot order, which the lists below promise
     * (portal order decides the order of straddlers, and so keeps plans made through the
     * index equal to those made by a full scan) */
    int nslots = 0;
    for (int l = 0; l < s->live_len; l++)
        if (s->live[l] >= 0)
            x->slots[nslots++] = s->live[l];
    qsort(x->slots, (size_t)nslots, sizeof *x->slots, by_slot);
    int nshapes = 0, nsurf = 0;
    x->nportals = 0;
    x->nsurf_slots = 0;
    /* shapes from the front of ids, surfaces from the back */
    for (int l = 0; l < nslots; l++) {
        int i = x->slots[l];
        const limen__node *n = &s->nodes[i];
        if (!(is_shape(n) || limen__is_surface(n)))
            continue;
        limen__node_box(n, &x->boxes[i]);
        if (is_shape(n)) {
            x->ids[nshapes++] = i;
            continue;
        }
        x->ids[s->cap - 1 - nsurf++] = i;
        if (!limen__reserve((void **)&x->surf_slots, &x->surf_slots_cap, x->nsurf_slots + 1,
                  sizeof *x->surf_slots))
            return false;
        x->surf_slots[x->nsurf_slots++] = i;
        if (n->kind == LIMEN_NODE_PORTAL) {
            if (!limen__reserve((void **)&x->portals, &x->portals_cap, x->nportals + 1,
                                sizeof *x->portals))
                return false;
            x->portals[x->nportals++] = i;
        }
    }
    if (!limen__bvh_build(&x->shapes, x->ids, nshapes, x->boxes, s->cap) ||
        !limen__bvh_build(&x->surfaces, nsurf ? x->ids + s->cap - nsurf : x->ids, nsurf,
                          x->boxes, s->cap))
        return false;
    x->nmoved = 0;
    x->nchanged = 0;
    x->churn = 0;
    x->builds++;
    x->built = true;
    x->rtc_current = false;
    return true;
}

/* Puts slot k into (or takes it out of) an ascending list. */
static bool list_set(int **list, int *n, int *cap, int k, bool in)
{
    int lo = 0, hi = *n;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if ((*list)[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    bool there = lo < *n && (*list)[lo] == k;
    if (in == there)
        return true;
    if (!in) {
        memmove(*list + lo, *list + lo + 1, sizeof **list * (size_t)(*n - lo - 1));
        (*n)--;
        return true;
    }
    if (!limen__reserve((void **)list, cap, *n + 1, sizeof **list))
        return false;
    memmove(*list + lo + 1, *list + lo, sizeof **list * (size_t)(*n - lo));
    (*list)[lo] = k;
    (*n)++;
    return true;
}

/* The slots created or destroyed since the last use, as leaves inserted and removed (a slot
 * destroyed and reused since may change trees). False when the tree must be rebuilt instead:
 * too many changes, out of memory, or an insertion made it too deep. */
static bool apply_changes(limen_scene *s, limen__spatial *x)
{
    if (x->churn + x->nchanged >= churn_limit(x))
        return false;
    for (int i = 0; i < x->nchanged; i++) {
        int k = x->changed[i];
        const limen__node *n = &s->nodes[k];
        bool alive = limen__alive(n), shape = alive && is_shape(n);
        bool surface = alive && limen__is_surface(n);
        limen__bvh *want = shape ? &x->shapes : surface ? &x->surfaces : NULL;
        limen__bvh *trees[2] = { &x->shapes, &x->surfaces };
        for (int t = 0; t < 2; t++)
            if (trees[t] != want && limen__bvh_holds(trees[t], k)) {
                limen__bvh_remove(trees[t], k);
                x->churn++;
            }
        if (want && !limen__bvh_holds(want, k)) {
            limen__box b;
            limen__node_box(n, &b);
            if (!limen__bvh_insert(want, k, &b))
                return false;
            x->churn++;
        }
        if (!list_set(&x->surf_slots, &x->nsurf_slots, &x->surf_slots_cap, k, surface) ||
            !list_set(&x->portals, &x->nportals, &x->portals_cap, k,
                      surface && n->kind == LIMEN_NODE_PORTAL))
            return false;
    }
    x->nchanged = 0;
    x->rtc_current = false;
    return true;
}

limen__spatial *limen__scene_index(limen_scene *s)
{
    limen__scene_refresh(s);
    if (s->dirty)
        return NULL;
    limen__spatial *x = s->index;
    if (!x) {
        x = s->index = calloc(1, sizeof *x);
        if (!x)
            return NULL;
    }
    if (x->built && x->nchanged && !apply_changes(s, x))
        x->built = false;
    if (!x->built)
        return rebuild(s, x) ? x : NULL;
    for (int i = 0; i < x->nmoved; i++) {
        int k = x->moved[i];
        const limen__node *n = &s->nodes[k];
        if (!limen__alive(n))
            continue;
        limen__box b;
        limen__node_box(n, &b);
        limen__bvh_update(is_shape(n) ? &x->shapes : &x->surfaces, k, &b);
        x->rtc_current = false;
    }
    x->nmoved = 0;
    return x;
}

const limen__bvh *limen__index_shapes(const limen__spatial *x)
{
    return &x->shapes;
}

const limen__bvh *limen__index_surfaces(const limen__spatial *x)
{
    return &x->surfaces;
}

const limen__rtc *limen__index_rtc(limen__spatial *x)
{
    if (x->rtc_failed)
        return NULL;
    if (!x->rtc && !(x->rtc = limen__rtc_create())) {
        x->rtc_failed = true;
        return NULL;
    }
    if (!x->rtc_current && !limen__rtc_commit(x->rtc, &x->shapes, &x->surfaces)) {
        x->rtc_failed = true;
        return NULL;
    }
    x->rtc_current = true;
    return x->rtc;
}

int limen__index_portals(const limen__spatial *x, const int **out)
{
    *out = x->portals;
    return x->nportals;
}

int limen__index_surface_slots(const limen__spatial *x, const int **out)
{
    *out = x->surf_slots;
    return x->nsurf_slots;
}

long limen__index_builds(const limen__spatial *x)
{
    return x->builds;
}
