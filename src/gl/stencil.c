/* stencil.c - the stencil method of nesting views: every view draws into the frame itself,
 * on the pixels the stencil buffer gives it (views.c draws what a view holds). */
#include <math.h>
#include <string.h>

#include "gl/gl_internal.h"

enum { MODE_FLAT = LIMEN__MODE_FLAT, AREA_CAP = 32 };

/* ------------------------------------------------------------------ where a view can draw */

/* The pixels a nested view can draw lie inside its surface's polygon, as its parent drew
 * it, and inside every ancestor's: the polygons nest on the one image. Their intersection,
 * kept on the processor as a convex polygon in image pixels (x, y, 0, 1, for the clipper),
 * tells what cannot touch the view's pixels and need not be drawn: the things outside it
 * and the surfaces outside it with all that lies behind them. The planner knows only the
 * view's rectangle, which is often twice the polygon (a reflection seen at a slant is a
 * sliver across it). The stencil test alone decides which pixels are drawn, so leaving out
 * a draw that could not pass it changes no pixel; the edges are pushed out by AREA_MARGIN
 * pixels, far more than rasterization rounds. */
#define AREA_MARGIN 2.0
typedef struct area {
    int n;
    double p[AREA_CAP][4];
} area;

static void area_of_rect(const int rect[4], area *a)
{
    double x0 = rect[0], y0 = rect[1], x1 = rect[0] + rect[2], y1 = rect[1] + rect[3];
    const double c[4][2] = { { x0, y0 }, { x1, y0 }, { x1, y1 }, { x0, y1 } };
    a->n = 4;
    for (int i = 0; i < 4; i++) {
        a->p[i][0] = c[i][0], a->p[i][1] = c[i][1];
        a->p[i][2] = 0, a->p[i][3] = 1;
    }
}

/* Edge i of a (turning either way) as a line inside >= 0, pushed out by AREA_MARGIN. */
static bool area_edge(const area *a, int i, double line[3])
{
    double turn = 0;
    for (int k = 0; k < a->n; k++) {
        const double *p = a->p[k], *q = a->p[(k + 1) % a->n];
        turn += p[0] * q[1] - q[0] * p[1];
    }
    const double *p = a->p[i], *q = a->p[(i + 1) % a->n];
    double ex = q[0] - p[0], ey = q[1] - p[1], len = sqrt(ex * ex + ey * ey);
    if (!(len > 0) || turn == 0)
        return false;
    double s = turn > 0 ? 1 : -1;
    line[0] = -s * ey, line[1] = s * ex;
    line[2] = s * (ey * p[0] - ex * p[1]) + AREA_MARGIN * len;
    return true;
}

/* The area of the view seen through the surface of sp: its polygon within the parent's
 * area. False where nothing is left. */
static bool area_within(const limen_renderer *r, const limen__spoly *sp, const area *parent,
                        area *out)
{
    if (sp->nxy < 3)
        return false;
    out->n = sp->nxy;
    for (int i = 0; i < sp->nxy; i++) {
        out->p[i][0] = (sp->xy[i][0] + 1) * 0.5 * r->width;
        out->p[i][1] = (sp->xy[i][1] + 1) * 0.5 * r->height;
        out->p[i][2] = 0, out->p[i][3] = 1;
    }
    double tmp[AREA_CAP][4];
    for (int e = 0; e < parent->n && out->n + 1 < AREA_CAP; e++) {
        double line[3];
        if (!area_edge(parent, e, line))
            continue;
        const double plane[4] = { line[0], line[1], 0, line[2] };
        out->n = limen_clip_polygon(&out->p[0][0], out->n, plane, &tmp[0][0], AREA_CAP);
        if (out->n < 3)
            return false;
        memcpy(out->p, tmp, sizeof(double) * 4 * (size_t)out->n);
    }
    return true;
}

