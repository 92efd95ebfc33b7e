/* backend.c - the OpenGL backend of the draw list (limen.h, "draw list"): one loop over a
 * frame's commands, each drawn with the state it carries. It holds no scene and decides
 * nothing the list has decided: what it adds is OpenGL's (programs, buffers, the unit meshes'
 * levels of detail, textures, targets, queries). */
#include <string.h>

#include "gl/gl_internal.h"

#ifndef GL_TRIANGLE_FAN
#define GL_TRIANGLE_FAN 0x0006
#endif
#ifndef GL_STREAM_DRAW
#define GL_STREAM_DRAW 0x88E0
#endif

static const float keep_all[4] = { 0, 0, 0, 1 };
static const float ident[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };

/* Floats per instance: model matrix, normal matrix, albedo (gl/assets.c lays them out). */
typedef struct limen__instance {
    float model[16];
    float normal[9];            /* inverse transpose of the model's 3x3 part */
    float albedo[3];
} instance;

_Static_assert(sizeof(instance) == sizeof(float) * LIMEN__INSTANCE_FLOATS,
               "an instance is LIMEN__INSTANCE_FLOATS floats");

/* ------------------------------------------------------------------ state */

static GLenum compare_gl(limen_compare c)
{
    static const GLenum gl[LIMEN_COMPARE_COUNT] = { GL_ALWAYS, GL_LESS, GL_LEQUAL, GL_EQUAL,
                                                    GL_GREATER, GL_GEQUAL };
    return (unsigned)c < LIMEN_COMPARE_COUNT ? gl[c] : GL_LESS;
}

static GLenum stencil_gl(limen_stencil_op op)
{
    return op == LIMEN_STENCIL_INVERT ? GL_INVERT : op == LIMEN_STENCIL_DECR ? GL_DECR : GL_KEEP;
}

static void toggle(limen_renderer *r, GLenum cap, bool on)
{
    if (on)
        GL(Enable)(cap);
    else
        GL(Disable)(cap);
}

/* Sets what of state s differs from what is set (all of it at a frame's start); target:
 * the frame's scissor is offset by its origin in the framebuffer; planes: false for the fill
 * program, whose clip distances cut nothing, so that flat polygons between lit draws leave
 * the clip planes (and the variants' uploaded values) as they are. */
