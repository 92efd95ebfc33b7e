/* plan.h - the planner's internals, shared by plan.c and cull.c (the spatial index's part). */
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
typedef struct limen__view_surface {
    int node;               /* node index */
    int child;              /* bfs index of the child view, or -1 */
    int state;
    int rect[4];            /* pixels its visible part may cover in this view */
} limen__view_surface;

/* A mirror or portal of the scene, as every view tests it. */
typedef struct limen__plan_surface {
    int node;
    int exit;               /* node index of the surface the view comes out of */
    double plane[4];
    double corners[4][3];
    double x[16], xinv[16];
    double err[3];          /* bound on the float rounding of its corners, per world axis */
    bool has_x;
} limen__plan_surface;

/* A view as the planner finds it (breadth first), in double precision. */
typedef struct limen__plan_view {
    limen_view pub;
    double view[16];
    double eye[3];
    double clip[4];
    double clip_err[3];     /* the exit surface's rounding bound (limen__plan_surface.err) */
    int parent;             /* bfs index */
    int surface, exit;      /* node indices, -1 for the camera */
    int first_surface, nsurfaces;   /* range in view_surfaces */
    int first_thing, nthings;       /* range in thing_slots */
    int made_by;            /* the parent's view_surfaces entry that made it */
    bool dropped;           /* over the frame budget: not in the tree */
} limen__plan_view;

struct limen_plan {
    int width, height;
    limen_depth_range range;
    limen_limits limits;    /* resolved: defaults filled in */
    limen_cull cull;
    bool multisample;       /* surfaces count by any part of a pixel (limen_plan_desc) */
    float znear;
    float proj_f[16];
    double proj_d[16];
    double frustum[6][4];   /* proj_d's planes in eye space (limen__frustum_planes) */

    limen__plan_view *found;        /* the views in the order they are found: breadth first */
    int nviews, found_cap;
    limen_view *views;              /* the tree in draw order: depth first (public) */
    int count, views_cap;
    int *bfs_to_dfs, bfs_to_dfs_cap;    /* per found view: its index in views, if kept */
    int *dfs_to_bfs, dfs_to_bfs_cap;    /* per view: its index in found */
    limen__plan_surface *surfaces;  /* the scene's visible mirrors and portals */
    int nsurfaces, surfaces_cap;
    limen__view_surface *view_surfaces;     /* per found view, the surfaces it sees */
    int nview_surfaces, view_surfaces_cap;
    limen_view_surface *public_surfaces;    /* view_surfaces in draw order, public form */
    int public_surfaces_cap;
    int *public_first, public_first_cap;    /* per view (draw order): first in public_surfaces */
    int *thing_slots, nthing_slots, thing_slots_cap;    /* per found view, its shapes (node
                                                         * slots, ascending) */
    limen_node *things;             /* thing_slots in draw order, as handles */
    int things_cap;
    int *things_first, things_first_cap;    /* per view (draw order): first index in things */
    limen_clone *clones;            /* shapes passing through portals */
    int nclones, clones_cap;
    int *clone_of, clone_of_cap;    /* per node slot: index in clones, or -1 */
    int truncated;
    limen_frame_budget budget;      /* with the defaults filled in */
    int64_t view_pixels;
    int64_t surface_tests;          /* exact surface-in-view tests made (tests read it) */
    unsigned budgets_hit;
    int64_t triangles;              /* mesh triangles of the views looked into so far */
    /* the spatial index's part (core/cull.c) */
    int *surface_of, surface_of_cap;    /* per node slot: index in surfaces, or -1 */
    int *candidates, candidates_cap;    /* one view's candidate surfaces */
    int *shape_hits, shape_hits_cap;    /* one view's shapes, as the index returns them */
    uint64_t *slot_bits;            /* one bit per node slot: shape_hits put in node order */
    int slot_bits_cap;
    bool sort_hits;                 /* tests: order shape_hits by sorting alone, never the bits */
    limen__bvh_stats stat_index;    /* the index's box tests */
};

/* The surfaces (indices in p->surfaces, ascending) whose boxes meet view v's narrowed
 * region, left in p->candidates; their count, or -1 when out of memory. */
int limen__plan_candidates(limen_plan *p, limen_scene *s, const limen__plan_view *v);
/* The shapes (node slots, ascending; visible ones) whose boxes meet view v's region, left in
 * p->shape_hits: what limen_plan_things lists for the view; their count, or -1 when out of
 * memory. */
int limen__plan_view_shapes(limen_plan *p, limen_scene *s, const limen__plan_view *v);
/* The slots of the scene's mirrors and portals, ascending, from its index; or *out = NULL
 * and s->cap (every slot) without the index. */
int limen__plan_surface_slots(limen_scene *s, const int **out);

/* The surfaces seen from view `view` (draw-order index); returns their count. */
static inline int limen__plan_view_surfaces(const limen_plan *p, int view,
                                            const limen__view_surface **out)
{
    const limen__plan_view *v = &p->found[p->dfs_to_bfs[view]];
    *out = v->nsurfaces ? &p->view_surfaces[v->first_surface] : NULL;
    return v->nsurfaces;
}

/* Draw-order index of a child given as a bfs index (-1 stays -1). */
static inline int limen__plan_child_view(const limen_plan *p, int bfs_child)
{
    return bfs_child >= 0 ? p->bfs_to_dfs[bfs_child] : -1;
}

/* Node index of the surface view `view` comes out of (never drawn in it), or -1. */
static inline int limen__plan_exit_node(const limen_plan *p, int view)
{
    return p->found[p->dfs_to_bfs[view]].exit;
}

#endif