/* Adds the planes through the eye and the area's edges to v's cull planes, as many as fit. */
static void cull_to_area(const limen_renderer *r, rview *v, const area *a)
{
    const int cap = (int)(sizeof v->cull / sizeof v->cull[0]);
    double W = r->width, H = r->height;
    for (int e = 0; e < a->n && v->ncull < cap; e++) {
        double line[3];
        if (!area_edge(a, e, line))
            continue;
        /* pixel x = (x_clip / w + 1) W / 2: the line times w, in clip coordinates */
        double cx = line[0] * W / 2, cy = line[1] * H / 2, cw = cx + cy + line[2];
        double pl[4];
        for (int c = 0; c < 4; c++)
            pl[c] = cx * v->view_proj[c][0] + cy * v->view_proj[c][1] + cw * v->view_proj[c][3];
        double len = sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
        if (!(len > 0))
            continue;
        for (int c = 0; c < 4; c++)
            v->cull[v->ncull][c] = (float)(pl[c] / len);
        v->ncull++;
    }
}

/* The far-plane fill limited to a nested view's region: the parts of the surface it is
 * seen through, as the parent view drew them (stencil decides the rest). */
static void draw_region_fill(limen_renderer *r, const rview *v, const limen__spoly *reg,
                             const float rgb[3])
{
    limen__flat_parts(r, v, reg, rgb, true, r->range == LIMEN_DEPTH_ZO_REVERSED ? 0.0f : 1.0f);
}

/* The pixels of rect that the area can touch: rect narrowed to the area's bounding box,
 * one pixel wider on every side (the surface's own edges carry no margin). */
static void area_rect(const area *a, const int rect[4], int out[4])
{
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < a->n; i++) {
        x0 = fmin(x0, a->p[i][0]), x1 = fmax(x1, a->p[i][0]);
        y0 = fmin(y0, a->p[i][1]), y1 = fmax(y1, a->p[i][1]);
    }
    int lo[2] = { rect[0], rect[1] }, hi[2] = { rect[0] + rect[2], rect[1] + rect[3] };
    if (a->n >= 3) {
        lo[0] = (int)fmax(lo[0], floor(x0) - 1), hi[0] = (int)fmin(hi[0], ceil(x1) + 1);
        lo[1] = (int)fmax(lo[1], floor(y0) - 1), hi[1] = (int)fmin(hi[1], ceil(y1) + 1);
    }
    out[0] = lo[0], out[1] = lo[1];
    out[2] = hi[0] > lo[0] ? hi[0] - lo[0] : 0;
    out[3] = hi[1] > lo[1] ? hi[1] - lo[1] : 0;
}

static void set_scissor(limen_renderer *r, const int rect[4])
{
    GL(Enable)(GL_SCISSOR_TEST);
    GL(Scissor)(r->origin[0] + rect[0], r->origin[1] + rect[1], rect[2], rect[3]);
}

/* How the stencil method tells views apart. Where the tree has at most 255 views each gets
 * a value of its own (its parent's pixels are switched to it by inverting the bits in which
 * the two differ). Then a view finishes its own passes, marks included, before any child
 * draws, and nothing tests a finished view's pixels again: a child may reset depth with a
 * clear of its whole rectangle, and no pass has to seal it. Larger trees count nesting depth
 * instead (the plan's `stencil`): each child is marked, drawn and sealed in turn (its pixels
 * back to its parent's value, with the surface's depth), and resets depth inside the
 * surface's polygon only. */
typedef struct stencil_ids {
    bool unique;
    int next;                   /* the next unused value */
    int marked;                 /* views marked so far */
} stencil_ids;

/* llvmpipe bins draws and rasterizes them when flushed. A whole frame of views in one batch
 * grew its binning memory by megabytes that went back to the system when it was done and
 * faulted in again the next frame (the kaleidoscope at depth 8, rendered alone in a
 * process: 110 ms instead of 32), while a flush after every view made the rasterizer threads
 * start and stop so often that interleaved with other renderers the frame took 1.5 times as
 * long. A batch of about FLUSH_VIEWS views did best at both (measured 4 to 32). */
enum { FLUSH_VIEWS = 8 };

