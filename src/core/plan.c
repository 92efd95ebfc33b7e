/* plan.c - the view planner: from scene, camera and limits to a tree of virtual views.
 *
 * Views are found breadth first, so a view budget is spent on shallow levels before deep
 * ones, and then stored depth first (draw order). A child view exists only where its surface
 * faces the parent's eye, survives the parent's clip plane and near plane, and covers at
 * least one pixel centre inside the parent's scissor rectangle; the child's scissor is that
 * rectangle. Matrices are composed in double precision. Each view also lists the shapes it
 * may show (limen_plan_things), found once, as the triangle budget counts them.
 *
 * limen_plan_build is its phases, in order (see "the phases of a build" below). */
#include <float.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dmath.h"
#include "core/internal.h"
#include "core/lmath.h"
#include "core/mesh.h"
#include "core/plan.h"
#include "core/reserve.h"
#include "core/testing.h"

#define MAX_POLY 12

/* ------------------------------------------------------------------ storage */

limen_status limen_plan_create(limen_plan **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    *out = calloc(1, sizeof **out);
    return *out ? LIMEN_OK : LIMEN_ERR_NOMEM;
}

void limen_plan_destroy(limen_plan *p)
{
    if (!p)
        return;
    free(p->found);
    free(p->views);
    free(p->surfaces);
    free(p->view_surfaces);
    free(p->bfs_to_dfs);
    free(p->dfs_to_bfs);
    free(p->public_surfaces);
    free(p->public_first);
    free(p->clones);
    free(p->clone_of);
    free(p->surface_of);
    free(p->candidates);
    free(p->shape_hits);
    free(p->slot_bits);
    free(p->thing_slots);
    free(p->things);
    free(p->things_first);
    free(p);
}

int limen_plan_count(const limen_plan *p)
{
    return p ? p->count : 0;
}

const limen_view *limen_plan_view(const limen_plan *p, int i)
{
    return p && i >= 0 && i < p->count ? &p->views[i] : NULL;
}

int limen_plan_truncated(const limen_plan *p)
{
    return p ? p->truncated : 0;
}

void limen_plan_get_work(const limen_plan *p, limen_plan_work *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof *out);
    if (!p)
        return;
    out->views = p->count;
    out->truncated = p->truncated;
    out->view_pixels = p->view_pixels;
    out->surface_tests = p->surface_tests;
    out->budgets_hit = p->budgets_hit;
    out->triangles = p->triangles;
}

/* ------------------------------------------------------------------ screen rectangles */

/* Multisampled frames: the rectangle of the pixels (within scissor s) that the convex
 * polygon (sx, sy) meets at all, not only at their centres, as a sample anywhere in a pixel
 * may fall inside it; false if none. Row by row: the polygon's x extent over the row's
 * band is that of its edges clipped to the band. */
static bool pixels_met(const double *sx, const double *sy, int n, const int s[4], int rect[4])
{
    double y0 = 1e300, y1 = -1e300;
    for (int i = 0; i < n; i++) {
        y0 = fmin(y0, sy[i]);
        y1 = fmax(y1, sy[i]);
    }
    double r0 = fmax(floor(y0), s[1]), r1 = fmin(ceil(y1) - 1, s[1] + s[3] - 1);
    double cx0 = 1e300, cx1 = -1e300, cy0 = 1e300, cy1 = -1e300;
    for (double py = r0; py <= r1; py++) {
        double xa = 1e300, xb = -1e300;
        for (int i = 0; i < n; i++) {
            int j = (i + 1) % n;
            double ya = sy[i], yb = sy[j], lo = fmax(fmin(ya, yb), py),
                   hi = fmin(fmax(ya, yb), py + 1);
            if (lo > hi)
                continue;
            double xl = sx[i], xh = sx[j];
            if (fabs(yb - ya) > 1e-12) {
                xl = sx[i] + (lo - ya) / (yb - ya) * (sx[j] - sx[i]);
                xh = sx[i] + (hi - ya) / (yb - ya) * (sx[j] - sx[i]);
            }
            xa = fmin(xa, fmin(xl, xh));
            xb = fmax(xb, fmax(xl, xh));
        }
        double qa = fmax(floor(xa), s[0]), qb = fmin(ceil(xb) - 1, s[0] + s[2] - 1);
        if (qb >= qa) {
            cx0 = fmin(cx0, qa);
            cx1 = fmax(cx1, qb);
            cy0 = fmin(cy0, py);
            cy1 = fmax(cy1, py);
        }
    }
    if (!(cx1 >= cx0 && cy1 >= cy0))
        return false;
    rect[0] = (int)cx0;
    rect[1] = (int)cy0;
    rect[2] = (int)(cx1 - cx0) + 1;
    rect[3] = (int)(cy1 - cy0) + 1;
    return true;
}

/* Pixel rectangle (x, y, w, h) of the pixel centres that the surface's visible part may
 * cover in view v; false if none. */
