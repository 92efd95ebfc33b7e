/* drawlist_texture.c - the texture method of nesting views as draw-list commands: each
 * view draws into an offscreen target of its depth (or the frame, for the camera's), at
 * texture_scale, over the viewport of its rectangle, and its parent shows that target on
 * the surface's polygon (drawlist.c lists what a view holds). */
#include <math.h>
#include <string.h>

#include "core/drawlist.h"

/* Where a view's pixels land in its target: image pixel rect -> target viewport. */
typedef struct placement {
    int target;             /* 0: the frame; k: target k */
    int tw, th;             /* the target's size (0: the frame) */
    int ox, oy;             /* the viewport's corner in the target */
    int vw, vh;             /* viewport size in the target */
    float sx, sy;           /* target pixels per image pixel */
    int rect[4];            /* image rectangle the viewport covers */
} placement;

static void bind_placement(limen_drawlist *dl, const placement *pl)
{
    dl->st.scissor[0] = pl->ox, dl->st.scissor[1] = pl->oy;
    dl->st.scissor[2] = pl->vw, dl->st.scissor[3] = pl->vh;
    limen_draw_cmd *c = limen__dl_emit(dl, LIMEN_DRAW_TARGET);
    if (!c)
        return;
    c->target = pl->target;
    c->target_w = pl->tw, c->target_h = pl->th;
    c->viewport[0] = pl->ox, c->viewport[1] = pl->oy;
    c->viewport[2] = pl->vw, c->viewport[3] = pl->vh;
}

/* Renders view `index` into the placement. */
static void texture_view(limen_drawlist *dl, int index, const placement *pl)
{
    /* narrow the projection from the whole image to this view's rectangle */
    mat4 narrow;
    limen__dl_narrow_to(dl, pl->rect, narrow);
    dl_view v;
    if (!limen__dl_view_new(dl, index, narrow, &v))
        return;
    v.img_map[0] = 1.0f / pl->sx;
    v.img_map[1] = 1.0f / pl->sy;
    /* the image pixels of the target's first fragment */
    const float px0 = (float)pl->rect[0] - (float)pl->ox / pl->sx;
    const float py0 = (float)pl->rect[1] - (float)pl->oy / pl->sy;
    v.img_map[2] = px0;
    v.img_map[3] = py0;
    v.target = pl->target;
    limen__dl_view_pass(dl, &v);
    limen__dl_view_cull(dl, &v, NULL);

    bind_placement(dl, pl);
    const float *tint = v.pub->tint;
    limen_draw_cmd *clr = limen__dl_emit(dl, LIMEN_DRAW_CLEAR);
    if (clr) {
        clr->color[0] = dl->background[0] * tint[0];
        clr->color[1] = dl->background[1] * tint[1];
        clr->color[2] = dl->background[2] * tint[2];
        clr->state.color_write = clr->state.depth_write = 1;
        clr->state.stencil_write_mask = 0;
    }
    limen__dl_view_apply(dl, &v);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(dl->plan, index, &vs);
    const limen_drawable *node;
    /* the surfaces that show a child's image go into depth first, so that nothing behind
     * them is shaded; then the view's own things, nearest first */
    dl->st.color_write = 0;
    for (int k = 0; k < n; k++)
        if ((node = limen__dl_recursed(dl, &vs[k])))
            limen__dl_surface_fill(dl, &v, node, dl->background, NULL);
    dl->st.color_write = 1;
    dl->st.counted = 1;
    limen__dl_opaque(dl, &v, vs, n);
    dl->st.counted = 0;

    const float scale = dl->desc.texture_scale;
    for (int k = 0; k < n; k++) {
        if (!(node = limen__dl_recursed(dl, &vs[k])))
            continue;
        int ci = vs[k].child;
        const limen_view *c = limen_plan_view(dl->plan, ci);
        placement cp;
        cp.target = c->depth;
        cp.tw = (int)ceilf((float)dl->width * scale);
        cp.th = (int)ceilf((float)dl->height * scale);
        cp.ox = cp.oy = 0;
        cp.vw = (int)ceilf((float)c->scissor[2] * scale);
        cp.vh = (int)ceilf((float)c->scissor[3] * scale);
        cp.sx = (float)cp.vw / (float)c->scissor[2];
        cp.sy = (float)cp.vh / (float)c->scissor[3];
        memcpy(cp.rect, c->scissor, sizeof cp.rect);
        texture_view(dl, ci, &cp);

        /* back in this view: the surface samples the child's image where it appears on
         * screen (the child applied the tints already) */
        bind_placement(dl, pl);
        limen__dl_view_apply(dl, &v);
        /* fragment (this target) -> image pixel -> child texel -> uv */
        float map[4] = {
            cp.sx / (pl->sx * (float)cp.tw),
            cp.sy / (pl->sy * (float)cp.th),
            (px0 - (float)cp.rect[0]) * cp.sx / (float)cp.tw,
            (py0 - (float)cp.rect[1]) * cp.sy / (float)cp.th,
        };
        static const float white[3] = { 1, 1, 1 };
        dl->st.depth_test = limen__dl_lequal(dl);         /* its own depth is there already */
        dl->st.counted = 1;
        limen__dl_surface_image(dl, &v, node, white, LIMEN_IMAGE_TARGET, map, cp.target);
        dl->st.counted = 0;
        dl->st.depth_test = limen__dl_less(dl);
    }
    /* blended parts over the finished picture, the surfaces' images included */
    bind_placement(dl, pl);
    limen__dl_view_apply(dl, &v);
    limen__dl_blended(dl, &v);
}

void limen__dl_texture(limen_drawlist *dl)
{
    placement root = { 0, 0, 0, 0, 0, dl->width, dl->height, 1.0f, 1.0f,
                       { 0, 0, dl->width, dl->height } };
    texture_view(dl, 0, &root);
}
