/* stencil.c - the stencil method of nesting views: every view draws into the frame itself,
 * on the pixels the stencil buffer gives it (views.c draws what a view holds). */
#include "gl/gl_internal.h"

enum { MODE_FLAT = LIMEN__MODE_FLAT };

/* The far-plane fill limited to a nested view's region: the parts of the surface it is
 * seen through, as the parent view drew them (stencil decides the rest). */
static void draw_region_fill(limen_renderer *r, const rview *v, const limen__spoly *reg,
                             const float rgb[3])
{
    limen__flat_parts(r, v, reg, rgb, true, r->range == LIMEN_DEPTH_ZO_REVERSED ? 0.0f : 1.0f);
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
} stencil_ids;

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

/* Pixels of view `index` hold stencil == sv when this is called, reg the parts of the surface
 * the view is seen through (NULL for the root view).
 *
 * Each pixel is shaded once, without a depth-only pass over the scene: the surfaces the view
 * recurses into are laid into depth first (flat polygons, cheap), so that the view's things
 * are shaded only where nothing nearer, surface or thing, covers them; then each surface is
 * marked where its depth survived (its visible pixels) and its view drawn there. */
static void stencil_view(limen_renderer *r, int index, const limen__spoly *reg, int sv,
                         stencil_ids *ids)
{
    mat4 id;
    glm_mat4_identity(id);
    rview v;
    limen__rview_make(r, index, id, &v);
    limen__rview_cull(r, &v, v.pub->scissor);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(r->plan, index, &vs);
    set_scissor(r, v.pub->scissor);
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
    const limen_drawable *node;
    for (int k = 0; k < n; k++) {
        if (!(node = limen__recursed(r, &vs[k])))
            continue;
        limen__surface_parts(r, &v, node, &sp);
        limen__surface_flat(r, &v, node, MODE_FLAT, r->background, &sp);
    }

    /* shade this view's things where they are nearest */
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    limen__samples_begin(r);
    limen__draw_opaque(r, &v, vs, n);
    limen__samples_end(r);

    if (ids->unique) {
        const int first = ids->next;
        for (int k = 0; k < n; k++) {
            if (!(node = limen__recursed(r, &vs[k])))
                continue;
            limen__surface_parts(r, &v, node, &sp);
            mark_surface(r, &v, node, &sp, sv, ids->next++);
        }
        if (reg && !paint)
            view_background(r, &v, reg, sv);
        int cv = first;
        for (int k = 0; k < n; k++) {
            if (!(node = limen__recursed(r, &vs[k])))
                continue;
            limen__surface_parts(r, &v, node, &sp);
            stencil_view(r, vs[k].child, &sp, cv++, ids);
        }
        GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        return;
    }

    for (int k = 0; k < n; k++) {
        if (!(node = limen__recursed(r, &vs[k])))
            continue;
        limen__surface_parts(r, &v, node, &sp);
        mark_surface(r, &v, node, &sp, sv, sv + 1);
        stencil_view(r, vs[k].child, &sp, sv + 1, ids);

        /* seal: back to this view's value, with the surface's depth over the child's */
        set_scissor(r, v.pub->scissor);
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
}

limen_status limen__draw_stencil(limen_renderer *r)
{
    limen__lights_set(r);
    stencil_ids ids = { .unique = limen_plan_count(r->plan) <= 255, .next = 1 };
    stencil_view(r, 0, NULL, 0, &ids);
    GL(Disable)(GL_STENCIL_TEST);
    GL(Disable)(GL_SCISSOR_TEST);
    GL(FrontFace)(GL_CCW);
    return LIMEN_OK;
}
