/* drawlist_batch.c - meshes in the draw list, in batches. The nodes of a view that show the
 * same geometry at the same level of detail, with the same normals and texture and no
 * checker, go in one MESHES command: one state change and one call for a thousand statues
 * instead of a thousand. What differs from node to node (the world matrix, the albedo) is an
 * instance. A batch is drawn where its nearest member stands in the view's nearest-first
 * order. The frame's triangle budget is spent here, so a backend draws what it is given. */
#include <stdlib.h>
#include <string.h>

#include "core/drawlist.h"

/* A mesh among the view's things, with what decides its batch. */
struct limen__dl_batch_item {
    const limen_mesh_geometry *mesh;
    const limen_image *texture;
    float repeat[2];            /* the texture's (limen_drawable.texture_repeat) */
    int filter;                 /* and its limen_drawable.texture_filter */
    int lod, smooth, solo;      /* solo: a checker's colours are uniforms, so it goes alone */
    int k;                      /* where it stands in the view's order */
    int node;                   /* its drawable */
};

struct limen__dl_batch {
    int first, count;           /* items of bitems */
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
    const struct limen__dl_batch_item *a = pa, *b = pb;
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

static bool same_batch(const struct limen__dl_batch_item *a, const struct limen__dl_batch_item *b)
{
    return a->mesh == b->mesh && a->lod == b->lod && a->smooth == b->smooth &&
           a->texture == b->texture && a->repeat[0] == b->repeat[0] &&
           a->repeat[1] == b->repeat[1] && a->filter == b->filter && !a->solo && !b->solo;
}

static int by_first(const void *pa, const void *pb, void *ctx)
{
    const struct limen__dl_batch_item *items = ctx;
    const struct limen__dl_batch *a = pa, *b = pb;
    return cmp_int(items[a->first].k, items[b->first].k);
}

static int mesh_lod(const limen_drawlist *dl, const dl_view *v, const limen_drawable *d)
{
    return limen_view_mesh_lod(v->pub, dl->height, d, dl->desc.limits.lod_pixels);
}

int limen__dl_batches_plan(limen_drawlist *dl, const dl_view *v, int n)
{
    if (!limen__reserve((void **)&dl->bitems, &dl->bitems_cap, n, sizeof *dl->bitems) ||
        !limen__reserve((void **)&dl->batches, &dl->batches_cap, n, sizeof *dl->batches)) {
        dl->nomem = true;
        return -1;
    }
    int m = 0;
    for (int k = 0; k < n; k++) {
        int i = dl->order[k].node;
        const limen_drawable *d = &dl->items[i];
        if (d->kind != LIMEN_NODE_MESH || !d->mesh || dl->clone_of[i] >= 0)
            continue;
        dl->bitems[m++] = (struct limen__dl_batch_item){
            .mesh = d->mesh, .texture = d->texture, .smooth = d->smooth != 0,
            .repeat = { d->texture ? d->texture_repeat[0] : 1, d->texture ? d->texture_repeat[1] : 1 },
            .filter = d->texture ? (int)d->texture_filter : 0,
            .solo = d->cell > 0, .k = k, .node = i, .lod = mesh_lod(dl, v, d),
        };
    }
    if (m > 1)
        qsort(dl->bitems, (size_t)m, sizeof *dl->bitems, by_batch);
    int nb = 0;
    for (int j = 0; j < m; j++) {
        if (nb && same_batch(&dl->bitems[j - 1], &dl->bitems[j])) {
            dl->batches[nb - 1].count++;
            continue;
        }
        dl->batches[nb++] = (struct limen__dl_batch){ j, 1 };
    }
    if (nb > 1)
        qsort_r(dl->batches, (size_t)nb, sizeof *dl->batches, by_first, dl->bitems);
    return nb;
}

int limen__dl_batch_first(const limen_drawlist *dl, int b)
{
    return dl->bitems[dl->batches[b].first].k;
}

/* Triangles of mesh g at level lod as a renderer keeps its levels (at most 16; a coarser one
 * asked for gets the last). */
static uint64_t level_triangles(const limen_mesh_geometry *g, int lod)
{
    if (!g->lods || g->lod_count < 1)
        return (uint64_t)g->triangle_count;
    int nlods = g->lod_count > 16 ? 16 : g->lod_count;
    lod = lod < 0 ? 0 : lod >= nlods ? nlods - 1 : lod;
    return (uint64_t)g->lods[lod].triangle_count;
}

/* The n instances just added to the list as one MESHES command of drawable d at level lod:
 * its opaque parts, or in the blend pass its blended ones. The frame's triangle budget: the
 * planner kept only the views that fit, but the camera's own view is always drawn, so the
 * meshes stop here at the budget (counted once, in the pass of the opaque parts). */
static void meshes_cmd(limen_drawlist *dl, const dl_view *v, const limen_drawable *d, int lod,
                       int n)
{
    const limen_mesh_geometry *g = d->mesh;
    if (dl->blend_pass && !g->has_blend)     /* (a plain mesh has no blended part) */
        return;
    uint64_t per = level_triangles(g, lod);
    if (!dl->blend_pass) {
        if (per * (uint64_t)n > dl->tris_left)
            n = per ? (int)(dl->tris_left / per) : n;
        dl->tris_left -= per * (uint64_t)n;
    }
    if (n <= 0)
        return;
    limen_draw_cmd *c = limen__dl_emit(dl, LIMEN_DRAW_MESHES);
    if (!c)
        return;
    c->item = (int)(d - dl->items);
    c->lod = lod;
    c->parts = dl->blend_pass ? LIMEN_PARTS_BLENDED : LIMEN_PARTS_OPAQUE;
    c->first = dl->ninst;
    c->count = n;
    c->state.depth_clamp = limen__dl_depth_clamped(v->pub, false);
    c->state.cull_back = 0;         /* meshes need not be closed: both sides show */
}

void limen__dl_batch_draw(limen_drawlist *dl, const dl_view *v, int b)
{
    const struct limen__dl_batch *bt = &dl->batches[b];
    const struct limen__dl_batch_item *it = &dl->bitems[bt->first];
    limen_draw_instance *inst = limen__dl_instances(dl, bt->count);
    if (!inst)
        return;
    for (int j = 0; j < bt->count; j++) {
        const limen_drawable *d = &dl->items[it[j].node];
        memcpy(inst[j].world, d->world, sizeof inst[j].world);
        memcpy(inst[j].color, d->color, sizeof inst[j].color);
    }
    int before = dl->ncmd;
    meshes_cmd(dl, v, &dl->items[it[0].node], it[0].lod, bt->count);
    if (dl->ncmd > before)
        dl->ninst += dl->cmd[dl->ncmd - 1].count;
}

void limen__dl_mesh(limen_drawlist *dl, const dl_view *v, const limen_drawable *d,
                    const float world[16], const float albedo[3])
{
    if (!d->mesh)
        return;
    limen_draw_instance *inst = limen__dl_instances(dl, 1);
    if (!inst)
        return;
    memcpy(inst->world, world, sizeof inst->world);
    memcpy(inst->color, albedo, sizeof inst->color);
    int before = dl->ncmd;
    meshes_cmd(dl, v, d, mesh_lod(dl, v, d), 1);
    if (dl->ncmd > before)
        dl->ninst += 1;
}

void limen__dl_batches_free(limen_drawlist *dl)
{
    free(dl->batches);
    free(dl->bitems);
    dl->batches = NULL;
    dl->bitems = NULL;
    dl->bitems_cap = dl->batches_cap = 0;
}
