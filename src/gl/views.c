/* views.c - drawing a planned view tree: the scene's geometry for one view, the surfaces
 * seen from it, and the texture method of nesting views (the stencil method: stencil.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gl_internal.h"

enum { MODE_LIT = LIMEN__MODE_LIT, MODE_FLAT = LIMEN__MODE_FLAT, MODE_TEXTURE = LIMEN__MODE_TEXTURE };

static bool is_surface(const limen_drawable *d)
{
    return d->kind == LIMEN_NODE_MIRROR || d->kind == LIMEN_NODE_PORTAL;
}

/* The drawable of a node the plan names (a surface, a clone); NULL if it has none. */
static const limen_drawable *item_of(const limen_renderer *r, limen_node n)
{
    const limen_drawable *items;
    limen_drawables_items(r->draw, &items);
    int i = limen_drawables_find(r->draw, n);
    return i >= 0 ? &items[i] : NULL;
}

/* The clip-space transform that stretches the pixel rectangle rect of the image over the
 * whole of [-1, 1]^2. */
static void narrow_to(const limen_renderer *r, const int rect[4], mat4 out)
{
    float W = (float)r->width, H = (float)r->height;
    float x0 = 2.0f * rect[0] / W - 1.0f, x1 = 2.0f * (rect[0] + rect[2]) / W - 1.0f;
    float y0 = 2.0f * rect[1] / H - 1.0f, y1 = 2.0f * (rect[1] + rect[3]) / H - 1.0f;
    glm_mat4_identity(out);
    out[0][0] = 2.0f / (x1 - x0);
    out[1][1] = 2.0f / (y1 - y0);
    out[3][0] = -(x1 + x0) / (x1 - x0);
    out[3][1] = -(y1 + y0) / (y1 - y0);
}

/* The planes of what view v can show: its projection's sides narrowed to the pixels it
 * may draw, its near plane (the oblique one where there is one) and its clip plane. A node
 * whose bounding sphere lies wholly outside one of them cannot touch a pixel. */