static void apply_state(limen_renderer *r, const limen_draw_state *s, int target, bool planes)
{
    limen_draw_state *o = &r->applied;
    bool all = !r->applied_valid;
    int sc[4] = { s->scissor[0], s->scissor[1], s->scissor[2], s->scissor[3] };
    if (target == 0)
        sc[0] += r->origin[0], sc[1] += r->origin[1];
    if (all || memcmp(sc, r->applied_scissor, sizeof sc)) {
        GL(Enable)(GL_SCISSOR_TEST);
        GL(Scissor)(sc[0], sc[1], sc[2], sc[3]);
        memcpy(r->applied_scissor, sc, sizeof sc);
    }
    if (all || s->color_write != o->color_write) {
        GLboolean c = s->color_write ? GL_TRUE : GL_FALSE;
        GL(ColorMask)(c, c, c, c);
    }
    if (all || s->depth_write != o->depth_write)
        GL(DepthMask)(s->depth_write ? GL_TRUE : GL_FALSE);
    if (all || s->depth_clamp != o->depth_clamp)
        toggle(r, GL_DEPTH_CLAMP, s->depth_clamp);
    if (all || s->cull_back != o->cull_back)
        toggle(r, GL_CULL_FACE, s->cull_back);
    if (all || s->blend != o->blend) {
        toggle(r, GL_BLEND, s->blend);
        if (s->blend)
            GL(BlendFunc)(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    }
    if (all || s->stencil_test != o->stencil_test)
        toggle(r, GL_STENCIL_TEST, s->stencil_test);
    if (all || s->stencil_ref != o->stencil_ref)
        GL(StencilFunc)(GL_EQUAL, s->stencil_ref, 0xFF);
    if (all || s->stencil_write_mask != o->stencil_write_mask)
        GL(StencilMask)(s->stencil_write_mask);
    if (all || s->stencil_pass != o->stencil_pass)
        GL(StencilOp)(GL_KEEP, GL_KEEP, stencil_gl(s->stencil_pass));
    if (all || s->depth_test != o->depth_test)
        GL(DepthFunc)(compare_gl(s->depth_test));
    bool clip = planes || all, cut = planes || all;
    if (clip && (all || s->clip_on != o->clip_on || memcmp(s->clip, o->clip, sizeof s->clip))) {
        memcpy(r->shared.clip_plane, s->clip_on ? s->clip : keep_all, sizeof s->clip);
        r->clip0_on = s->clip_on;
        toggle(r, GL_CLIP_DISTANCE0, s->clip_on);
        r->shared_stamp++;
    }
    if (cut && (all || s->cut_on != o->cut_on || memcmp(s->cut, o->cut, sizeof s->cut))) {
        memcpy(r->shared.cut_plane, s->cut_on ? s->cut : keep_all, sizeof s->cut);
        r->clip1_on = s->cut_on;
        toggle(r, GL_CLIP_DISTANCE1, s->cut_on);
        r->shared_stamp++;
    }
    /* occlusion queries around the shading passes (the frame's samples) */
    if (s->counted && !r->q_active)
        limen__samples_begin(r);
    else if (!s->counted && r->q_active)
        limen__samples_end(r);
    limen_draw_state was = *o;
    *o = *s;
    if (!clip) {
        o->clip_on = was.clip_on;
        memcpy(o->clip, was.clip, sizeof o->clip);
    }
    if (!cut) {
        o->cut_on = was.cut_on;
        memcpy(o->cut, was.cut, sizeof o->cut);
    }
    r->applied_valid = true;
}

/* The pass's camera: its matrix, eye, tint and winding for what follows. */
static void bind_pass(limen_renderer *r, const limen_draw_pass *p)
{
    memcpy(r->shared.view_proj, p->view_proj, sizeof r->shared.view_proj);
    memcpy(r->shared.eye, p->eye, sizeof r->shared.eye);
    memcpy(r->shared.tint, p->tint, sizeof r->shared.tint);
    r->shared_stamp++;
    GL(FrontFace)(p->front_cw ? GL_CW : GL_CCW);
}

/* The list's lights and ambient term, once per frame. */
static void lights_set(limen_renderer *r, const limen_drawlist *dl)
{
    const limen_draw_light *l;
    int n = limen_drawlist_lights(dl, &l, &r->shared.ambient);
    bool ranged = false;
    for (int i = 0; i < n && i < LIMEN_MAX_LIGHTS; i++) {
        memcpy(r->shared.light_pos[i], l[i].pos, sizeof l[i].pos);
        memcpy(r->shared.light_col[i], l[i].color, sizeof l[i].color);
        r->shared.light_inv_r2[i] = l[i].inv_range2;
        ranged |= l[i].inv_range2 > 0;
    }
    r->shared.nlights = n < LIMEN_MAX_LIGHTS ? n : LIMEN_MAX_LIGHTS;
    r->shared.ranged = ranged;
    r->shared_stamp++;
}

/* ------------------------------------------------------------------ polygons */

/* The list's vertices, once a frame, into fresh storage (the buffer orphaned, then filled):
 * llvmpipe serves a same-sized glBufferData of new data as a write into the old storage,
 * and so first finishes every draw queued so far that might read it. */
static bool upload_polygons(limen_renderer *r, const float (*v)[3], int n)
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
    if (!n)
        return true;
    if (!limen__gl_grow((void **)&r->poly, &r->poly_cap, n, sizeof *r->poly))
        return false;
    for (int i = 0; i < n; i++) {
        limen__vertex *b = &r->poly[i];
        memcpy(b->pos, v[i], sizeof b->pos);
        b->nrm[0] = b->nrm[1] = 0, b->nrm[2] = 1;
    }
    GL(BindVertexArray)(r->poly_vao);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->poly_vbo);
    GLsizeiptr size = (GLsizeiptr)(sizeof(limen__vertex) * (size_t)n);
    GL(BufferData)(GL_ARRAY_BUFFER, size, NULL, GL_STREAM_DRAW);
    GL(BufferSubData)(GL_ARRAY_BUFFER, 0, size, r->poly);
    GL(BindVertexArray)(r->vao);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->vbo);
    return true;
}