static bool surface_rect(const limen_plan *p, const limen__plan_view *v, const limen__plan_surface *sf,
                         int rect[4])
{
    double a[MAX_POLY][3], b[MAX_POLY][3];
    memcpy(a, sf->corners, sizeof sf->corners);
    int n = 4;
    if (v->pub.depth > 0) {
        /* only what lies in front of the exit surface: a surface on its plane (to within the
         * rounding of the float world matrices of both) is not, as for the ray tracer, whose
         * next segment leaves the exit's plane. The bound follows the matrices' entries
         * along the plane's normal, not the size of the coordinates: two facing mirrors a
         * billion units wide and ten apart are not on each other's plane. */
        double c[4], tol = 0;
        memcpy(c, v->clip, sizeof c);
        for (int k = 0; k < 3; k++)
            tol += fabs(c[k]) * (sf->err[k] + v->clip_err[k]);
        c[3] -= 4.0 * tol;
        n = limen__d_clip3((const double(*)[3])a, n, c, b, MAX_POLY - 1);
        memcpy(a, b, sizeof(double) * 3 * (size_t)n);
    }
    /* to view space, then keep what is in front of the eye: surfaces are not cut by the
     * near plane (the renderer draws them with depth clamping) */
    for (int i = 0; i < n; i++)
        limen__d_point(v->view, a[i], a[i]);
    /* keep what lies inside the four sides of the frustum (planes through the eye, so no
     * distance scale enters): the projection of what is left is bounded, however close
     * the surface is to the eye. Right, left, top, bottom. */
    static const int sides[4] = { 1, 0, 3, 2 };
    for (int k = 0; k < 4 && n >= 3; k++) {
        n = limen__d_clip3((const double(*)[3])a, n, p->frustum[sides[k]], b, MAX_POLY - 1);
        memcpy(a, b, sizeof(double) * 3 * (size_t)n);
    }
    if (n < 3)
        return false;
    for (int i = 0; i < n; i++)
        if (!(-a[i][2] > 0))
            return false;   /* a vertex at the eye: the surface's plane passes through it */
    double sx[MAX_POLY], sy[MAX_POLY];
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int i = 0; i < n; i++) {
        double w = -a[i][2];
        sx[i] = (p->proj_d[0] * a[i][0] + p->proj_d[8] * a[i][2]) / w;
        sy[i] = (p->proj_d[5] * a[i][1] + p->proj_d[9] * a[i][2]) / w;
        sx[i] = (sx[i] + 1.0) * 0.5 * p->width;
        sy[i] = (sy[i] + 1.0) * 0.5 * p->height;
        x0 = fmin(x0, sx[i]);
        x1 = fmax(x1, sx[i]);
        y0 = fmin(y0, sy[i]);
        y1 = fmax(y1, sy[i]);
    }
    if (p->cull == LIMEN_CULL_FRUSTUM) {
        memcpy(rect, (int[4]){ 0, 0, p->width, p->height }, sizeof(int) * 4);
        return true;
    }
    if (p->multisample)
        return pixels_met(sx, sy, n, v->pub.scissor, rect);
    /* pixel k has its centre at k + 0.5 */
    double py0 = ceil(y0 - 0.5), py1 = floor(y1 - 0.5);
    const int *s = v->pub.scissor;
    py0 = fmax(py0, s[1]);
    py1 = fmin(py1, s[1] + s[3] - 1);
    /* the pixel centres the convex polygon covers, row by row: a sliver whose bounding box
     * spans many pixels may cover none */
    const double eps = 1e-7;
    double cx0 = 1e300, cx1 = -1e300, cy0 = 1e300, cy1 = -1e300;
    for (double py = py0; py <= py1; py++) {
        double yc = py + 0.5, xa = 1e300, xb = -1e300;
        for (int i = 0; i < n; i++) {
            int j = (i + 1) % n;
            double ya = sy[i], yb = sy[j];
            if ((yc < fmin(ya, yb) - eps) || (yc > fmax(ya, yb) + eps))
                continue;
            double x;
            if (fabs(yb - ya) < 1e-12) {
                xa = fmin(xa, fmin(sx[i], sx[j]));
                xb = fmax(xb, fmax(sx[i], sx[j]));
                continue;
            }
            double t = fmin(1.0, fmax(0.0, (yc - ya) / (yb - ya)));
            x = sx[i] + t * (sx[j] - sx[i]);
            xa = fmin(xa, x);
            xb = fmax(xb, x);
        }
        double qa = fmax(ceil(xa - 0.5 - eps), s[0]), qb = fmin(floor(xb - 0.5 + eps), s[0] + s[2] - 1);
        if (qb >= qa) {
            cx0 = fmin(cx0, qa);
            cx1 = fmax(cx1, qb);
            cy0 = fmin(cy0, py);
            cy1 = fmax(cy1, py);
        }
    }
    if (!(cx1 >= cx0 && cy1 >= cy0))
        return false;
    double px0 = cx0, px1 = cx1;
    py0 = cy0, py1 = cy1;
    rect[0] = (int)px0;
    rect[1] = (int)py0;
    rect[2] = (int)(px1 - px0) + 1;
    rect[3] = (int)(py1 - py0) + 1;
    return true;
}

/* ------------------------------------------------------------------ views */

static void fill_public(limen__plan_view *v, limen_scene *s, const limen_plan *p)
{
    limen_view *pub = &v->pub;
    limen__d_to_f(v->view, pub->view);
    for (int i = 0; i < 3; i++)
        pub->eye[i] = (float)v->eye[i];
    for (int i = 0; i < 4; i++)
        pub->clip_plane[i] = (float)v->clip[i];
    pub->stencil = pub->depth;
    memcpy(pub->proj, p->proj_f, sizeof pub->proj);
    if (pub->depth == 0) {
        pub->clip = LIMEN_CLIP_NONE;
        return;
    }
    pub->clip = p->limits.clip;
    if (p->limits.clip != LIMEN_CLIP_OBLIQUE)
        return;
    /* The clip plane in this view's eye space; the eye must be clearly behind it. Closer than
     * the camera's near distance the oblique near plane would squeeze depth precision below
     * what the camera itself has, so the user clip plane takes over there. */
    double vinv[16], c[4];
    float cf[4];
    pub->clip = LIMEN_CLIP_PLANE;
    if (!limen__d_inv(v->view, vinv) || !limen__d_plane(vinv, v->clip, c))
        return;
    if (!(-c[3] >= p->znear))
        return;
    for (int i = 0; i < 4; i++)
        cf[i] = (float)c[i];
    if (limen_oblique_projection(p->proj_f, cf, p->range, pub->proj) == LIMEN_OK)
        pub->clip = LIMEN_CLIP_OBLIQUE;
    (void)s;
}

