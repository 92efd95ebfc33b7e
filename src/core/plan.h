/* plan.h - the planner's internals, shared with the renderers. */
#ifndef LIMEN_PLAN_H
#define LIMEN_PLAN_H

#include "core/bvh.h"
#include "core/internal.h"

enum {
    LIMEN__SURF_CHILD,      /* front-facing, recursed into: `child` is its view (bfs index) */
    LIMEN__SURF_FILL,       /* front-facing, recursion stopped: draw the fill colour */
    LIMEN__SURF_BACK        /* a mirror seen from behind: draw its matte back */
};

/* A surface as seen from one view. */
typedef struct limen__vsurf {
    int node;               /* node index */
    int child;              /* bfs index of the child view, or -1 */
    int state;
    int rect[4];            /* pixels its visible part may cover in this view */
} limen__vsurf;

typedef struct limen__psurf {
    int node;
    int exit;               /* node index of the surface the view comes out of */
    double plane[4];
    double corners[4][3];
    double x[16], xinv[16];
    double err[3];          /* bound on the float rounding of its corners, per world axis */
    bool has_x;
} limen__psurf;

typedef struct limen__pview {
    limen_view pub;
    double view[16];
    double eye[3];
    double clip[4];
    double clip_err[3];     /* the exit surface's rounding bound (limen__psurf.err) */
    int parent;             /* bfs index */
    int surface, exit;      /* node indices, -1 for the camera */
    int first_surf, nsurf;  /* range in vsurf */
    int from_vsurf;         /* the parent's vsurf entry that made it */
    bool dropped;           /* over the frame budget: not in the tree */
} limen__pview;

struct limen_plan {
    int width, height;
    limen_depth_range range;
    limen_limits limits;    /* resolved: defaults filled in */
    limen_cull cull;
    bool multisample;       /* surfaces count by any part of a pixel (limen_plan_desc) */
    float znear;
    float proj_f[16];
    double proj_d[16];

    limen__pview *pv;       /* breadth first */
    int nviews, pv_cap;
    limen_view *views;      /* depth first (public) */
    int count, views_cap;
    limen__psurf *surf;
    int nsurf, surf_cap;
    limen__vsurf *vsurf;
    int nvsurf, vsurf_cap;
    limen_view_surface *pubsurf;    /* vsurf in draw order, public form */
    int pubsurf_cap;
    int *pubfirst, pubfirst_cap;     /* per view (draw order): first index in pubsurf */
    limen_clone *clones;            /* shapes passing through portals */
    int nclones, clones_cap;
    int *clone_of, clone_of_cap;    /* per node slot: index in clones, or -1 */
    int *tmp, tmp_cap;
    int *bfs_to_dfs, *dfs_to_bfs;
    int truncated;
    limen_frame_budget budget;      /* with the defaults filled in */
    int64_t view_pixels;
    int64_t surface_tests;          /* exact surface-in-view tests made (tests read it) */
    unsigned budgets_hit;
    int64_t triangles;              /* mesh triangles of the views looked into so far */
    int *shape_hits;                /* scratch of the triangle count: the shapes of a view */
    int shape_hits_cap;
    /* the spatial index's part (core/cull.c) */
    int *surf_of, surf_of_cap;      /* per node slot: index in surf, or -1 */
    int *cand, cand_cap;            /* one view's candidate surfaces */
    limen__bvh_stats stat_index;    /* the index's box tests */
};

/* The surfaces (indices in p->surf, ascending) whose boxes meet view v's narrowed region,
 * left in p->cand; their count, or -1 when out of memory. */
int limen__plan_candidates(limen_plan *p, limen_scene *s, const limen__pview *v);
/* The shapes (node slots) whose boxes meet view v's region, as limen_plan_view_things finds
 * them, left in p->shape_hits; their count, or -1 when out of memory. */
int limen__plan_view_shapes(limen_plan *p, limen_scene *s, const limen__pview *v);
/* The slots of the scene's mirrors and portals, ascending, from its index; or *out = NULL
 * and s->cap (every slot) without the index. */
int limen__plan_surface_slots(limen_scene *s, const int **out);

/* The surfaces seen from view `view` (draw-order index); returns their count. */
static inline int limen__plan_view_surfaces(const limen_plan *p, int view,
                                            const limen__vsurf **out)
{
    const limen__pview *v = &p->pv[p->dfs_to_bfs[view]];
    *out = v->nsurf ? &p->vsurf[v->first_surf] : NULL;
    return v->nsurf;
}

/* Draw-order index of a child given as a bfs index (-1 stays -1). */
static inline int limen__plan_child_view(const limen_plan *p, int bfs_child)
{
    return bfs_child >= 0 ? p->bfs_to_dfs[bfs_child] : -1;
}

/* Node index of the surface view `view` comes out of (never drawn in it), or -1. */
static inline int limen__plan_exit_node(const limen_plan *p, int view)
{
    return p->pv[p->dfs_to_bfs[view]].exit;
}

#endif