static void draw_fan(limen_renderer *r, const limen_draw_cmd *c)
{
    GL(BindVertexArray)(r->poly_vao);
    GL(DrawArrays)(GL_TRIANGLE_FAN, c->first, c->count);
    r->draw_calls++;
    r->triangles += (uint64_t)c->count - 2;
    GL(BindVertexArray)(r->vao);
}

/* A polygon in NDC: flat colour with the fill program, or an image (the previous frame, a
 * target) times its colour with the main program over identity matrices. */
static void draw_polygon(limen_renderer *r, const limen_draw_cmd *c, const limen_draw_pass *p,
                         int target)
{
    if (c->count < 3)
        return;
    if (c->image == LIMEN_IMAGE_NONE) {
        GL(UseProgram)(r->fill_prog);
        r->bound_prog = r->fill_prog;
        GL(Uniform3fv)(r->u_fill_color, 1, c->color);
        draw_fan(r, c);
        return;
    }
    /* multisampled, a target over the frame pixel for pixel gives each sample its own;
     * another image is read once a pixel, at its centre: the average of the samples it
     * holds (a resolved target's pixel), not a blend of its neighbours' */
    const limen__target *t = c->image == LIMEN_IMAGE_TARGET && c->target > 0 &&
                             c->target < LIMEN__MAX_TARGETS ? &r->targets[c->target] : NULL;
    bool samples = t && t->ms_tex && r->opts.texture_scale == 1 && r->gl.MinSampleShading;
    GLuint bound = target > 0 && target < LIMEN__MAX_TARGETS ? r->targets[target].fbo : r->fbo;
    GLuint tex = samples ? t->ms_tex : c->image == LIMEN_IMAGE_PREVIOUS ? r->prev_tex
                                     : limen__target_texture(r, c->target, bound);
    if (!tex)
        return;
    GL(ActiveTexture)(GL_TEXTURE0);
    GL(BindTexture)(samples ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, tex);
    /* the list's fragments start at the target's corner; the frame's lie at its origin */
    float map[4];
    memcpy(map, c->image_map, sizeof map);
    if (target == 0) {
        map[2] -= map[0] * (float)r->origin[0];
        map[3] -= map[1] * (float)r->origin[1];
    }
    memcpy(r->shared.tex_map, map, sizeof map);
    memcpy(r->shared.view_proj, ident, sizeof ident);
    r->shared_stamp++;
    bool per_pixel = r->msaa && r->gl.MinSampleShading && !samples;
    if (per_pixel)
        GL(Disable)(GL_SAMPLE_SHADING);
    if (limen__variant_use(r, samples ? LIMEN__MODE_SAMPLES : LIMEN__MODE_TEXTURE, 0, 0,
                           LIMEN__UV_NONE)) {
        GL(UniformMatrix4fv)(r->u.model, 1, GL_FALSE, ident);
        GL(Uniform3fv)(r->u.albedo, 1, c->color);
        draw_fan(r, c);
    }
    if (per_pixel)
        GL(Enable)(GL_SAMPLE_SHADING);
    memcpy(r->shared.view_proj, p->view_proj, sizeof r->shared.view_proj);
    r->shared_stamp++;
}

/* ------------------------------------------------------------------ shapes */

/* A box, sphere, cylinder or quad from the unit shapes' buffers (render.c), lit, at the
 * command's world matrix and scale, at the command's level (a sphere's or cylinder's
 * segments). The normals a curved shape shades with are the true shape's (LIMEN__SHAPE_*). */