/* Adaptive depth: a view whose every pixel is multiplied by tints whose product is under
 * the threshold cannot change a pixel by more than it. */
static bool too_faint(const limen_plan *p, const limen__plan_view *v, const limen__node *n)
{
    if (p->limits.adaptive <= 0 || n->kind != LIMEN_NODE_MIRROR)
        return false;
    float m = 0;
    for (int k = 0; k < 3; k++)
        m = fmaxf(m, v->pub.tint[k] * n->tint[k]);
    return m < p->limits.adaptive;
}

static limen__plan_view *push_view(limen_plan *p)
{
    if (!limen__reserve((void **)&p->found, &p->found_cap, p->nviews + 1, sizeof *p->found))
        return NULL;
    limen__plan_view *v = &p->found[p->nviews++];
    memset(v, 0, sizeof *v);
    v->pub.first_child = v->pub.next_sibling = v->pub.parent = -1;
    v->exit = -1;
    v->surface = -1;
    return v;
}

static bool push_view_surface(limen_plan *p, limen__plan_view *v, int surf, int child, int state,
                       const int rect[4])
{
    if (!limen__reserve((void **)&p->view_surfaces, &p->view_surfaces_cap, p->nview_surfaces + 1, sizeof *p->view_surfaces))
        return false;
    p->view_surfaces[p->nview_surfaces++] = (limen__view_surface){ surf, child, state, { rect[0], rect[1], rect[2], rect[3] } };
    p->view_pixels += (int64_t)rect[2] * rect[3];   /* the renderer draws it in this view */
    v->nsurfaces++;
    return true;
}

/* |v| in float, as glm_vec3_norm has it, of a const vector. */
static float norm3f(const float v[3])
{
    return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Per world axis r, a bound on how far float rounding of the world matrix W (half an ulp
 * per entry) can move a corner (+-w/2, +-h/2, 0) of the surface: sum over the columns j of
 * ulp(W[j][r]) times the corner's local coordinate, plus the translation's. */
static void rounding_bound(const limen__node *n, double err[3])
{
    const double half[2] = { 0.5 * n->dims[0], 0.5 * n->dims[1] };
    for (int r = 0; r < 3; r++) {
        err[r] = 0.5 * ((double)fabsf(n->world[3][r]) * FLT_EPSILON + FLT_MIN);
        for (int j = 0; j < 2; j++)
            err[r] += 0.5 * ((double)fabsf(n->world[j][r]) * FLT_EPSILON + FLT_MIN) * half[j];
    }
}

static limen_status collect_surfaces(limen_plan *p, limen_scene *s)
{
    p->nsurfaces = 0;
    if (!limen__reserve((void **)&p->surface_of, &p->surface_of_cap, s->cap, sizeof *p->surface_of))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    for (int i = 0; i < s->cap; i++)
        p->surface_of[i] = -1;
    /* the index's list of surfaces, or every slot */
    const int *slots = NULL;
    int nslots = limen__plan_surface_slots(s, &slots);
    for (int k = 0; k < nslots; k++) {
        int i = slots ? slots[k] : k;
        limen__node *n = &s->nodes[i];
        if (!limen__alive(n) || !n->visible || !limen__is_surface(n))
            continue;
        p->surface_of[i] = p->nsurfaces;
        if (!limen__reserve((void **)&p->surfaces, &p->surfaces_cap, p->nsurfaces + 1, sizeof *p->surfaces))
            return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
        limen__plan_surface *sf = &p->surfaces[p->nsurfaces];
        memset(sf, 0, sizeof *sf);
        sf->node = i;
        rounding_bound(n, sf->err);
        limen__surface_plane_d(n, sf->plane);
        limen__surface_corners(n, sf->corners);
        sf->has_x = limen__surface_matrix_d(s, n, sf->x);
        if (sf->has_x && n->kind == LIMEN_NODE_PORTAL &&
            (s->test_faults & LIMEN_FAULT_PORTAL_NO_TURN)) {
            /* X * (W_A R_y(180) W_A^-1) = W_B S(k) W_A^-1: the turn taken out again */
            double wa[16], wainv[16], turn[16];
            limen__d_from_f(&n->world[0][0], wa);
            limen__d_identity(turn);
            turn[0] = turn[10] = -1.0;
            if (limen__d_inv(wa, wainv)) {
                limen__d_mul(wa, turn, turn);
                limen__d_mul(turn, wainv, turn);
                limen__d_mul(sf->x, turn, sf->x);
            }
        }
        sf->has_x = sf->has_x && limen__d_inv(sf->x, sf->xinv);
        sf->exit = n->kind == LIMEN_NODE_PORTAL ? (int)n->pair - 1 : i;
        if (n->kind == LIMEN_NODE_PORTAL && n->pair) {
            const limen__node *b = &s->nodes[n->pair - 1];
            double wa = norm3f(n->world[0]) * n->dims[0];
            double ha = norm3f(n->world[1]) * n->dims[1];
            double wb = norm3f(b->world[0]) * b->dims[0];
            double hb = norm3f(b->world[1]) * b->dims[1];
            if (fabs((wa / ha) / (wb / hb) - 1.0) > 1e-3)
                return limen__fail(s, LIMEN_ERR_ARG,
                                   "%s%sportals '%s' and '%s' differ in shape in the world "
                                   "(%.4gx%.4g against %.4gx%.4g): width/height must match",
                                   n->label, n->label[0] ? ": " : "", limen__node_title(n),
                                   limen__node_title(b), wa, ha,
                                   wb, hb);
            if (!b->visible)
                sf->has_x = false;
        }
        p->nsurfaces++;
    }
    return LIMEN_OK;
}

/* Shapes passing through portals: the copy's matrix and the two planes. */
static limen_status collect_clones(limen_plan *p, limen_scene *s)
{
    p->nclones = 0;
    if (!limen__reserve((void **)&p->clone_of, &p->clone_of_cap, s->cap, sizeof *p->clone_of))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    int n = limen__find_straddlers(s, p->clone_of);
    if (n && !limen__reserve((void **)&p->clones, &p->clones_cap, n, sizeof *p->clones))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        int a = i >= 0 ? p->clone_of[i] : -1;
        if (a < 0)
            continue;
        const limen__node *pa = &s->nodes[a], *pb = &s->nodes[pa->pair - 1];
        double x[16], keep[4], copy_keep[4];
        p->clone_of[i] = -1;
        if (!limen__surface_matrix_d(s, pa, x))
            continue;
        limen__surface_plane_d(pa, keep);
        limen__surface_plane_d(pb, copy_keep);
        limen_clone *c = &p->clones[p->nclones];
        c->node = limen__node_handle(s, i);
        c->portal = limen__node_handle(s, a);
        limen__d_to_f(x, c->matrix);
        for (int k = 0; k < 4; k++) {
            c->keep[k] = (float)keep[k];
            c->copy_keep[k] = (float)copy_keep[k];
        }
        p->clone_of[i] = p->nclones++;
    }
    return LIMEN_OK;
}