void limen__rview_cull(limen_renderer *r, rview *v, const int *rect)
{
    mat4 m, narrow;
    glm_mat4_identity(narrow);
    if (rect)
        narrow_to(r, rect, narrow);
    glm_mat4_mul(narrow, v->view_proj, m);
    /* Gribb-Hartmann: rows of m (m[col][row]) */
    v->ncull = 0;
    for (int i = 0; i < 5; i++) {
        vec4 pl;
        for (int c = 0; c < 4; c++) {
            float row = i < 4 ? m[c][i / 2] : m[c][2];
            float sign = (i & 1) ? -1.0f : 1.0f;
            if (i == 4 && r->range != LIMEN_DEPTH_NO) {
                /* zero-to-one depth: near is row 3 alone (reversed: row 4 - row 3) */
                pl[c] = r->range == LIMEN_DEPTH_ZO ? m[c][2] : m[c][3] - m[c][2];
                continue;
            }
            pl[c] = m[c][3] + sign * row;
        }
        float len = sqrtf(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
        if (!(len > 0))
            continue;
        glm_vec4_scale(pl, 1.0f / len, v->cull[v->ncull++]);
    }
    if (v->pub->clip == LIMEN_CLIP_PLANE)
        memcpy(v->cull[v->ncull++], v->pub->clip_plane, sizeof(float) * 4);
}

/* carry: an extra world transform (a clone's portal matrix), or NULL. */
static bool outside(const rview *v, const limen_drawable *n, const float *carry)
{
    double rad = n->radius;
    vec3 cf = { n->centre[0], n->centre[1], n->centre[2] };
    if (carry) {
        mat4 m;
        memcpy(m, carry, sizeof m);
        glm_mat4_mulv3(m, cf, 1.0f, cf);
        rad *= glm_vec3_norm(m[0]);
    }
    for (int i = 0; i < v->ncull; i++)
        if (glm_vec3_dot((float *)v->cull[i], cf) + v->cull[i][3] < -(float)rad)
            return true;
    return false;
}

/* Whether the view must cut what lies behind its exit surface: every nested view but those
 * of the CLIP_NONE baseline. */
static bool exit_cuts(const rview *v)
{
    return v->pub->depth > 0 && v->pub->clip != LIMEN_CLIP_NONE;
}

static void set_mat4(limen_renderer *r, GLint loc, mat4 m)
{
    GL(UniformMatrix4fv)(loc, 1, GL_FALSE, (const GLfloat *)m);
}

/* ------------------------------------------------------------------ per-view state */

/* proj_pre: the narrowing applied for the texture method (identity otherwise). */
void limen__rview_make(limen_renderer *r, int index, mat4 proj_pre, rview *v)
{
    const limen_view *pub = limen_plan_view(r->plan, index);
    v->pub = pub;
    v->index = index;
    memcpy(v->view, pub->view, sizeof v->view);
    memcpy(v->proj, pub->proj, sizeof v->proj);
    glm_mat4_mul(proj_pre, v->proj, v->proj);
    glm_mat4_mul(v->proj, v->view, v->view_proj);
    v->px_scale = pub->proj[5] * 0.5f * (float)r->height;
    v->img_map[0] = v->img_map[1] = 1.0f;
    v->img_map[2] = -(float)r->origin[0];
    v->img_map[3] = -(float)r->origin[1];
}

static const float keep_all[4] = { 0, 0, 0, 1 };

/* The view's clip plane where it has one (and clip distance 0 on), else none. */
static void set_view_clip(limen_renderer *r, const rview *v)
{
    bool plane = v->pub->clip == LIMEN_CLIP_PLANE;
    memcpy(r->shared.clip_plane, plane ? v->pub->clip_plane : keep_all, sizeof(float) * 4);
    r->clip0_on = plane;
    if (plane)
        GL(Enable)(GL_CLIP_DISTANCE0);
    else
        GL(Disable)(GL_CLIP_DISTANCE0);
    r->shared_stamp++;
}

void limen__rview_apply(limen_renderer *r, const rview *v)
{
    GL(BindVertexArray)(r->vao);
    memcpy(r->shared.view_proj, v->view_proj, sizeof r->shared.view_proj);
    memcpy(r->shared.eye, v->pub->eye, sizeof r->shared.eye);
    set_view_clip(r, v);
    GL(FrontFace)(v->pub->front_face_cw ? GL_CW : GL_CCW);
    r->shared.ambient = r->ambient;
    /* the product of the mirror tints on the way here, applied once to every colour */
    memcpy(r->shared.tint, v->pub->tint, sizeof r->shared.tint);
}

void limen__lights_set(limen_renderer *r)
{
    float (*pos)[3] = r->shared.light_pos, (*col)[3] = r->shared.light_col;
    float *inv_r2 = r->shared.light_inv_r2;
    bool ranged = false;
    const limen_drawable *items;
    int count = limen_drawables_items(r->draw, &items), n = 0;
    for (int i = 0; i < count && n < LIMEN_MAX_LIGHTS; i++) {
        const limen_drawable *d = &items[i];
        if (d->kind != LIMEN_NODE_LIGHT || !d->visible)
            continue;
        memcpy(pos[n], d->world + 12, sizeof(float) * 3);
        memcpy(col[n], d->color, sizeof(float) * 3);
        /* 1/R^2: the shader's falloff takes (d/R)^2 as d^2 times it; 0 weighs 1 */
        inv_r2[n] = d->range > 0 ? 1.0f / (d->range * d->range) : 0.0f;
        ranged |= d->range > 0;
        n++;
    }
    r->shared.nlights = n;
    r->shared.ranged = ranged;
    r->shared_stamp++;
}

/* ------------------------------------------------------------------ meshes */

/* Draws one node's mesh; `mode` lit, flat or textured with colour `albedo`. */
static void draw_node_at(limen_renderer *r, const rview *v, const limen_drawable *node,
                         mat4 world, int mode, const float *albedo)
{
    limen__range range = { 0, 0 };
    vec3 scale = { 1, 1, 1 };
    int shape = 0;
    if (node->kind == LIMEN_NODE_MESH) {
        limen__mesh_draw(r, v->pub, node, (const float *)world, albedo);
        return;
    }
    if (!limen__unit_mesh(r, v->view, v->px_scale, node, world, &range, scale, &shape))
        return;
    int checker = mode != MODE_LIT || !(node->cell > 0) ? 0
                  : node->kind == LIMEN_NODE_QUAD                ? 1
                                                                 : 2;
    /* an albedo texture, bound on unit 1, its coordinates as limen.h says */
    int textured = LIMEN__UV_NONE;
    if (node->texture && mode == MODE_LIT && limen__gpu_texture(r, node->texture, node->texture_filter))
        textured = node->kind == LIMEN_NODE_QUAD ? LIMEN__UV_PLANE : LIMEN__UV_BOX;
    /* In an oblique view the near plane is the exit plane, and clamping (below) would keep
     * what of a surface lies beyond it (a neighbour poking through a mirror shows its back
     * there): the view's clip plane cuts it instead, as in a plane view, through a variant
     * that writes the clip distance. */
    bool cut = is_surface(node) && exit_cuts(v) && v->pub->clip == LIMEN_CLIP_OBLIQUE;
    if (cut) {
        memcpy(r->shared.clip_plane, v->pub->clip_plane, sizeof(float) * 4);
        r->clip0_on = true;
        GL(Enable)(GL_CLIP_DISTANCE0);
        r->shared_stamp++;
    }
    if (!limen__variant_use(r, mode, shape, checker, textured)) {
        if (cut)
            set_view_clip(r, v);
        return;
    }
    mat4 model;
    mat3 nm;
    glm_mat4_copy(world, model);
    glm_scale(model, scale);
    limen__normal_matrix(model, nm);
    set_mat4(r, r->u.model, model);
    GL(UniformMatrix3fv)(r->u.normal_mat, 1, GL_FALSE, (const GLfloat *)nm);
    GL(Uniform3fv)(r->u.albedo, 1, albedo);
    if (checker) {
        GL(Uniform3fv)(r->u.albedo_b, 1, node->checker);
        GL(Uniform1f)(r->u.cell, node->cell);
        GL(Uniform3fv)(r->u.scale, 1, scale);
    }
    if (textured)
        GL(Uniform2fv)(r->u.uv_repeat, 1, node->texture_repeat);
    if (limen__depth_clamped(v->pub, is_surface(node)))
        GL(Enable)(GL_DEPTH_CLAMP);
    else
        GL(Disable)(GL_DEPTH_CLAMP);
    /* Closed shapes hide their back faces; flat shapes are seen from both sides (meshes,
     * whose files need not be closed, too: gl/batch.c). */
    if (shape || node->kind == LIMEN_NODE_BOX)
        GL(Enable)(GL_CULL_FACE);
    else
        GL(Disable)(GL_CULL_FACE);
    GL(DrawElements)(GL_TRIANGLES, (GLsizei)range.count, GL_UNSIGNED_INT,
                     (void *)(sizeof(uint32_t) * range.first));
    r->draw_calls++;
    r->triangles += range.count / 3;
    if (cut)
        set_view_clip(r, v);
}


/* ------------------------------------------------------------------ surfaces as polygons */

#ifndef GL_TRIANGLE_FAN
#define GL_TRIANGLE_FAN 0x0006
#endif
#ifndef GL_STREAM_DRAW
#define GL_STREAM_DRAW 0x88E0
#endif

/* polygons of up to 31 vertices in arrays of 32 */
static int clip4(double in[][4], int n, const double pl[4], double out[][4])
{
    return limen_clip_polygon(&in[0][0], n, pl, &out[0][0], 31);
}

static void to_ndc(double p[][4], int n, float out[][3], int *count)
{
    *count = n < 3 ? 0 : n;
    for (int i = 0; i < *count; i++)
        for (int k = 0; k < 3; k++)
            out[i][k] = (float)(p[i][k] / p[i][3]);
}

/* The surface polygon clipped to the view's exit plane (in every nested view: with depth
 * clamping an oblique near plane would not cut it), to the frustum's four sides (so that the
 * GPU clips nothing: its float clipping fails when the surface nearly touches the eye, w a
 * few float steps of x), then split at the near and far planes. */
void limen__surface_parts(const limen_renderer *r, const rview *v, const limen_drawable *node,
                          limen__spoly *sp)
{
    double a[32][4], b[32][4], c[32][4];
    const double lx[4] = { -0.5, 0.5, 0.5, -0.5 }, ly[4] = { -0.5, -0.5, 0.5, 0.5 };
    const float *w = node->world;
    for (int i = 0; i < 4; i++) {
        for (int k = 0; k < 3; k++)
            a[i][k] = (double)w[k] * lx[i] * node->dims[0] +
                      (double)w[4 + k] * ly[i] * node->dims[1] + w[12 + k];
        a[i][3] = 1;
    }
    int n = 4;
    if (exit_cuts(v)) {
        const double cp[4] = { v->pub->clip_plane[0], v->pub->clip_plane[1],
                               v->pub->clip_plane[2], v->pub->clip_plane[3] };
        n = clip4(a, n, cp, b);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    for (int i = 0; i < n; i++) {
        double q[4];
        for (int row = 0; row < 4; row++)
            q[row] = (double)v->view_proj[0][row] * a[i][0] + (double)v->view_proj[1][row] * a[i][1] +
                     (double)v->view_proj[2][row] * a[i][2] + (double)v->view_proj[3][row] * a[i][3];
        memcpy(a[i], q, sizeof q);
    }
    static const double sides[4][4] = { { -1, 0, 0, 1 }, { 1, 0, 0, 1 }, { 0, -1, 0, 1 }, { 0, 1, 0, 1 } };
    for (int k = 0; k < 4 && n >= 3; k++) {
        n = clip4(a, n, sides[k], b);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    int m = 0;
    for (int i = 0; i < n; i++)
        if (a[i][3] > 0)
            memcpy(b[m++], a[i], sizeof(double) * 4);
    n = m;
    memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    memset(sp->n, 0, sizeof sp->n);
    sp->nxy = n < 3 ? 0 : n;
    for (int i = 0; i < sp->nxy; i++)
        sp->xy[i][0] = a[i][0] / a[i][3], sp->xy[i][1] = a[i][1] / a[i][3];
    /* near and far planes (inside >= 0) and the depths clamping gives beyond them */
    double np[4] = { 0, 0, 1, 1 }, fp[4] = { 0, 0, -1, 1 };
    sp->z[0] = -1, sp->z[1] = 1;
    if (r->range == LIMEN_DEPTH_ZO) {
        np[3] = 0, sp->z[0] = 0;
    } else if (r->range == LIMEN_DEPTH_ZO_REVERSED) {
        double t1[4] = { 0, 0, -1, 1 }, t2[4] = { 0, 0, 1, 0 };
        memcpy(np, t1, sizeof np), memcpy(fp, t2, sizeof fp);
        sp->z[0] = 1, sp->z[1] = 0;
    }
    if (n < 3)
        return;
    double nn[4] = { -np[0], -np[1], -np[2], -np[3] }, fn[4] = { -fp[0], -fp[1], -fp[2], -fp[3] };
    to_ndc(c, clip4(a, n, nn, c), sp->p[0], &sp->n[0]);
    to_ndc(c, clip4(a, n, fn, c), sp->p[1], &sp->n[1]);
    int k = clip4(a, n, np, c);
    to_ndc(b, clip4(c, k, fp, b), sp->p[2], &sp->n[2]);
}

/* Draws the parts of sp with the bound program (positions in NDC): at their own depth, or
 * all at z where fixed. The vertices go into fresh storage each time (the buffer orphaned,
 * then filled): llvmpipe serves a same-sized glBufferData of new data as a write into the
 * old storage, and so first finishes every draw queued so far that might read it, which
 * made the stencil method's hundreds of flat passes a frame wait, one by one, for the
 * rasterizer threads. */
static void draw_parts(limen_renderer *r, const limen__spoly *sp, bool fixed, float z)
{
    if (!r->poly_vao) {
        GL(GenVertexArrays)(1, &r->poly_vao);
        GL(BindVertexArray)(r->poly_vao);
        GL(GenBuffers)(1, &r->poly_vbo);
        GL(BindBuffer)(GL_ARRAY_BUFFER, r->poly_vbo);
        GL(EnableVertexAttribArray)(0);
        GL(VertexAttribPointer)(0, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex), (void *)0);
        GL(EnableVertexAttribArray)(1);
        GL(VertexAttribPointer)(1, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex),
                                (void *)offsetof(limen__vertex, nrm));
    }
    limen__vertex buf[3 * 32];
    int first[3], total = 0;
    for (int part = 0; part < 3; part++) {
        int n = sp->n[part];
        first[part] = total;
        if (n < 3)
            continue;
        float pz = fixed ? z : part < 2 ? sp->z[part] : 0;
        for (int i = 0; i < n; i++) {
            limen__vertex *b = &buf[total + i];
            b->pos[0] = sp->p[part][i][0];
            b->pos[1] = sp->p[part][i][1];
            b->pos[2] = !fixed && part == 2 ? sp->p[part][i][2] : pz;
            b->nrm[0] = b->nrm[1] = 0, b->nrm[2] = 1;
        }
        total += n;
    }
    if (!total)
        return;
    GL(BindVertexArray)(r->poly_vao);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->poly_vbo);
    GLsizeiptr size = (GLsizeiptr)(sizeof(limen__vertex) * (size_t)total);
    GL(BufferData)(GL_ARRAY_BUFFER, size, NULL, GL_STREAM_DRAW);
    GL(BufferSubData)(GL_ARRAY_BUFFER, 0, size, buf);
    for (int part = 0; part < 3; part++)
        if (sp->n[part] >= 3) {
            GL(DrawArrays)(GL_TRIANGLE_FAN, first[part], sp->n[part]);
            r->draw_calls++;
            r->triangles += (uint64_t)sp->n[part] - 2;
        }
    GL(BindVertexArray)(r->vao);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->vbo);
}