static void draw_shape(limen_renderer *r, const limen_draw_cmd *c, const limen_draw_pass *p,
                       const limen_drawable *node)
{
    const limen_kind_info *k = limen_kind_get(node->kind);
    int shape = LIMEN__SHAPE_FACE;
    if (!k || (unsigned)k->unit >= LIMEN_UNIT_COUNT || !r->unit_levels[k->unit])
        return;                         /* (NONE has no levels) */
    switch (k->unit) {
    case LIMEN_UNIT_NONE:
    case LIMEN_UNIT_COUNT:
    case LIMEN_UNIT_BOX:
    case LIMEN_UNIT_SQUARE:
        break;
    case LIMEN_UNIT_BALL:
        shape = LIMEN__SHAPE_SPHERE;
        break;
    case LIMEN_UNIT_CYLINDER:
        shape = LIMEN__SHAPE_CYLINDER;
        break;
    }
    int level = c->lod >= 0 && c->lod < r->unit_levels[k->unit] ? c->lod : 0;
    limen__range range = r->units[k->unit][level];
    vec3 scale = { c->scale[0], c->scale[1], c->scale[2] };
    /* the checker's cells and an albedo texture's coordinates as the kind's facts say: a
     * flat shape's over x + y (plane uvs), a solid's over x + y + z (a box face's) */
    int checker = !(node->cell > 0) ? 0 : k->flat && k->shape ? 1 : 2;
    int textured = LIMEN__UV_NONE;      /* (the same numbers as limen_uv_rule) */
    if (node->texture && limen__gpu_texture(r, node->texture, node->texture_filter))
        textured = (int)k->uv;
    if (!limen__variant_use(r, LIMEN__MODE_LIT, shape, checker, textured))
        return;
    mat4 model;
    mat3 nm;
    memcpy(model, c->world, sizeof model);
    glm_scale(model, scale);
    limen__normal_matrix(model, nm);
    GL(UniformMatrix4fv)(r->u.model, 1, GL_FALSE, (const GLfloat *)model);
    GL(UniformMatrix3fv)(r->u.normal_mat, 1, GL_FALSE, (const GLfloat *)nm);
    GL(Uniform3fv)(r->u.albedo, 1, c->color);
    if (checker) {
        GL(Uniform3fv)(r->u.albedo_b, 1, node->checker);
        GL(Uniform1f)(r->u.cell, node->cell);
        GL(Uniform3fv)(r->u.scale, 1, scale);
    }
    if (textured)
        GL(Uniform2fv)(r->u.uv_repeat, 1, node->texture_repeat);
    GL(BindVertexArray)(r->vao);
    GL(DrawElements)(GL_TRIANGLES, (GLsizei)range.count, GL_UNSIGNED_INT,
                     (void *)(sizeof(uint32_t) * range.first));
    r->draw_calls++;
    r->triangles += range.count / 3;
}

/* ------------------------------------------------------------------ meshes */

/* Whether mesh g shades as before materials: one white opaque part without textures,
 * emission or vertex colours (then it takes the variants without MATERIAL). */
static bool plain(const limen_mesh_geometry *g)
{
    if (g->colors || g->part_count > 1 || !g->materials)
        return !g->materials && !g->colors;
    const limen_material *m = &g->materials[0];
    return m->base_color[0] == 1 && m->base_color[1] == 1 && m->base_color[2] == 1 &&
           m->base_color[3] == 1 && !m->base_texture && m->alpha_mode == LIMEN_ALPHA_OPAQUE &&
           m->emissive[0] == 0 && m->emissive[1] == 0 && m->emissive[2] == 0;
}

/* The command's instances as copies of mesh drawable d at its level, part by part where it
 * has materials: the opaque and masked ones, or the blended ones. What differs from node to
 * node comes from the instance buffer, computed exactly as the one-node draws compute their
 * uniforms, so a node looks the same drawn either way. */