static bool all_finite(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

static bool view_finite(const limen_view *v)
{
    return all_finite(v->view, 16) && all_finite(v->proj, 16) && all_finite(v->eye, 3) &&
           all_finite(v->clip_plane, 4) && all_finite(v->tint, 3);
}

/* ------------------------------------------------------------------ budgets */

/* Which frame budget (LIMEN_BUDGET_* bit) is spent before a view is looked into; 0 if none.
 * Views are looked into breadth first, so once one is dropped, all later ones are; what a
 * view spends past the budget is at most one view's work (every surface in its scissor). */
static unsigned budget_spent(const limen_plan *p)
{
    if (p->view_pixels >= p->budget.view_pixels)
        return LIMEN_BUDGET_VIEW_PIXELS;
    if (p->nsurfaces > p->budget.surface_tests - p->surface_tests)
        return LIMEN_BUDGET_SURFACE_TESTS;
    return 0;
}

/* A view made by its parent but over the budget when its turn came: the parent shows the
 * surface's fill instead, and the view is left out of the tree (it has no children yet). */
static void drop_view(limen_plan *p, limen__plan_view *v, unsigned why)
{
    limen__view_surface *vs = &p->view_surfaces[v->made_by];
    vs->child = -1;
    vs->state = LIMEN__SURF_FILL;
    v->dropped = true;
    p->truncated++;
    p->budgets_hit |= why;
}

/* ------------------------------------------------------------------ the phases of a build */

/* Phase 1: the scene is sound and the desc valid; the resolved limits, the projection and
 * the work counters of a new plan. */
static limen_status check_inputs(limen_plan *p, limen_scene *s, const limen_plan_desc *desc)
{
    limen_status st = limen__scene_check(s);
    if (st)
        return st;
    limen_plan_desc d = limen_plan_desc_defaults(desc);
    p->width = d.width;
    p->height = d.height;
    if ((unsigned)d.range >= LIMEN_DEPTH_RANGE_COUNT || (unsigned)d.cull >= LIMEN_CULL_COUNT)
        return limen__fail(s, LIMEN_ERR_ARG, "plan: unknown depth range or cull rule");
    if ((st = limen__limits_resolve(s, "plan", &d.limits, &p->limits)))
        return st;
    p->budget = p->limits.budget;
    p->range = d.range;
    p->cull = d.cull;
    p->multisample = d.multisample != 0;
    p->nviews = p->nview_surfaces = p->nthing_slots = p->count = p->truncated = 0;
    p->view_pixels = p->surface_tests = 0;
    p->budgets_hit = 0;
    p->triangles = 0;
    float view_f[16];
    if ((st = limen_camera_matrices(s, (float)p->width / (float)p->height, p->range, view_f,
                                    p->proj_f)))
        return st;
    limen__d_from_f(p->proj_f, p->proj_d);
    limen__frustum_planes(p->proj_d, NULL, p->range, p->frustum);
    limen_camera_get_lens(s, limen_scene_get_camera(s), NULL, &p->znear, NULL);
    return LIMEN_OK;
}

/* Phase 4: the camera's view, the root of the tree, over the whole image. */
static limen_status root_view(limen_plan *p, limen_scene *s)
{
    limen__plan_view *root = push_view(p);
    if (!root)
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    limen__scene_refresh(s);
    const limen__node *cam = &s->nodes[s->camera - 1];
    double cw[16];
    limen__d_from_f(&cam->world[0][0], cw);
    if (!limen__d_inv(cw, root->view))
        return limen__fail(s, LIMEN_ERR_DEGENERATE, "plan: the camera's matrix is singular");
    for (int i = 0; i < 3; i++)
        root->eye[i] = cw[12 + i];
    root->pub.kind = LIMEN_VIEW_CAMERA;
    root->pub.scissor[2] = p->width;
    root->pub.scissor[3] = p->height;
    root->pub.tint[0] = root->pub.tint[1] = root->pub.tint[2] = 1.0f;
    p->surface_tests = 0;
    memset(&p->stat_index, 0, sizeof p->stat_index);
    return LIMEN_OK;
}

/* The shapes view v may show (the index's answer, kept for limen_plan_things) and the mesh
 * triangles it draws of them, each mesh at the level of detail the view picks (as a
 * renderer does); -1 when out of memory. */
static int64_t view_things(limen_plan *p, limen_scene *s, limen__plan_view *v)
{
    int n = limen__plan_view_shapes(p, s, v);
    if (n < 0 || n > INT_MAX - p->nthing_slots ||  /* more than an int counts: no memory */
        !limen__reserve((void **)&p->thing_slots, &p->thing_slots_cap, p->nthing_slots + n,
                        sizeof *p->thing_slots))
        return -1;
    v->first_thing = p->nthing_slots;
    v->nthings = n;
    if (n)      /* both arrays are NULL before any shape */
        memcpy(p->thing_slots + p->nthing_slots, p->shape_hits, sizeof *p->shape_hits * (size_t)n);
    p->nthing_slots += n;
    if (!s->nmeshes)
        return 0;
    fill_public(v, s, p);       /* the matrices the level is chosen with */
    int64_t tris = 0;
    for (int k = 0; k < n; k++) {
        const limen__node *node = &s->nodes[p->shape_hits[k]];
        if (node->kind != LIMEN_NODE_MESH || !node->mesh)
            continue;
        limen_drawable d;
        limen__drawable_read(s, p->shape_hits[k], &d);
        int lod = limen_view_mesh_lod(&v->pub, p->height, &d, p->limits.lod_pixels);
        tris += d.mesh->lods[lod].triangle_count;
    }
    return tris;
}

/* The view through surface sf, seen from view `parent`, with scissor rect: pushed as a new
 * view to be looked into later (breadth first); its index, or -1 when out of memory. */
static int make_child(limen_plan *p, limen_scene *s, int parent, const limen__plan_surface *sf,
                      const int rect[4])
{
    limen__plan_view *c = push_view(p);
    if (!c)
        return -1;
    const limen__plan_view *v = &p->found[parent];    /* push_view may move the array */
    const limen__node *n = &s->nodes[sf->node];
    c->made_by = p->nview_surfaces;
    c->parent = parent;
    c->surface = sf->node;
    c->exit = sf->exit;
    c->pub.depth = v->pub.depth + 1;
    c->pub.kind = n->kind == LIMEN_NODE_MIRROR ? LIMEN_VIEW_MIRROR : LIMEN_VIEW_PORTAL;
    c->pub.through = limen__node_handle(s, sf->node);
    limen__d_mul(v->view, sf->xinv, c->view);
    limen__d_point(sf->x, v->eye, c->eye);
    const limen__plan_surface *exit = sf;
    if (sf->exit != sf->node && p->surface_of[sf->exit] >= 0)
        exit = &p->surfaces[p->surface_of[sf->exit]];
    memcpy(c->clip, exit->plane, sizeof c->clip);
    memcpy(c->clip_err, exit->err, sizeof c->clip_err);
    c->pub.front_face_cw = v->pub.front_face_cw ^ (n->kind == LIMEN_NODE_MIRROR);
    memcpy(c->pub.scissor, rect, sizeof c->pub.scissor);
    for (int k = 0; k < 3; k++)
        c->pub.tint[k] = v->pub.tint[k] * (n->kind == LIMEN_NODE_MIRROR ? n->tint[k] : 1.0f);
    return p->nviews - 1;
}

/* Tests view vi against the surfaces the index finds in its region (or all of them): each
 * one it sees is listed with what the view draws for it, a child view where the limits
 * allow one. */
static limen_status look_into(limen_plan *p, limen_scene *s, int vi)
{
    int ncandidates = s->brute_force ? -1 : limen__plan_candidates(p, s, &p->found[vi]);
    int ntest = ncandidates >= 0 ? ncandidates : p->nsurfaces;
    for (int ci = 0; ci < ntest; ci++) {
        const limen__plan_surface *sf = &p->surfaces[ncandidates >= 0 ? p->candidates[ci] : ci];
        limen__plan_view *v = &p->found[vi];
        if (sf->node == v->exit)
            continue;
        const limen__node *n = &s->nodes[sf->node];
        int rect[4];
        p->surface_tests++;
        if (!surface_rect(p, v, sf, rect))
            continue;   /* clipped away, off screen or under a pixel */
        bool front = limen__d_plane_dist(sf->plane, v->eye) > 0;
        if (!front) {
            if (n->kind == LIMEN_NODE_MIRROR &&
                !push_view_surface(p, v, sf->node, -1, LIMEN__SURF_BACK, rect))
                return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
            continue;
        }
        int child = -1;
        unsigned over = 0;
        if (!sf->has_x) {
            /* unpaired portal: fill */
        } else if (v->pub.depth + 1 > limen__limits_depth(&p->limits, n->max_depth) ||
                   too_faint(p, v, n) ||
                   (p->nviews >= p->limits.max_views && (over = LIMEN_BUDGET_VIEWS))) {
            p->truncated++;
            p->budgets_hit |= over;
        } else if ((child = make_child(p, s, vi, sf, rect)) < 0) {
            return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
        }
        if (!push_view_surface(p, &p->found[vi], sf->node, child,
                               child >= 0 ? LIMEN__SURF_CHILD : LIMEN__SURF_FILL, rect))
            return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    }
    return LIMEN_OK;
}

/* Phase 5: the views in the order they are found, breadth first, so that the limits and
 * budgets are spent on shallow levels before deep ones: each view is kept or dropped (over
 * a budget), its shapes listed, and its surfaces tested, which appends its children. */
static limen_status expand_views(limen_plan *p, limen_scene *s)
{
    for (int vi = 0; vi < p->nviews; vi++) {
        limen__plan_view *v = &p->found[vi];
        v->first_surface = p->nview_surfaces;
        unsigned spent = vi ? budget_spent(p) : 0;     /* the root is always drawn */
        if (spent) {
            drop_view(p, v, spent);
            continue;
        }
        /* triangles: a view that would take the frame over is dropped like the others; the
         * root always stays (the renderer cuts its meshes at the budget) */
        int64_t tris = view_things(p, s, v);
        if (tris < 0)
            return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
        if (vi && tris > p->budget.triangles - p->triangles) {
            p->nthing_slots = v->first_thing;
            v->nthings = 0;
            drop_view(p, v, LIMEN_BUDGET_TRIANGLES);
            continue;
        }
        if (!vi && tris > p->budget.triangles) {
            p->truncated++;
            p->budgets_hit |= LIMEN_BUDGET_TRIANGLES;
        }
        p->triangles += tris;
        p->view_pixels += (int64_t)v->pub.scissor[2] * v->pub.scissor[3];
        limen_status st = look_into(p, s, vi);
        if (st)
            return st;
    }
    return LIMEN_OK;
}

/* Depth-first order from the breadth-first list, re-linking parents and children. */
static void depth_first(limen_plan *p, int bfs, int parent_pos, int *pos)
{
    int me = (*pos)++;
    limen__plan_view *v = &p->found[bfs];
    limen_view *out = &p->views[me];
    *out = v->pub;
    out->id = me;
    out->parent = parent_pos;
    out->first_child = -1;
    out->next_sibling = -1;
    p->bfs_to_dfs[bfs] = me;
    p->dfs_to_bfs[me] = bfs;
    int last = -1;
    for (int k = 0; k < v->nsurfaces; k++) {
        const limen__view_surface *vs = &p->view_surfaces[v->first_surface + k];
        if (vs->child < 0)
            continue;
        int child_pos = *pos;
        depth_first(p, vs->child, me, pos);
        if (last < 0)
            out->first_child = child_pos;
        else
            p->views[last].next_sibling = child_pos;
        last = child_pos;
    }
}

/* Phase 6: the public views in draw order (depth first: a parent before its children), each
 * with its float matrices; a view out of a float's range refuses the plan. */
static limen_status order_views(limen_plan *p, limen_scene *s)
{
    if (!limen__reserve((void **)&p->views, &p->views_cap, p->nviews, sizeof *p->views) ||
        !limen__reserve((void **)&p->bfs_to_dfs, &p->bfs_to_dfs_cap, p->nviews,
                        sizeof *p->bfs_to_dfs) ||
        !limen__reserve((void **)&p->dfs_to_bfs, &p->dfs_to_bfs_cap, p->nviews,
                        sizeof *p->dfs_to_bfs))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    for (int i = 0; i < p->nviews; i++) {
        fill_public(&p->found[i], s, p);
        if (!p->found[i].dropped && !view_finite(&p->found[i].pub)) {
            /* portals that scale the view, nested until a float overflows: a clear refusal,
             * never a tree (or a JSON plan) with infinities in it */
            const limen__node *n = &s->nodes[p->found[i].surface];
            return limen__fail(s, LIMEN_ERR_ARG,
                               "%s%s%s '%s': the view through it at depth %d is out of a "
                               "float's range (the portals on the way scale it past what a "
                               "float holds)", n->label, n->label[0] ? ": " : "",
                               n->kind == LIMEN_NODE_MIRROR ? "mirror" : "portal", n->name,
                               p->found[i].pub.depth);
        }
    }
    int pos = 0;
    depth_first(p, 0, -1, &pos);
    p->count = pos;     /* dropped views are not reached */
    return LIMEN_OK;
}

/* Phase 7: the surfaces of each view, in draw order and public form. */
static limen_status list_surfaces(limen_plan *p, limen_scene *s)
{
    if (!limen__reserve((void **)&p->public_surfaces, &p->public_surfaces_cap,
                        p->nview_surfaces, sizeof *p->public_surfaces) ||
        !limen__reserve((void **)&p->public_first, &p->public_first_cap, p->count + 1,
                        sizeof *p->public_first))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    int k = 0;
    for (int i = 0; i < p->count; i++) {
        const limen__plan_view *v = &p->found[p->dfs_to_bfs[i]];
        p->public_first[i] = k;
        for (int j = 0; j < v->nsurfaces; j++) {
            const limen__view_surface *vs = &p->view_surfaces[v->first_surface + j];
            limen_view_surface *o = &p->public_surfaces[k++];
            o->node = limen__node_handle(s, vs->node);
            o->state = vs->state == LIMEN__SURF_CHILD  ? LIMEN_SURFACE_RECURSE
                       : vs->state == LIMEN__SURF_FILL ? LIMEN_SURFACE_FILL
                                                       : LIMEN_SURFACE_BACK;
            o->child = limen__plan_child_view(p, vs->child);
            memcpy(o->rect, vs->rect, sizeof o->rect);
        }
    }
    p->public_first[p->count] = k;
    return LIMEN_OK;
}

/* Phase 8: the shapes of each view (found in phase 5, as the triangle budget counted them),
 * in draw order and as handles: one array for the whole plan. */
static limen_status list_things(limen_plan *p, limen_scene *s)
{
    if (!limen__reserve((void **)&p->things, &p->things_cap, p->nthing_slots,
                        sizeof *p->things) ||
        !limen__reserve((void **)&p->things_first, &p->things_first_cap, p->count + 1,
                        sizeof *p->things_first))
        return limen__fail(s, LIMEN_ERR_NOMEM, "plan: out of memory");
    int k = 0;
    for (int i = 0; i < p->count; i++) {
        const limen__plan_view *v = &p->found[p->dfs_to_bfs[i]];
        p->things_first[i] = k;
        for (int j = 0; j < v->nthings; j++)
            p->things[k++] = limen__node_handle(s, p->thing_slots[v->first_thing + j]);
    }
    p->things_first[p->count] = k;
    return LIMEN_OK;
}

limen_status limen_plan_build(limen_plan *p, limen_scene *s, const limen_plan_desc *desc)
{
    if (!p || !s)
        return LIMEN_ERR_ARG;
    limen_status st;
    if ((st = check_inputs(p, s, desc)) ||      /* 1 */
        (st = collect_surfaces(p, s)) ||        /* 2: the mirrors and portals */
        (st = collect_clones(p, s)) ||          /* 3: the shapes passing through portals */
        (st = root_view(p, s)) ||               /* 4 */
        (st = expand_views(p, s)) ||            /* 5: breadth first */
        (st = order_views(p, s)) ||             /* 6: depth first */
        (st = list_surfaces(p, s)) ||           /* 7 */
        (st = list_things(p, s)))               /* 8 */
        return st;
    return LIMEN_OK;
}

int limen_plan_clones(const limen_plan *p, const limen_clone **out)
{
    if (out)
        *out = p ? p->clones : NULL;
    return p ? p->nclones : 0;
}

int limen_plan_view_surfaces(const limen_plan *p, int i, const limen_view_surface **out)
{
    if (!p || !out || i < 0 || i >= p->count) {
        if (out)
            *out = NULL;
        return 0;
    }
    int n = p->public_first[i + 1] - p->public_first[i];
    *out = n ? p->public_surfaces + p->public_first[i] : NULL;  /* NULL in a plan of none */
    return n;
}

int limen_plan_things(const limen_plan *p, int i, const limen_node **out)
{
    if (!p || !out || i < 0 || i >= p->count) {
        if (out)
            *out = NULL;
        return 0;
    }
    int n = p->things_first[i + 1] - p->things_first[i];
    *out = n ? p->things + p->things_first[i] : NULL;
    return n;
}

int limen_plan_view_things(const limen_plan *p, limen_scene *s, int i, limen_node *out, int max)
{
    if (!p || i < 0 || i >= p->count || max < 0 || (max > 0 && !out)) {
        if (s)
            limen__fail(s, LIMEN_ERR_ARG, "plan_view_things: no view %d, or no buffer", i);
        return -1;
    }
    const limen_node *things;
    int n = limen_plan_things(p, i, &things);
    if (n && max)
        memcpy(out, things, sizeof *things * (size_t)(n < max ? n : max));
    return n;
}

/* ------------------------------------------------------------------ JSON */

static void json_floats(FILE *f, const float *v, int n)
{
    fputc('[', f);
    for (int i = 0; i < n; i++)
        fprintf(f, "%s%.9g", i ? ", " : "", (double)v[i]);
    fputc(']', f);
}

static void json_string(FILE *f, const char *str)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)str; *c; c++) {
        if (*c == '"' || *c == '\\')
            fprintf(f, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(f, "\\u%04x", *c);
        else
            fputc(*c, f);
    }
    fputc('"', f);
}