/* Flat polygons in one colour (times the view's tint) with the fill program; the main
 * program is bound again after. */
void limen__flat_parts(limen_renderer *r, const rview *v, const limen__spoly *sp,
                       const float rgb[3], bool fixed, float z)
{
    const float *t = v->pub->tint;
    float c[3] = { rgb[0] * t[0], rgb[1] * t[1], rgb[2] * t[2] };
    GL(UseProgram)(r->fill_prog);
    r->bound_prog = r->fill_prog;
    GL(Uniform3fv)(r->u_fill_color, 1, c);
    GL(Enable)(GL_DEPTH_CLAMP);
    GL(Disable)(GL_CULL_FACE);
    draw_parts(r, sp, fixed, z);
}

/* A surface's flat pass (mark, seal, fill: flat colour; or the previous frame's picture)
 * from its parts (computed here where sp is NULL). */
void limen__surface_flat(limen_renderer *r, const rview *v, const limen_drawable *node,
                         int mode, const float *albedo, const limen__spoly *sp)
{
    limen__spoly own;
    if (!sp) {
        limen__surface_parts(r, v, node, &own);
        sp = &own;
    }
    if (mode == MODE_FLAT) {
        limen__flat_parts(r, v, sp, albedo, false, 0);
        return;
    }
    /* the parts are in NDC already: identity matrices, planes that keep everything */
    static const float ident[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    memcpy(r->shared.view_proj, ident, sizeof ident);
    memcpy(r->shared.clip_plane, keep_all, sizeof keep_all);
    memcpy(r->shared.cut_plane, keep_all, sizeof keep_all);
    r->shared_stamp++;
    if (limen__variant_use(r, mode, 0, 0, LIMEN__UV_NONE)) {
        GL(UniformMatrix4fv)(r->u.model, 1, GL_FALSE, ident);
        GL(Uniform3fv)(r->u.albedo, 1, albedo);
        GL(Enable)(GL_DEPTH_CLAMP);
        GL(Disable)(GL_CULL_FACE);
        draw_parts(r, sp, false, 0);
    }
    memcpy(r->shared.view_proj, v->view_proj, sizeof r->shared.view_proj);
    set_view_clip(r, v);
}

static void draw_node(limen_renderer *r, const rview *v, const limen_drawable *node, int mode,
                      const float *albedo)
{
    if ((mode == MODE_FLAT || mode == MODE_TEXTURE) && is_surface(node)) {
        limen__surface_flat(r, v, node, mode, albedo, NULL);
        return;
    }
    mat4 world;
    memcpy(world, node->world, sizeof world);
    draw_node_at(r, v, node, world, mode, albedo);
}

/* Clip distance 1: the cut of a shape passing through a portal (NULL: none). */
static void set_cut(limen_renderer *r, const float *plane)
{
    memcpy(r->shared.cut_plane, plane ? plane : keep_all, sizeof keep_all);
    r->clip1_on = plane != NULL;
    r->shared_stamp++;
    if (plane)
        GL(Enable)(GL_CLIP_DISTANCE1);
    else
        GL(Disable)(GL_CLIP_DISTANCE1);
}

static int by_distance(const void *a, const void *b)
{
    const struct limen__draw_key *x = a, *y = b;
    int c = (x->dist > y->dist) - (x->dist < y->dist);
    return c ? c : (x->node > y->node) - (x->node < y->node);
}

/* A shape (not a surface, not a light) that view v may show. */
static bool shows(const rview *v, const limen_drawable *d)
{
    return d->visible && (d->kind == LIMEN_NODE_BOX || d->kind == LIMEN_NODE_SPHERE ||
                          d->kind == LIMEN_NODE_CYLINDER || d->kind == LIMEN_NODE_QUAD ||
                          d->kind == LIMEN_NODE_MESH) &&
           !outside(v, d, NULL);
}

/* The candidates for view v from the scene's spatial index (limen_plan_view_things), in
 * r->things: what the view's pyramid meets, found in time that follows what it holds, not
 * what the scene holds. Returns their count, or -1 where the index cannot answer. */
static int view_things(limen_renderer *r, const rview *v)
{
    if (!r->scene)
        return -1;
    int n = limen_plan_view_things(r->plan, r->scene, v->index, r->things, r->things_cap);
    if (n > r->things_cap) {
        limen_node *t = realloc(r->things, sizeof *t * (size_t)n);
        if (!t)
            return -1;
        r->things = t;
        r->things_cap = n;
        n = limen_plan_view_things(r->plan, r->scene, v->index, r->things, r->things_cap);
    }
    return n;
}

/* The shapes view v can show, nearest first (so that, without a depth-only pass, what lies
 * behind fails the depth test before it is shaded; ties in list order), in r->order.
 * Returns the count, or -1 where the list cannot grow (then draw them in list order). */
static int view_order(limen_renderer *r, const rview *v)
{
    const limen_drawable *items;
    int count = limen_drawables_items(r->draw, &items);
    if (r->order_cap < count) {
        struct limen__draw_key *o = realloc(r->order, sizeof *o * (size_t)count);
        if (!o)
            return -1;
        r->order = o;
        r->order_cap = count;
    }
    int nt = view_things(r, v), n = 0;
    for (int k = 0; k < (nt < 0 ? count : nt); k++) {
        int i = nt < 0 ? k : limen_drawables_find(r->draw, r->things[k]);
        if (i < 0 || !shows(v, &items[i]))
            continue;
        const float *c = items[i].centre, *eye = v->pub->eye;
        double dx = (double)c[0] - eye[0], dy = (double)c[1] - eye[1], dz = (double)c[2] - eye[2];
        r->order[n++] = (struct limen__draw_key){ (float)(dx * dx + dy * dy + dz * dz), i };
    }
    if (n > 1)  /* r->order is NULL while nothing was ever listed (UBSan) */
        qsort(r->order, (size_t)n, sizeof *r->order, by_distance);
    return n;
}

/* Drawable i, cut at its portal where it passes through one. */
static void draw_thing(limen_renderer *r, const rview *v, const limen_drawable *items, int i)
{
    const limen_clone *clones;
    limen_plan_clones(r->plan, &clones);
    int c = r->clone_of[i];
    if (c >= 0)
        set_cut(r, clones[c].keep);
    draw_node(r, v, &items[i], MODE_LIT, items[i].color);
    if (c >= 0)
        set_cut(r, NULL);
}

/* The copies of what has gone into a portal, coming out of its partner (limen_plan_clones),
 * each cut at the partner's plane; only meshes with blended parts where blended (the blend
 * pass). */
static void draw_clones(limen_renderer *r, const rview *v, bool blended)
{
    const limen_clone *clones;
    int nclones = limen_plan_clones(r->plan, &clones);
    for (int c = 0; c < nclones; c++) {
        const limen_clone *cl = &clones[c];
        const limen_drawable *node = item_of(r, cl->node);
        if (!node || (blended && (node->kind != LIMEN_NODE_MESH || !node->mesh ||
                                  !node->mesh->has_blend)) ||
            outside(v, node, cl->matrix))
            continue;
        mat4 carry, own, world;
        memcpy(carry, cl->matrix, sizeof carry);
        memcpy(own, node->world, sizeof own);
        glm_mat4_mul(carry, own, world);
        set_cut(r, cl->copy_keep);
        draw_node_at(r, v, node, world, MODE_LIT, node->color);
        set_cut(r, NULL);
    }
}

/* fresh: nothing is in the view's depth yet (it sees no surface). Then the nearest thing,
 * drawn first, passes the depth test wherever it lands if it is a shape (each is convex,
 * closed ones without their back faces; a mesh need not be): it only writes depth, which
 * llvmpipe does without reading it. */
static void draw_geometry(limen_renderer *r, const rview *v, bool fresh)
{
    const limen_drawable *items;
    int count = limen_drawables_items(r->draw, &items);
    int n = view_order(r, v);
    if (n < 0) {
        for (int i = 0; i < count; i++)
            if (shows(v, &items[i]))
                draw_thing(r, v, items, i);
    }
    /* meshes that share geometry go in batches, each drawn where its nearest member stands */
    int nb = n > 0 ? limen__batches_plan(r, v->pub, items, r->order, n) : 0, b = 0;
    bool first_free = fresh && n > 0 && items[r->order[0].node].kind != LIMEN_NODE_MESH;
    for (int k = 0; k < n; k++) {
        int i = r->order[k].node;
        if (nb >= 0 && items[i].kind == LIMEN_NODE_MESH && r->clone_of[i] < 0) {
            if (b < nb && limen__batch_first(r, b) == k)
                limen__batch_draw(r, v->pub, items, b++);
            continue;
        }
        if (k == 0 && first_free)
            GL(DepthFunc)(GL_ALWAYS);
        draw_thing(r, v, items, i);
        if (k == 0 && first_free)
            GL(DepthFunc)(r->range == LIMEN_DEPTH_ZO_REVERSED ? GL_GREATER : GL_LESS);
    }
    /* what has gone into a portal, coming out of its partner */
    draw_clones(r, v, false);
}

/* ------------------------------------------------------------------ blended parts */

bool limen__scene_blends(const limen_renderer *r)
{
    const limen_drawable *items;
    int count = limen_drawables_items(r->draw, &items);
    for (int i = 0; i < count; i++)
        if (items[i].visible && items[i].kind == LIMEN_NODE_MESH && items[i].mesh &&
            items[i].mesh->has_blend)
            return true;
    return false;
}

void limen__draw_blended(limen_renderer *r, const rview *v)
{
    if (!limen__scene_blends(r))
        return;
    const limen_drawable *items;
    limen_drawables_items(r->draw, &items);
    int n = view_order(r, v);
    GL(Enable)(GL_BLEND);
    GL(BlendFunc)(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    GL(DepthMask)(GL_FALSE);
    r->blend_pass = true;
    limen__samples_begin(r);
    for (int k = n - 1; k >= 0; k--) {     /* farthest first */
        int i = r->order[k].node;
        if (items[i].kind == LIMEN_NODE_MESH && items[i].mesh && items[i].mesh->has_blend)
            draw_thing(r, v, items, i);
    }
    draw_clones(r, v, true);
    limen__samples_end(r);
    r->blend_pass = false;
    GL(DepthMask)(GL_TRUE);
    GL(Disable)(GL_BLEND);
}

/* The previous frame's picture of a surface where recursion stops: the rectangle of the
 * shallowest view through it, stretched onto the surface's rectangle here. False where there
 * is no such picture. */
static bool draw_previous(limen_renderer *r, const rview *v, const limen_view_surface *vs,
                          const limen_drawable *n)
{
    if (r->opts.fill != LIMEN_FILL_PREVIOUS || !r->have_prev)
        return false;
    const limen_view *best = NULL;
    for (int i = 1; i < limen_plan_count(r->plan); i++) {
        const limen_view *u = limen_plan_view(r->plan, i);
        if (u->through.id == vs->node.id && (!best || u->depth < best->depth))
            best = u;
    }
    if (!best)
        return false;
    const int *rt = vs->rect, *r1 = best->scissor;
    float kx = (float)r1[2] / (float)rt[2], ky = (float)r1[3] / (float)rt[3];
    float W = (float)r->width, H = (float)r->height;
    float map[4] = {
        v->img_map[0] * kx / W,
        v->img_map[1] * ky / H,
        ((v->img_map[2] - (float)rt[0]) * kx + (float)r1[0]) / W,
        ((v->img_map[3] - (float)rt[1]) * ky + (float)r1[1]) / H,
    };
    GL(ActiveTexture)(GL_TEXTURE0);
    GL(BindTexture)(GL_TEXTURE_2D, r->prev_tex);
    memcpy(r->shared.tex_map, map, sizeof map);
    r->shared_stamp++;
    draw_node(r, v, n, MODE_TEXTURE, v->pub->tint);
    return true;
}

/* The surfaces a view sees that end there: a mirror's back, or a fill where recursion
 * stopped. */
static void draw_terminal_surface(limen_renderer *r, const rview *v,
                                  const limen_view_surface *vs)
{
    const limen_drawable *n = item_of(r, vs->node);
    if (!n)
        return;
    if (vs->state == LIMEN_SURFACE_BACK)
        draw_node(r, v, n, MODE_LIT, n->back);
    else if (vs->state == LIMEN_SURFACE_FILL && !draw_previous(r, v, vs, n))
        draw_node(r, v, n, MODE_FLAT, n->fill);
}

/* ------------------------------------------------------------------ shared by both methods */

GLenum limen__depth_less(const limen_renderer *r)
{
    return r->range == LIMEN_DEPTH_ZO_REVERSED ? GL_GREATER : GL_LESS;
}

GLenum limen__depth_lequal(const limen_renderer *r)
{
    return r->range == LIMEN_DEPTH_ZO_REVERSED ? GL_GEQUAL : GL_LEQUAL;
}

/* The view's opaque things: the surfaces that end here (flat, cheap to shade twice), then
 * the geometry. */
void limen__draw_opaque(limen_renderer *r, const rview *v, const limen_view_surface *vs, int n)
{
    for (int k = 0; k < n; k++)
        if (vs[k].state != LIMEN_SURFACE_RECURSE)
            draw_terminal_surface(r, v, &vs[k]);
    draw_geometry(r, v, n == 0);
}

/* The drawable of a surface that a view recurses into; NULL for the others. */
const limen_drawable *limen__recursed(const limen_renderer *r, const limen_view_surface *vs)
{
    return vs->state == LIMEN_SURFACE_RECURSE ? item_of(r, vs->node) : NULL;
}

/* ------------------------------------------------------------------ texture method */

void limen__targets_free(limen_renderer *r)
{
    for (int i = 0; i < LIMEN__MAX_LEVELS; i++) {
        limen__target *t = &r->levels[i];
        if (t->fbo) {
            GL(DeleteFramebuffers)(1, &t->fbo);
            GL(DeleteTextures)(1, &t->tex);
            GL(DeleteRenderbuffers)(1, &t->depth_rb);
        }
        memset(t, 0, sizeof *t);
    }
}

static limen__target *level_target(limen_renderer *r, int level, float scale)
{
    if (r->levels_scale != scale) {
        limen__targets_free(r);
        r->levels_scale = scale;
    }
    limen__target *t = &r->levels[level];
    if (t->fbo)
        return t;
    t->w = (int)ceilf((float)r->width * scale);
    t->h = (int)ceilf((float)r->height * scale);
    GL(GenTextures)(1, &t->tex);
    GL(BindTexture)(GL_TEXTURE_2D, t->tex);
    GL(TexImage2D)(GL_TEXTURE_2D, 0, GL_RGBA8, t->w, t->h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    GL(GenRenderbuffers)(1, &t->depth_rb);
    GL(BindRenderbuffer)(GL_RENDERBUFFER, t->depth_rb);
    GL(RenderbufferStorage)(GL_RENDERBUFFER, limen__depth_format(r), t->w, t->h);
    GL(GenFramebuffers)(1, &t->fbo);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, t->fbo);
    GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->tex, 0);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                t->depth_rb);
    if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        limen__targets_free(r);
        return NULL;
    }
    return t;
}