static void draw_meshes(limen_renderer *r, const limen_draw_cmd *c, const limen_drawable *d,
                        const limen_draw_instance *inst)
{
    const limen_mesh_geometry *g = d->mesh;
    bool blended = c->parts == LIMEN_PARTS_BLENDED;
    int n = c->count, lod = c->lod;
    if (!g || n <= 0 || (blended && !g->has_blend))
        return;
    /* a baked level is a mesh of its own (its vertices, texture and material); a node's
     * texture is drawn over the level's triangles on the mesh's vertices instead */
    int at = limen__gpu_mesh_level(g, lod);
    if (g->lods && g->lod_count > 0 && g->lods[at].baked && !d->texture) {
        g = g->lods[at].baked;
        lod = 0;
    }
    bool simple = plain(g);
    if (!limen__gl_grow((void **)&r->inst, &r->inst_cap, n, sizeof(instance))) {
        limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory for %d instances", n);
        return;
    }
    instance *out = r->inst;
    for (int j = 0; j < n; j++) {
        mat4 model;
        mat3 nm;
        memcpy(model, inst[j].world, sizeof model);
        limen__normal_matrix(model, nm);
        memcpy(out[j].model, inst[j].world, sizeof out[j].model);
        memcpy(out[j].normal, nm, sizeof out[j].normal);
        memcpy(out[j].albedo, inst[j].color, sizeof out[j].albedo);
    }
    GLint first;
    GLsizei count;
    bool indexed;
    if (!limen__gpu_mesh_bind(r, g, d->smooth, lod, &first, &count, &indexed))
        return;
    int level = limen__gpu_mesh_level(g, lod);
    const limen_mesh_part *parts = g->lods && g->lod_count > 0 && g->lods[level].parts
                                       ? g->lods[level].parts : g->parts;
    int nparts = simple || !parts ? 1 : g->part_count;
    int checker = d->cell > 0 ? 2 : 0;
    bool uploaded = false;
    for (int p = 0; p < nparts; p++) {
        const limen_material *mt = simple ? NULL : &g->materials[parts[p].material];
        if (mt && (mt->alpha_mode == LIMEN_ALPHA_BLEND) != blended)
            continue;
        GLint pfirst = simple ? first : first + parts[p].first_triangle * 3;
        GLsizei pcount = simple ? count : (GLsizei)parts[p].triangle_count * 3;
        if (pcount <= 0)
            continue;
        /* the node's texture replaces the part's */
        const limen_image *tex = d->texture ? d->texture : mt ? mt->base_texture : NULL;
        int textured = tex && limen__gpu_texture(r, tex, d->texture_filter) ? LIMEN__UV_MESH
                                                                           : LIMEN__UV_NONE;
        bool glow = mt && textured && !d->texture && mt->emissive_texture &&
                    limen__gpu_texture_on(r, mt->emissive_texture, 2, d->texture_filter);
        r->instanced = true;
        r->material = mt != NULL;
        bool ok = limen__variant_use(r, LIMEN__MODE_LIT, d->smooth ? LIMEN__SHAPE_SMOOTH : 0,
                                     checker, textured);
        r->instanced = false;
        r->material = false;
        if (!ok)
            continue;
        if (checker) {
            GL(Uniform3fv)(r->u.albedo_b, 1, d->checker);
            GL(Uniform1f)(r->u.cell, d->cell);
            GL(Uniform3fv)(r->u.scale, 1, (const float[3]){ 1, 1, 1 });
        }
        if (textured)
            GL(Uniform2fv)(r->u.uv_repeat, 1, d->texture_repeat);
        if (mt) {
            GL(Uniform4fv)(r->u.base, 1, mt->base_color);
            GL(Uniform3fv)(r->u.emissive, 1, mt->emissive);
            GL(Uniform1f)(r->u.cutoff, mt->alpha_mode == LIMEN_ALPHA_MASK ? mt->alpha_cutoff : -1.0f);
            GL(Uniform1i)(r->u.emissive_on, glow);
            GL(Uniform1i)(r->u.blend, mt->alpha_mode == LIMEN_ALPHA_BLEND);
        }
        if (!uploaded) {
            /* fresh storage each time: refilling the old one would wait for the draws
             * queued on it (llvmpipe) */
            GLsizeiptr size = (GLsizeiptr)(sizeof(instance) * (size_t)n);
            GL(BindBuffer)(GL_ARRAY_BUFFER, r->inst_vbo);
            GL(BufferData)(GL_ARRAY_BUFFER, size, NULL, GL_STREAM_DRAW);
            GL(BufferSubData)(GL_ARRAY_BUFFER, 0, size, r->inst);
            uploaded = true;
        }
        if (indexed)
            GL(DrawElementsInstanced)(GL_TRIANGLES, pcount, GL_UNSIGNED_INT,
                                      (void *)(sizeof(uint32_t) * (size_t)pfirst), n);
        else
            GL(DrawArraysInstanced)(GL_TRIANGLES, pfirst, pcount, n);
        r->draw_calls++;
        r->triangles += (uint64_t)(pcount / 3) * (uint64_t)n;
    }
    GL(BindVertexArray)(r->vao);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->vbo);
}

/* ------------------------------------------------------------------ the loop */