/* A node by its name, or where it was made ("scenes/x.lua:7") when it has none; null for
 * no node. */
static void json_node(FILE *f, const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    if (!node)
        fprintf(f, "null");
    else
        json_string(f, node->name[0] || !node->label[0] ? node->name : node->label);
}

/* The surfaces view i sees, in the order it draws them (limen_plan_view_surfaces). */
static void json_view_surfaces(FILE *f, const limen_plan *p, const limen_scene *s, int i)
{
    static const char *states[] = { "recurse", "fill", "back" };
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(p, i, &vs);
    fprintf(f, ", \"surfaces\": [");
    for (int k = 0; k < n; k++) {
        fprintf(f, "%s{\"node\": ", k ? ", " : "");
        json_node(f, s, vs[k].node);
        fprintf(f, ", \"state\": \"%s\", \"child\": ", states[vs[k].state]);
        if (vs[k].child < 0)
            fprintf(f, "null");
        else
            fprintf(f, "%d", vs[k].child);
        fprintf(f, ", \"rect\": [%d, %d, %d, %d]}", vs[k].rect[0], vs[k].rect[1], vs[k].rect[2],
                vs[k].rect[3]);
    }
    fputc(']', f);
}

/* A mesh's parts at level lod (each a range of that level's triangles in one material) and
 * its materials as they are shaded: what a renderer of the plan needs besides the geometry. */
