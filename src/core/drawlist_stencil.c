/* drawlist_stencil.c - the stencil method of nesting views as draw-list commands: every
 * view draws into the frame itself, on the pixels the stencil buffer gives it (drawlist.c
 * lists what a view holds). */
#include <math.h>
#include <string.h>

#include "core/drawlist.h"

enum { AREA_CAP = 32 };

/* ------------------------------------------------------------------ where a view can draw */

/* The pixels a nested view can draw lie inside its surface's polygon, as its parent drew
 * it, and inside every ancestor's: the polygons nest on the one image. Their intersection,
 * kept as a convex polygon in image pixels (x, y, 0, 1, for the clipper), tells what cannot
 * touch the view's pixels and need not be drawn: the things outside it and the surfaces
 * outside it with all that lies behind them. The planner knows only the view's rectangle,
 * which is often twice the polygon (a reflection seen at a slant is a sliver across it). The
 * stencil test alone decides which pixels are drawn, so leaving out a draw that could not
 * pass it changes no pixel; the edges are pushed out by AREA_MARGIN pixels, far more than
 * rasterization rounds. */
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
static bool area_within(const limen_drawlist *dl, const limen__spoly *sp, const area *parent,
                        area *out)
{
    if (sp->nxy < 3)
        return false;
    out->n = sp->nxy;
    for (int i = 0; i < sp->nxy; i++) {
        out->p[i][0] = (sp->xy[i][0] + 1) * 0.5 * dl->width;
        out->p[i][1] = (sp->xy[i][1] + 1) * 0.5 * dl->height;
        out->p[i][2] = 0, out->p[i][3] = 1;
    }
    double clipped[AREA_CAP][4];
    for (int e = 0; e < parent->n && out->n + 1 < AREA_CAP; e++) {
        double line[3];
        if (!area_edge(parent, e, line))
            continue;
        const double plane[4] = { line[0], line[1], 0, line[2] };
        out->n = limen_clip_polygon(&out->p[0][0], out->n, plane, &clipped[0][0], AREA_CAP);
        if (out->n < 3)
            return false;
        memcpy(out->p, clipped, sizeof(double) * 4 * (size_t)out->n);
    }
    return true;
}

