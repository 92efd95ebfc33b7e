/* batch.c - meshes drawn in batches. The nodes of a view that show the same geometry at the
 * same level of detail, with the same normals and texture and no checker, go in one
 * instanced draw: one state change and one call for a thousand statues instead of a
 * thousand. What differs from node to node (the model matrix, the normal matrix, the
 * albedo) comes from an instance buffer, computed exactly as the one-node draws compute
 * their uniforms, so a node looks the same drawn either way. A batch is drawn where its
 * nearest member stands in the view's nearest-first order. */
#include <stdlib.h>
#include <string.h>

#include "gl/gl_internal.h"

typedef struct limen__instance {
    float model[16];
    float normal[9];            /* inverse transpose of the model's 3x3 part */
    float albedo[3];
} limen__instance;

_Static_assert(sizeof(limen__instance) == sizeof(float) * LIMEN__INSTANCE_FLOATS,
               "an instance is LIMEN__INSTANCE_FLOATS floats");

/* A mesh among the view's things, with what decides its batch. */
struct limen__batch_item {
    const limen_mesh_geometry *mesh;
    const limen_image *texture;
    float repeat[2];            /* the texture's (limen_drawable.texture_repeat) */
    int filter;                 /* and its limen_drawable.texture_filter */
    int lod, smooth, solo;      /* solo: a checker's colours are uniforms, so it goes alone */
    int k;                      /* where it stands in the view's order */
    int node;                   /* its drawable */
};

struct limen__batch {
    int first, count;           /* items of batch_items */
};

static int cmp_int(int a, int b)
{
    return (a > b) - (a < b);
}

static int cmp_ptr(const void *a, const void *b)
{
    return ((uintptr_t)a > (uintptr_t)b) - ((uintptr_t)a < (uintptr_t)b);
}

/* Members of a batch next to each other, nearest first; solo items alone. */
static int by_batch(const void *pa, const void *pb)
{
    const struct limen__batch_item *a = pa, *b = pb;
    int c = cmp_ptr(a->mesh, b->mesh);
    if (!c)
        c = cmp_int(a->lod, b->lod);
    if (!c)
        c = cmp_int(a->smooth, b->smooth);
    if (!c)
        c = cmp_ptr(a->texture, b->texture);
    for (int i = 0; i < 2 && !c; i++)
        c = (a->repeat[i] > b->repeat[i]) - (a->repeat[i] < b->repeat[i]);
    if (!c)
        c = cmp_int(a->filter, b->filter);
    if (!c)
        c = cmp_int(a->solo ? a->k : -1, b->solo ? b->k : -1);
    return c ? c : cmp_int(a->k, b->k);
}

static bool same_batch(const struct limen__batch_item *a, const struct limen__batch_item *b)
{
    return a->mesh == b->mesh && a->lod == b->lod && a->smooth == b->smooth &&
           a->texture == b->texture && a->repeat[0] == b->repeat[0] &&
           a->repeat[1] == b->repeat[1] && a->filter == b->filter && !a->solo && !b->solo;
}

static int by_first(const void *pa, const void *pb, void *ctx)
{
    const struct limen__batch_item *items = ctx;
    const struct limen__batch *a = pa, *b = pb;
    return cmp_int(items[a->first].k, items[b->first].k);
}

static bool grow(limen_renderer *r, int n)
{
    if (n <= r->batch_cap)
        return true;
    struct limen__batch_item *it = realloc(r->batch_items, sizeof *it * (size_t)n);
    if (!it)
        return false;
    r->batch_items = it;
    struct limen__batch *b = realloc(r->batches, sizeof *b * (size_t)n);
    if (!b)
        return false;
    r->batches = b;
    r->batch_cap = n;
    return true;
}

int limen__batches_plan(limen_renderer *r, const limen_view *v, const limen_drawable *items,
                        const struct limen__draw_key *order, int n)
{
    if (!grow(r, n))
        return -1;
    int m = 0;
    for (int k = 0; k < n; k++) {
        int i = order[k].node;
        const limen_drawable *d = &items[i];
        if (d->kind != LIMEN_NODE_MESH || !d->mesh || r->clone_of[i] >= 0)
            continue;
        r->batch_items[m++] = (struct limen__batch_item){
            .mesh = d->mesh, .texture = d->texture, .smooth = d->smooth != 0,
            .repeat = { d->texture ? d->texture_repeat[0] : 1, d->texture ? d->texture_repeat[1] : 1 },
            .filter = d->texture ? (int)d->texture_filter : 0,
            .solo = d->cell > 0, .k = k, .node = i,
            .lod = limen_view_mesh_lod(v, r->height, d, r->opts.limits.lod_pixels),
        };
    }
    if (m > 1)
        qsort(r->batch_items, (size_t)m, sizeof *r->batch_items, by_batch);
    int nb = 0;
    for (int j = 0; j < m; j++) {
        if (nb && same_batch(&r->batch_items[j - 1], &r->batch_items[j])) {
            r->batches[nb - 1].count++;
            continue;
        }
        r->batches[nb++] = (struct limen__batch){ j, 1 };
    }
    if (nb > 1)
        qsort_r(r->batches, (size_t)nb, sizeof *r->batches, by_first, r->batch_items);
    return nb;
}