static void json_mesh_parts(FILE *f, const limen_mesh_geometry *g, int lod)
{
    static const char *const alpha[LIMEN_ALPHA_COUNT] = { "opaque", "mask", "blend" };
    const limen_mesh_part *parts = g->lods[lod].parts ? g->lods[lod].parts : g->parts;
    fprintf(f, ", \"parts\": [");
    for (int k = 0; parts && k < g->part_count; k++)
        fprintf(f, "%s{\"first\": %d, \"count\": %d, \"material\": %d}", k ? ", " : "",
                parts[k].first_triangle, parts[k].triangle_count, parts[k].material);
    fprintf(f, "], \"materials\": [");
    for (int k = 0; g->materials && k < g->material_count; k++) {
        const limen_material *m = &g->materials[k];
        fprintf(f, "%s{\"name\": ", k ? ", " : "");
        json_string(f, m->name ? m->name : "");
        fprintf(f, ", \"base_color\": [%.9g, %.9g, %.9g, %.9g], \"base_texture\": %s, "
                   "\"alpha_mode\": \"%s\", \"alpha_cutoff\": %.9g, "
                   "\"emissive\": [%.9g, %.9g, %.9g], \"emissive_texture\": %s}",
                m->base_color[0], m->base_color[1], m->base_color[2], m->base_color[3],
                m->base_texture ? "true" : "false",
                (unsigned)m->alpha_mode < LIMEN_ALPHA_COUNT ? alpha[m->alpha_mode] : "opaque",
                m->alpha_cutoff, m->emissive[0], m->emissive[1], m->emissive[2],
                m->emissive_texture ? "true" : "false");
    }
    fputc(']', f);
}

