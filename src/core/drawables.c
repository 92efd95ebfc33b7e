/* drawables.c - what a renderer draws: the nodes that draw or light, read from the scene in
 * one pass per frame into plain public structs. limen's own renderer draws from this list
 * and the plan alone, as a game's renderer does; nothing else of the scene is shared. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/mesh.h"
#include "core/texture.h"
#include "core/reserve.h"

struct limen_drawables {
    limen_drawable *items;
    int count, cap;
    int *slot_item;             /* per node slot: index in items, or -1 */
    int slots;                  /* entries of slot_item in use (the scene's slot count) */
    int slot_cap;
    float background[3];
    float ambient;
};

limen_status limen_drawables_create(limen_drawables **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    *out = calloc(1, sizeof **out);
    return *out ? LIMEN_OK : LIMEN_ERR_NOMEM;
}

void limen_drawables_destroy(limen_drawables *d)
{
    if (!d)
        return;
    free(d->items);
    free(d->slot_item);
    free(d);
}

/* What shows or lights (limen_drawables_build's list). */
static bool draws(limen_node_kind kind)
{
    const limen_kind_info *ki = limen_kind_get(kind);
    return ki->shape || ki->surface || ki->light;
}

void limen__drawable_read(const limen_scene *s, int slot, limen_drawable *it)
{
    const limen__node *n = &s->nodes[slot];
    memset(it, 0, sizeof *it);
    it->node = limen__node_handle(s, slot);
    it->kind = n->kind;
    it->visible = n->visible;
    memcpy(it->world, n->world, sizeof it->world);
    memcpy(it->dims, n->dims, sizeof it->dims);
    memcpy(it->color, n->color, sizeof it->color);
    memcpy(it->checker, n->checker_b, sizeof it->checker);
    it->cell = n->checker_cell;
    double c[3], r;
    limen__node_bounds(n, c, &r);
    for (int k = 0; k < 3; k++)
        it->centre[k] = (float)c[k];
    it->radius = (float)r;
    if (limen__is_surface(n)) {
        memcpy(it->tint, n->tint, sizeof it->tint);
        memcpy(it->back, n->back, sizeof it->back);
        memcpy(it->fill, n->fill, sizeof it->fill);
    }
    it->name = n->name;
    it->label = n->label;
    if (n->kind == LIMEN_NODE_LIGHT)
        it->range = n->range;
    if (n->kind == LIMEN_NODE_MESH && n->mesh) {
        it->mesh = &n->mesh->pub;
        it->smooth = n->smooth || n->mesh->file_normals;
    }
    /* a mesh's own textures are its materials' (limen_mesh_geometry.materials) */
    const limen__texture *tex = n->texture;
    if (tex && limen_kind_get(n->kind)->uv != LIMEN_UV_NONE)
        it->texture = &tex->pub;
    memcpy(it->texture_repeat, n->tex_repeat, sizeof it->texture_repeat);
    it->texture_filter = n->tex_filter;
}

/* Room for the scene's slots and its live nodes (the list's size is bounded by both). */
static bool grow(limen_drawables *d, const limen_scene *s)
{
    return limen__reserve((void **)&d->slot_item, &d->slot_cap, s->cap, sizeof *d->slot_item) &&
           limen__reserve((void **)&d->items, &d->cap, s->count, sizeof *d->items);
}

limen_status limen_drawables_build(limen_drawables *d, limen_scene *s)
{
    if (!d || !s)
        return LIMEN_ERR_ARG;
    d->count = d->slots = 0;
    limen_status st = limen__scene_check(s);
    if (st)
        return st;
    if (!grow(d, s))
        return limen__fail(s, LIMEN_ERR_NOMEM, "drawables: out of memory");
    for (int i = 0; i < s->cap; i++)
        d->slot_item[i] = -1;
    /* creation order, as the tracer and the planner walk the scene (it decides which lights
     * are the first LIMEN_MAX_LIGHTS) */
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        if (i < 0 || !draws(s->nodes[i].kind))
            continue;
        d->slot_item[i] = d->count;
        limen__drawable_read(s, i, &d->items[d->count++]);
    }
    d->slots = s->cap;
    memcpy(d->background, s->background, sizeof d->background);
    d->ambient = s->ambient;
    limen__meshes_framed(s);    /* the frame before is drawn: big meshes' levels may begin */
    return LIMEN_OK;
}

int limen_drawables_items(const limen_drawables *d, const limen_drawable **out)
{
    if (out)
        *out = d && d->count ? d->items : NULL;
    return d ? d->count : 0;
}

int limen_drawables_find(const limen_drawables *d, limen_node n)
{
    int slot = limen__node_get_index(n);
    if (!d || slot < 0 || slot >= d->slots)
        return -1;
    int i = d->slot_item[slot];
    return i >= 0 && d->items[i].node.id == n.id ? i : -1;
}

void limen_drawables_environment(const limen_drawables *d, float background[3], float *ambient)
{
    if (background) {
        for (int k = 0; k < 3; k++)
            background[k] = d ? d->background[k] : 0.0f;
    }
    if (ambient)
        *ambient = d ? d->ambient : 0.0f;
}