int limen__batch_first(const limen_renderer *r, int b)
{
    return r->batch_items[r->batches[b].first].k;
}

static void instance_of(const float world[16], const float albedo[3], limen__instance *out)
{
    mat4 model;
    mat3 nm;
    memcpy(model, world, sizeof model);
    limen__normal_matrix(model, nm);
    memcpy(out->model, world, sizeof out->model);
    memcpy(out->normal, nm, sizeof out->normal);
    memcpy(out->albedo, albedo, sizeof out->albedo);
}

static bool instances(limen_renderer *r, int n)
{
    if (n <= r->inst_cap)
        return true;
    limen__instance *p = realloc(r->inst, sizeof *p * (size_t)n);
    if (!p)
        return false;
    r->inst = p;
    r->inst_cap = n;
    return true;
}

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

/* Draws r->inst[0..n) as copies of mesh drawable d at level lod (d gives the normals, the
 * texture and the checker), part by part where it has materials: the opaque and masked ones,
 * or in the blend pass (r->blend_pass) the blended ones. */
static void draw_instances(limen_renderer *r, const limen_view *v, const limen_drawable *d,
                           int lod, int n)
{
    const limen_mesh_geometry *g = d->mesh;
    bool simple = plain(g);
    if (r->blend_pass && (simple || !g->has_blend))
        return;
    GLint first;
    GLsizei count;
    bool indexed;
    if (!limen__gpu_mesh_bind(r, g, d->smooth, lod, &first, &count, &indexed))
        return;
    /* the frame's triangle budget: the planner kept only the views that fit, but the
     * camera's own view is always drawn, so its meshes stop here at the budget (counted
     * once, in the pass of the opaque parts) */
    uint64_t per = (uint64_t)(count / 3);
    if (!r->blend_pass) {
        if (per * (uint64_t)n > r->mesh_tris_left)
            n = per ? (int)(r->mesh_tris_left / per) : n;
        r->mesh_tris_left -= per * (uint64_t)n;
    }
    int level = limen__gpu_mesh_level(g, lod);
    const limen_mesh_part *parts = g->lods && g->lod_count > 0 && g->lods[level].parts
                                       ? g->lods[level].parts : g->parts;
    int nparts = n <= 0 ? 0 : simple || !parts ? 1 : g->part_count;
    int checker = d->cell > 0 ? 2 : 0;
    if (limen__depth_clamped(v, false))
        GL(Enable)(GL_DEPTH_CLAMP);
    else
        GL(Disable)(GL_DEPTH_CLAMP);
    GL(Disable)(GL_CULL_FACE);      /* meshes need not be closed: both sides show */
    bool uploaded = false;
    for (int p = 0; p < nparts; p++) {
        const limen_material *mt = simple ? NULL : &g->materials[parts[p].material];
        if (mt && (mt->alpha_mode == LIMEN_ALPHA_BLEND) != r->blend_pass)
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
            GLsizeiptr size = (GLsizeiptr)(sizeof(limen__instance) * (size_t)n);
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

void limen__batch_draw(limen_renderer *r, const limen_view *v, const limen_drawable *items, int b)
{
    const struct limen__batch *bt = &r->batches[b];
    const struct limen__batch_item *it = &r->batch_items[bt->first];
    if (!instances(r, bt->count)) {
        /* one at a time then */
        for (int j = 0; j < bt->count; j++)
            limen__mesh_draw(r, v, &items[it[j].node], items[it[j].node].world,
                             items[it[j].node].color);
        return;
    }
    for (int j = 0; j < bt->count; j++) {
        const limen_drawable *d = &items[it[j].node];
        instance_of(d->world, d->color, &r->inst[j]);
    }
    draw_instances(r, v, &items[it[0].node], it[0].lod, bt->count);
}

void limen__mesh_draw(limen_renderer *r, const limen_view *v, const limen_drawable *d,
                      const float world[16], const float albedo[3])
{
    if (!d->mesh || !instances(r, 1))
        return;
    instance_of(world, albedo, &r->inst[0]);
    draw_instances(r, v, d, limen_view_mesh_lod(v, r->height, d, r->opts.limits.lod_pixels), 1);
}

void limen__batches_free(limen_renderer *r)
{
    free(r->inst);
    free(r->batches);
    free(r->batch_items);
    r->inst = NULL;
    r->batches = NULL;
    r->batch_items = NULL;
    r->inst_cap = r->batch_cap = 0;
}