/* The meshes view i may show (limen_plan_things) and the level of detail each is drawn at
 * there (limen_view_mesh_lod under the plan's limits and height). */
static void json_view_meshes(FILE *f, const limen_plan *p, const limen_scene *s, int i)
{
    const limen_node *things;
    int n = limen_plan_things(p, i, &things);
    fprintf(f, ", \"meshes\": [");
    int listed = 0;
    for (int k = 0; k < n; k++) {
        const limen__node *node = limen__node_get(s, things[k]);
        if (!node || node->kind != LIMEN_NODE_MESH || !node->mesh)
            continue;
        /* the drawable a renderer picks the level from */
        limen_drawable d;
        limen__drawable_read(s, limen__index(s, node), &d);
        int lod = limen_view_mesh_lod(&p->views[i], p->height, &d, p->limits.lod_pixels);
        fprintf(f, "%s{\"node\": ", listed++ ? ", " : "");
        json_node(f, s, things[k]);
        /* a baked level's parts and material are its own (unless a node's texture is drawn) */
        const limen_mesh_geometry *baked = d.texture ? NULL : d.mesh->lods[lod].baked;
        fprintf(f, ", \"lod\": %d, \"triangles\": %d%s", lod, d.mesh->lods[lod].triangle_count,
                baked ? ", \"baked\": true" : "");
        json_mesh_parts(f, baked ? baked : d.mesh, baked ? 0 : lod);
        fputc('}', f);
    }
    fputc(']', f);
}