static void flush_now_and_then(limen_renderer *r, stencil_ids *ids)
{
    if (++ids->marked % FLUSH_VIEWS == 0)
        GL(Flush)();
}

/* Marks the visible pixels of the surface of sp (its depth still there) with value cv. */
static void mark_surface(limen_renderer *r, const rview *v, const limen_drawable *node,
                         const limen__spoly *sp, int sv, int cv)
{
    GL(Enable)(GL_STENCIL_TEST);
    GL(ColorMask)(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    GL(DepthMask)(GL_FALSE);
    GL(DepthFunc)(limen__depth_lequal(r));
    GL(StencilFunc)(GL_EQUAL, sv, 0xFF);
    GL(StencilMask)((GLuint)(sv ^ cv));
    GL(StencilOp)(GL_KEEP, GL_KEEP, GL_INVERT);
    limen__surface_flat(r, v, node, MODE_FLAT, node->fill, sp);
    GL(StencilMask)(0xFF);
    GL(StencilOp)(GL_KEEP, GL_KEEP, GL_KEEP);
    GL(DepthMask)(GL_TRUE);
    GL(DepthFunc)(limen__depth_less(r));
}

/* The background of a nested view where nothing landed (depth still at the far plane). */
static void view_background(limen_renderer *r, const rview *v, const limen__spoly *reg, int sv)
{
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    GL(StencilFunc)(GL_EQUAL, sv, 0xFF);
    GL(DepthFunc)(GL_EQUAL);
    limen__samples_begin(r);
    draw_region_fill(r, v, reg, r->background);
    limen__samples_end(r);
    GL(DepthFunc)(limen__depth_less(r));
}

/* The drawable of the k-th surface view v sees when it recurses into it and the surface
 * can touch the view's pixels (ar: the view's area), with its parts in sp and the area of
 * the view through it in child; NULL otherwise. */
static const limen_drawable *live_child(limen_renderer *r, const rview *v,
                                        const limen_view_surface *vs, const area *ar,
                                        limen__spoly *sp, area *child)
{
    const limen_drawable *node = limen__recursed(r, vs);
    if (!node)
        return NULL;
    limen__surface_parts(r, v, node, sp);
    return area_within(r, sp, ar, child) ? node : NULL;
}

/* Pixels of view `index` hold stencil == sv when this is called, reg the parts of the surface
 * the view is seen through (NULL for the root view).
 *
 * Each pixel is shaded once, without a depth-only pass over the scene: the surfaces the view
 * recurses into are laid into depth first (flat polygons, cheap), so that the view's things
 * are shaded only where nothing nearer, surface or thing, covers them; then each surface is
 * marked where its depth survived (its visible pixels) and its view drawn there. */
static void stencil_view(limen_renderer *r, int index, const limen__spoly *reg, const area *ar,
                         int sv, stencil_ids *ids)
{
    mat4 id;
    glm_mat4_identity(id);
    rview v;
    limen__rview_make(r, index, id, &v);
    /* the pixels it may draw: its rectangle, narrowed to its area */
    int rect[4];
    area_rect(ar, v.pub->scissor, rect);
    limen__rview_cull(r, &v, rect);
    if (reg)
        cull_to_area(r, &v, ar);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(r->plan, index, &vs);
    set_scissor(r, rect);
    /* the camera's view draws before any mark, where every pixel holds 0: its passes need
     * no stencil test (the first mark turns it on) */
    if (reg)
        GL(Enable)(GL_STENCIL_TEST);
    else
        GL(Disable)(GL_STENCIL_TEST);
    GL(StencilFunc)(GL_EQUAL, sv, 0xFF);
    GL(StencilOp)(GL_KEEP, GL_KEEP, GL_KEEP);

    /* depth: reset inside the view, then the surfaces it recurses into. With a value per
     * view (and one sample per pixel) the reset also paints the view's background (its
     * things land on it later), so that no pass after the marks has to find the pixels where
     * nothing landed. With MSAA the scissored clear and that later pass stay: the region's
     * polygon alone was seen to change a few edge pixels there. */
    bool paint = ids->unique && !r->msaa;
    GL(ColorMask)(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    if (reg && ids->unique && r->msaa) {
        GL(Clear)(GL_DEPTH_BUFFER_BIT);
    } else if (reg) {
        if (paint)
            GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        GL(DepthFunc)(GL_ALWAYS);
        draw_region_fill(r, &v, reg, r->background);
        GL(DepthFunc)(limen__depth_less(r));
        GL(ColorMask)(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    }
    limen__rview_apply(r, &v);
    /* (the parts are recomputed where needed: the same floats come out each time) */
    limen__spoly sp;
    area child;
    const limen_drawable *node;
    for (int k = 0; k < n; k++)
        if ((node = live_child(r, &v, &vs[k], ar, &sp, &child)))
            limen__surface_flat(r, &v, node, MODE_FLAT, r->background, &sp);

    /* shade this view's things where they are nearest */
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    limen__samples_begin(r);
    limen__draw_opaque(r, &v, vs, n);
    limen__samples_end(r);

    if (ids->unique) {
        const int first = ids->next;
        for (int k = 0; k < n; k++)
            if ((node = live_child(r, &v, &vs[k], ar, &sp, &child)))
                mark_surface(r, &v, node, &sp, sv, ids->next++);
        if (reg && !paint)
            view_background(r, &v, reg, sv);
        flush_now_and_then(r, ids);
        int cv = first;
        for (int k = 0; k < n; k++)
            if (live_child(r, &v, &vs[k], ar, &sp, &child))
                stencil_view(r, vs[k].child, &sp, &child, cv++, ids);
        GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        return;
    }

    for (int k = 0; k < n; k++) {
        if (!(node = live_child(r, &v, &vs[k], ar, &sp, &child)))
            continue;
        mark_surface(r, &v, node, &sp, sv, sv + 1);
        flush_now_and_then(r, ids);
        stencil_view(r, vs[k].child, &sp, &child, sv + 1, ids);

        /* seal: back to this view's value, with the surface's depth over the child's */
        set_scissor(r, rect);
        limen__rview_apply(r, &v);
        GL(ColorMask)(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        GL(StencilFunc)(GL_EQUAL, sv + 1, 0xFF);
        GL(StencilOp)(GL_KEEP, GL_KEEP, GL_DECR);
        GL(DepthFunc)(GL_ALWAYS);
        limen__surface_flat(r, &v, node, MODE_FLAT, node->fill, &sp);
        GL(DepthFunc)(limen__depth_less(r));
        GL(StencilFunc)(GL_EQUAL, sv, 0xFF);
        GL(StencilOp)(GL_KEEP, GL_KEEP, GL_KEEP);
    }
    if (reg)
        view_background(r, &v, reg, sv);
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    /* blended parts over the finished view (its surfaces sealed back to sv) */
    if (limen__scene_blends(r)) {
        set_scissor(r, rect);
        limen__rview_apply(r, &v);
        GL(Enable)(GL_STENCIL_TEST);
        GL(StencilFunc)(GL_EQUAL, sv, 0xFF);
        GL(StencilOp)(GL_KEEP, GL_KEEP, GL_KEEP);
        limen__draw_blended(r, &v);
    }
}

limen_status limen__draw_stencil(limen_renderer *r)
{
    limen__lights_set(r);
    /* blended parts are drawn over a view once its surfaces are sealed: depth counting */
    stencil_ids ids = { .unique = limen_plan_count(r->plan) <= 255 && !limen__scene_blends(r),
                        .next = 1 };
    area all;
    area_of_rect(limen_plan_view(r->plan, 0)->scissor, &all);
    stencil_view(r, 0, NULL, &all, 0, &ids);
    GL(Disable)(GL_STENCIL_TEST);
    GL(Disable)(GL_SCISSOR_TEST);
    GL(FrontFace)(GL_CCW);
    return LIMEN_OK;
}