static void clear(limen_renderer *r, const limen_draw_cmd *c)
{
    GLbitfield bits = 0;
    if (c->state.color_write) {
        GL(ClearColor)(c->color[0], c->color[1], c->color[2], 1.0f);
        bits |= GL_COLOR_BUFFER_BIT;
    }
    if (c->state.depth_write) {
        GL(ClearDepth)(r->range == LIMEN_DEPTH_ZO_REVERSED ? 0.0 : 1.0);
        bits |= GL_DEPTH_BUFFER_BIT;
    }
    if (c->state.stencil_write_mask) {
        GL(ClearStencil)(0);
        bits |= GL_STENCIL_BUFFER_BIT;
    }
    if (bits)
        GL(Clear)(bits);
}

/* Draws into target k (0: the frame) over the command's viewport; false where an offscreen
 * target cannot be made. */
static bool bind_target(limen_renderer *r, const limen_draw_cmd *c)
{
    const int *vp = c->viewport;
    if (c->target == 0) {
        GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
        GL(Viewport)(r->origin[0] + vp[0], r->origin[1] + vp[1], vp[2], vp[3]);
        return true;
    }
    limen__target *t = limen__target_get(r, c->target, c->target_w, c->target_h);
    if (!t)
        return false;
    t->dirty = true;
    GL(BindFramebuffer)(GL_FRAMEBUFFER, t->fbo);
    GL(Viewport)(vp[0], vp[1], vp[2], vp[3]);
    return true;
}

limen_status limen__execute(limen_renderer *r, const limen_drawlist *dl)
{
    const limen_draw_cmd *cmds;
    const limen_draw_pass *passes;
    const limen_draw_instance *inst;
    const float (*verts)[3];
    const limen_drawable *items;
    int ncmd = limen_drawlist_commands(dl, &cmds);
    int npass = limen_drawlist_passes(dl, &passes);
    int ninst = limen_drawlist_instances(dl, &inst);
    int nvert = limen_drawlist_vertices(dl, &verts);
    int nitems = limen_drawables_items(r->draw, &items);
    lights_set(r, dl);
    if (!upload_polygons(r, verts, nvert))
        return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory for %d polygon vertices", nvert);
    GL(BindVertexArray)(r->vao);
    r->applied_valid = false;
    int pass = -1, target = 0;
    limen_status st = LIMEN_OK;
    for (int i = 0; i < ncmd && !st; i++) {
        const limen_draw_cmd *c = &cmds[i];
        if (c->pass != pass && c->pass >= 0 && c->pass < npass) {
            pass = c->pass;
            bind_pass(r, &passes[pass]);
        }
        const limen_draw_pass *p = pass >= 0 ? &passes[pass] : NULL;
        switch (c->op) {
        case LIMEN_DRAW_TARGET:
            if (!bind_target(r, c))
                st = limen__rfail(r, LIMEN_ERR_GL, "texture method: cannot make an offscreen "
                                                   "target");
            target = c->target;
            break;
        case LIMEN_DRAW_CLEAR:
            apply_state(r, &c->state, target, true);
            clear(r, c);
            break;
        case LIMEN_DRAW_POLYGON:
            if (c->first < 0 || c->count < 0 || c->first + c->count > nvert || !p)
                break;
            apply_state(r, &c->state, target, c->image != LIMEN_IMAGE_NONE);
            draw_polygon(r, c, p, target);
            break;
        case LIMEN_DRAW_SHAPE:
            if (c->item < 0 || c->item >= nitems || !p)
                break;
            apply_state(r, &c->state, target, true);
            draw_shape(r, c, p, &items[c->item]);
            break;
        case LIMEN_DRAW_MESHES:
            if (c->item < 0 || c->item >= nitems || !items[c->item].mesh || c->first < 0 ||
                c->count < 0 || c->first + c->count > ninst)
                break;
            apply_state(r, &c->state, target, true);
            draw_meshes(r, c, &items[c->item], inst + c->first);
            break;
        case LIMEN_DRAW_FLUSH:
            GL(Flush)();
            break;
        case LIMEN_DRAW_OP_COUNT:
            break;
        }
    }
    limen__samples_end(r);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    GL(Viewport)(r->origin[0], r->origin[1], r->width, r->height);
    GL(Disable)(GL_STENCIL_TEST);
    GL(Disable)(GL_SCISSOR_TEST);
    GL(Disable)(GL_BLEND);
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    GL(DepthMask)(GL_TRUE);
    GL(StencilMask)(0xFF);
    GL(FrontFace)(GL_CCW);
    return st;
}