/* Shapes passing through portals (limen_plan_clones). */
static void json_clones(FILE *f, const limen_plan *p, const limen_scene *s)
{
    const limen_clone *c;
    int n = limen_plan_clones(p, &c);
    fprintf(f, "\"clones\": [");
    for (int k = 0; k < n; k++) {
        fprintf(f, "%s\n  {\"node\": ", k ? "," : "");
        json_node(f, s, c[k].node);
        fprintf(f, ", \"portal\": ");
        json_node(f, s, c[k].portal);
        fprintf(f, ", \"matrix\": ");
        json_floats(f, c[k].matrix, 16);
        fprintf(f, ", \"keep\": ");
        json_floats(f, c[k].keep, 4);
        fprintf(f, ", \"copy_keep\": ");
        json_floats(f, c[k].copy_keep, 4);
        fputc('}', f);
    }
    fprintf(f, "%s]", n ? "\n" : "");
}

limen_status limen_plan_write_json(const limen_plan *p, const limen_scene *s, const char *path)
{
    if (!p || !s || !path)
        return LIMEN_ERR_ARG;
    for (int i = 0; i < p->count; i++)
        if (!view_finite(&p->views[i]))
            return LIMEN_ERR_ARG;   /* JSON has no inf or nan (plan_build refuses them too) */
    limen__out out;
    limen_status st = limen__out_open(&out, path);
    if (st)
        return st;
    FILE *f = out.f;
    static const char *kinds[] = { "camera", "mirror", "portal" };
    static const char *clips[] = { "oblique", "plane", "none" };
    fprintf(f, "{\"width\": %d, \"height\": %d, \"truncated\": %d, \"view_pixels\": %lld, "
               "\"surface_tests\": %lld, \"budgets_hit\": %u, \"views\": [", p->width, p->height,
            p->truncated, (long long)p->view_pixels, (long long)p->surface_tests, p->budgets_hit);
    for (int i = 0; i < p->count; i++) {
        const limen_view *v = &p->views[i];
        fprintf(f, "%s\n  {\"id\": %d, \"parent\": ", i ? "," : "", v->id);
        if (v->parent < 0)
            fprintf(f, "null");
        else
            fprintf(f, "%d", v->parent);
        fprintf(f, ", \"depth\": %d, \"through\": ", v->depth);
        const char *name = v->depth ? limen_node_get_name(s, v->through) : NULL;
        if (name)
            json_string(f, name);
        else
            fprintf(f, "null");
        fprintf(f, ", \"kind\": \"%s\", \"view\": ", kinds[v->kind]);
        json_floats(f, v->view, 16);
        fprintf(f, ", \"proj\": ");
        json_floats(f, v->proj, 16);
        fprintf(f, ", \"clip_plane\": ");
        if (v->depth)
            json_floats(f, v->clip_plane, 4);
        else
            fprintf(f, "null");
        fprintf(f, ", \"clip\": \"%s\", \"front_face\": \"%s\", \"scissor\": [%d, %d, %d, %d]",
                clips[v->clip], v->front_face_cw ? "cw" : "ccw", v->scissor[0], v->scissor[1],
                v->scissor[2], v->scissor[3]);
        fprintf(f, ", \"stencil\": %d, \"eye\": ", v->stencil);
        json_floats(f, v->eye, 3);
        fprintf(f, ", \"tint\": ");
        json_floats(f, v->tint, 3);
        json_view_surfaces(f, p, s, i);
        json_view_meshes(f, p, s, i);
        fputc('}', f);
    }
    fprintf(f, "\n], ");
    json_clones(f, p, s);
    fprintf(f, "}\n");
    return limen__out_close(&out);
}