/* Adds the planes through the eye and the area's edges to v's cull planes, as many as fit. */
static void cull_to_area(const limen_drawlist *dl, dl_view *v, const area *a)
{
    const int cap = (int)(sizeof v->cull / sizeof v->cull[0]);
    double W = dl->width, H = dl->height;
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

/* ------------------------------------------------------------------ stencil values */

/* How the stencil method tells views apart. Where the tree has at most 255 views and
 * nothing blends, each gets a value of its own (its parent's pixels are switched to it by
 * inverting the bits in which the two differ). Then a view finishes its own passes, marks
 * included, before any child draws, and nothing tests a finished view's pixels again: a
 * child may reset depth with a clear of its whole rectangle, and no pass has to seal it.
 * Larger trees, and frames with blended parts (drawn over a view once its surfaces are
 * sealed), count nesting depth instead (the plan's `stencil`): each child is marked, drawn
 * and sealed in turn (its pixels back to its parent's value, with the surface's depth), and
 * resets depth inside the surface's polygon only. */
typedef struct stencil_ids {
    bool unique;
    int next;                   /* the next unused value */
    int marked;                 /* views marked so far */
} stencil_ids;

/* A rasterizer that bins draws (llvmpipe) and rasterizes them when flushed grew its binning
 * memory by megabytes over a whole frame of views in one batch, which went back to the
 * system when done and faulted in again the next frame (the kaleidoscope at depth 8,
 * rendered alone in a process: 110 ms instead of 32), while a flush after every view made
 * the rasterizer threads start and stop so often that interleaved with other renderers the
 * frame took 1.5 times as long. A batch of about FLUSH_VIEWS views did best at both
 * (measured 4 to 32). */
enum { FLUSH_VIEWS = 8 };

static void flush_now_and_then(limen_drawlist *dl, stencil_ids *ids)
{
    if (++ids->marked % FLUSH_VIEWS == 0)
        limen__dl_emit(dl, LIMEN_DRAW_FLUSH);
}

/* Marks the visible pixels of the surface of sp (its depth still there) with child_value. */
static void mark_surface(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                         const limen__spoly *sp, int value, int child_value)
{
    limen_draw_state *st = &dl->st;
    st->stencil_test = 1;
    st->color_write = 0;
    st->depth_write = 0;
    st->depth_test = limen__dl_lequal(dl);
    st->stencil_ref = (unsigned char)value;
    st->stencil_write_mask = (unsigned char)(value ^ child_value);
    st->stencil_pass = LIMEN_STENCIL_INVERT;
    limen__dl_surface_flat(dl, v, sp, node->fill, false, 0);
    st->stencil_write_mask = 0xFF;
    st->stencil_pass = LIMEN_STENCIL_KEEP;
    st->depth_write = 1;
    st->depth_test = limen__dl_less(dl);
}

/* The far-plane fill limited to a nested view's region: the parts of the surface it is
 * seen through, as the parent view drew them (stencil decides the rest). */
static void region_fill(limen_drawlist *dl, const dl_view *v, const limen__spoly *reg)
{
    limen__dl_surface_flat(dl, v, reg, dl->background, true, limen__dl_far_z(dl));
}

/* The background of a nested view where nothing landed (depth still at the far plane). */
static void view_background(limen_drawlist *dl, const dl_view *v, const limen__spoly *reg,
                            int value)
{
    dl->st.color_write = 1;
    dl->st.stencil_ref = (unsigned char)value;
    dl->st.depth_test = LIMEN_COMPARE_EQUAL;
    dl->st.counted = 1;
    region_fill(dl, v, reg);
    dl->st.counted = 0;
    dl->st.depth_test = limen__dl_less(dl);
}

/* The drawable of the k-th surface view v sees when it recurses into it and the surface
 * can touch the view's pixels (ar: the view's area), with its parts in sp and the area of
 * the view through it in child; NULL otherwise. */
static const limen_drawable *live_child(limen_drawlist *dl, const dl_view *v,
                                        const limen_view_surface *vs, const area *ar,
                                        limen__spoly *sp, area *child)
{
    const limen_drawable *node = limen__dl_recursed(dl, vs);
    if (!node)
        return NULL;
    limen__dl_surface_parts(dl, v, node, sp);
    return area_within(dl, sp, ar, child) ? node : NULL;
}

/* Pixels of view `index` hold stencil == value when this is called, reg the parts of the
 * surface the view is seen through (NULL for the root view).
 *
 * Each pixel is shaded once, without a depth-only pass over the scene: the surfaces the view
 * recurses into are laid into depth first (flat polygons, cheap), so that the view's things
 * are shaded only where nothing nearer, surface or thing, covers them; then each surface is
 * marked where its depth survived (its visible pixels) and its view drawn there. */
static void stencil_view(limen_drawlist *dl, int index, const limen__spoly *reg, const area *ar,
                         int value, stencil_ids *ids)
{
    dl_view v;
    if (!limen__dl_view_make(dl, index, &v))
        return;
    limen_draw_state *st = &dl->st;
    /* the pixels it may draw: its rectangle, narrowed to its area */
    int rect[4];
    area_rect(ar, v.pub->scissor, rect);
    limen__dl_view_cull(dl, &v, rect);
    if (reg)
        cull_to_area(dl, &v, ar);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(dl->plan, index, &vs);
    memcpy(st->scissor, rect, sizeof rect);
    /* the camera's view draws before any mark, where every pixel holds 0: its passes need
     * no stencil test (the first mark turns it on) */
    st->stencil_test = reg != NULL;
    st->stencil_ref = (unsigned char)value;
    st->stencil_pass = LIMEN_STENCIL_KEEP;

    /* depth: reset inside the view, then the surfaces it recurses into. With a value per
     * view (and one sample per pixel) the reset also paints the view's background (its
     * things land on it later), so that no pass after the marks has to find the pixels where
     * nothing landed. With MSAA the scissored clear and that later pass stay: the region's
     * polygon alone was seen to change a few edge pixels there. */
    bool msaa = dl->desc.msaa > 1;
    bool paint = ids->unique && !msaa;
    st->color_write = 0;
    if (reg && ids->unique && msaa) {
        limen_draw_cmd *c = limen__dl_emit(dl, LIMEN_DRAW_CLEAR);
        if (c) {
            c->state.depth_write = 1;
            c->state.stencil_write_mask = 0;
        }
    } else if (reg) {
        if (paint)
            st->color_write = 1;
        st->depth_test = LIMEN_COMPARE_ALWAYS;
        region_fill(dl, &v, reg);
        st->depth_test = limen__dl_less(dl);
        st->color_write = 0;
    }
    limen__dl_view_apply(dl, &v);
    /* (the parts are recomputed where needed: the same floats come out each time) */
    limen__spoly sp;
    area child;
    const limen_drawable *node;
    for (int k = 0; k < n; k++)
        if ((node = live_child(dl, &v, &vs[k], ar, &sp, &child)))
            limen__dl_surface_flat(dl, &v, &sp, dl->background, false, 0);

    /* shade this view's things where they are nearest */
    st->color_write = 1;
    st->counted = 1;
    limen__dl_opaque(dl, &v, vs, n);
    st->counted = 0;

    if (ids->unique) {
        const int first = ids->next;
        for (int k = 0; k < n; k++)
            if ((node = live_child(dl, &v, &vs[k], ar, &sp, &child)))
                mark_surface(dl, &v, node, &sp, value, ids->next++);
        if (reg && !paint)
            view_background(dl, &v, reg, value);
        flush_now_and_then(dl, ids);
        int child_value = first;
        for (int k = 0; k < n; k++)
            if (live_child(dl, &v, &vs[k], ar, &sp, &child))
                stencil_view(dl, vs[k].child, &sp, &child, child_value++, ids);
        st->color_write = 1;
        return;
    }

    for (int k = 0; k < n; k++) {
        if (!(node = live_child(dl, &v, &vs[k], ar, &sp, &child)))
            continue;
        mark_surface(dl, &v, node, &sp, value, value + 1);
        flush_now_and_then(dl, ids);
        stencil_view(dl, vs[k].child, &sp, &child, value + 1, ids);

        /* seal: back to this view's value, with the surface's depth over the child's */
        memcpy(st->scissor, rect, sizeof rect);
        limen__dl_view_apply(dl, &v);
        st->color_write = 0;
        st->stencil_ref = (unsigned char)(value + 1);
        st->stencil_pass = LIMEN_STENCIL_DECR;
        st->depth_test = LIMEN_COMPARE_ALWAYS;
        limen__dl_surface_flat(dl, &v, &sp, node->fill, false, 0);
        st->depth_test = limen__dl_less(dl);
        st->stencil_ref = (unsigned char)value;
        st->stencil_pass = LIMEN_STENCIL_KEEP;
    }
    if (reg)
        view_background(dl, &v, reg, value);
    st->color_write = 1;
    /* blended parts over the finished view (its surfaces sealed back to value) */
    if (dl->blends) {
        memcpy(st->scissor, rect, sizeof rect);
        limen__dl_view_apply(dl, &v);
        st->stencil_test = 1;
        st->stencil_ref = (unsigned char)value;
        st->stencil_pass = LIMEN_STENCIL_KEEP;
        limen__dl_blended(dl, &v);
    }
}

void limen__dl_stencil(limen_drawlist *dl)
{
    stencil_ids ids = { .unique = limen_plan_count(dl->plan) <= 255 && !dl->blends, .next = 1 };
    area all;
    area_of_rect(limen_plan_view(dl->plan, 0)->scissor, &all);
    stencil_view(dl, 0, NULL, &all, 0, &ids);
}