/* Where a view's pixels land in its target: image pixel rect -> target viewport. */
typedef struct placement {
    GLuint fbo;
    int ox, oy;             /* the viewport's corner in the target (the frame's origin) */
    int vw, vh;             /* viewport size in the target */
    float sx, sy;           /* target pixels per image pixel */
    int rect[4];            /* image rectangle the viewport covers */
} placement;

static void bind_placement(limen_renderer *r, const placement *pl)
{
    GL(BindFramebuffer)(GL_FRAMEBUFFER, pl->fbo);
    GL(Viewport)(pl->ox, pl->oy, pl->vw, pl->vh);
    GL(Enable)(GL_SCISSOR_TEST);
    GL(Scissor)(pl->ox, pl->oy, pl->vw, pl->vh);
}

/* Renders view `index` into the placement; returns false if a target could not be made. */
static bool texture_view(limen_renderer *r, int index, const placement *pl)
{
    /* narrow the projection from the whole image to this view's rectangle */
    mat4 narrow;
    narrow_to(r, pl->rect, narrow);
    rview v;
    limen__rview_make(r, index, narrow, &v);
    v.img_map[0] = 1.0f / pl->sx;
    v.img_map[1] = 1.0f / pl->sy;
    /* the image pixels of the target's first fragment */
    const float px0 = (float)pl->rect[0] - (float)pl->ox / pl->sx;
    const float py0 = (float)pl->rect[1] - (float)pl->oy / pl->sy;
    v.img_map[2] = px0;
    v.img_map[3] = py0;
    limen__rview_cull(r, &v, NULL);

    bind_placement(r, pl);
    const float *tint = v.pub->tint;
    GL(ClearColor)(r->background[0] * tint[0], r->background[1] * tint[1],
                   r->background[2] * tint[2], 1.0f);
    GL(ClearDepth)(r->range == LIMEN_DEPTH_ZO_REVERSED ? 0.0 : 1.0);
    GL(Clear)(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    limen__rview_apply(r, &v);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(r->plan, index, &vs);
    const limen_drawable *node;
    /* the surfaces that show a child's image go into depth first, so that nothing behind
     * them is shaded; then the view's own things, nearest first */
    GL(ColorMask)(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (int k = 0; k < n; k++)
        if ((node = limen__recursed(r, &vs[k])))
            limen__surface_flat(r, &v, node, MODE_FLAT, r->background, NULL);
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    limen__samples_begin(r);
    limen__draw_opaque(r, &v, vs, n);
    limen__samples_end(r);

    for (int k = 0; k < n; k++) {
        if (!(node = limen__recursed(r, &vs[k])))
            continue;
        int ci = vs[k].child;
        const limen_view *c = limen_plan_view(r->plan, ci);
        limen__target *t = level_target(r, c->depth, r->opts.texture_scale);
        if (!t)
            return false;
        placement cp;
        cp.fbo = t->fbo;
        cp.ox = cp.oy = 0;
        cp.vw = (int)ceilf((float)c->scissor[2] * r->opts.texture_scale);
        cp.vh = (int)ceilf((float)c->scissor[3] * r->opts.texture_scale);
        cp.sx = (float)cp.vw / (float)c->scissor[2];
        cp.sy = (float)cp.vh / (float)c->scissor[3];
        memcpy(cp.rect, c->scissor, sizeof cp.rect);
        if (!texture_view(r, ci, &cp))
            return false;

        /* back in this view: the surface samples the child's image where it appears on
         * screen (the child applied the tints already) */
        bind_placement(r, pl);
        limen__rview_apply(r, &v);
        GL(ActiveTexture)(GL_TEXTURE0);
        GL(BindTexture)(GL_TEXTURE_2D, t->tex);
        /* fragment (this target) -> image pixel -> child texel -> uv */
        float map[4] = {
            cp.sx / (pl->sx * (float)t->w),
            cp.sy / (pl->sy * (float)t->h),
            (px0 - (float)cp.rect[0]) * cp.sx / (float)t->w,
            (py0 - (float)cp.rect[1]) * cp.sy / (float)t->h,
        };
        memcpy(r->shared.tex_map, map, sizeof map);
        r->shared_stamp++;
        vec3 white = { 1, 1, 1 };
        GL(DepthFunc)(limen__depth_lequal(r));      /* its own depth is there already */
        limen__samples_begin(r);
        draw_node(r, &v, node, MODE_TEXTURE, white);
        limen__samples_end(r);
        GL(DepthFunc)(limen__depth_less(r));
    }
    /* blended parts over the finished picture, the surfaces' images included */
    bind_placement(r, pl);
    limen__rview_apply(r, &v);
    limen__draw_blended(r, &v);
    return true;
}

limen_status limen__draw_texture(limen_renderer *r)
{
    limen__lights_set(r);
    placement root = { r->fbo, r->origin[0], r->origin[1], r->width, r->height, 1.0f, 1.0f,
                       { 0, 0, r->width, r->height } };
    bool ok = texture_view(r, 0, &root);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    GL(Viewport)(r->origin[0], r->origin[1], r->width, r->height);
    GL(Disable)(GL_SCISSOR_TEST);
    GL(FrontFace)(GL_CCW);
    if (!ok)
        return limen__rfail(r, LIMEN_ERR_GL, "texture method: cannot make an offscreen target");
    return LIMEN_OK;
}
