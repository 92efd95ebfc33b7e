/* scene.c - the scene graph: a pool of nodes with generation-checked handles, local
 * transforms, parents and world matrices. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/kinds.h"
#include "core/mesh.h"
#include "core/reserve.h"
#include "core/texture.h"

/* The pool grows by doubling up to this many slots (an index must fit a handle's low 32
 * bits and an int). */
#define MAX_SLOTS (INT32_MAX / 2)

/* ------------------------------------------------------------------ handles */

static limen_node make_handle(uint32_t index, uint32_t gen)
{
    return (limen_node){ ((uint64_t)gen << 32) | ((uint64_t)index + 1u) };
}

limen_node limen__node_handle(const limen_scene *s, int index)
{
    return make_handle((uint32_t)index, s->nodes[index].gen);
}

/* The slot of handle n's live node, or -1. */
static int live_slot(const limen_scene *s, limen_node n)
{
    if (!s || !n.id)
        return -1;
    uint64_t index = (n.id & 0xFFFFFFFFu) - 1u;
    if (index >= (uint64_t)s->cap)
        return -1;
    const limen__node *node = &s->nodes[index];
    if (!(node->gen & 1u) || node->gen != (uint32_t)(n.id >> 32))
        return -1;
    return (int)index;
}

const limen__node *limen__node_get(const limen_scene *s, limen_node n)
{
    int i = live_slot(s, n);
    return i >= 0 ? &s->nodes[i] : NULL;
}

limen_status limen__node_lookup(limen_scene *s, limen_node n, unsigned kinds, const char *what,
                                const char *fn, limen__node **out)
{
    *out = NULL;
    if (!s)
        return LIMEN_ERR_ARG;
    int slot = live_slot(s, n);
    limen__node *node = slot >= 0 ? &s->nodes[slot] : NULL;
    if (!node)
        return limen__fail(s, LIMEN_ERR_HANDLE, "%s: %s node handle", fn,
                           n.id ? "stale or foreign" : "null");
    if (kinds && !(kinds & LIMEN__KIND(node->kind)))
        return limen__fail(s, LIMEN_ERR_HANDLE, "%s: '%s' is not %s", fn, limen__node_title(node),
                           what);
    *out = node;
    return LIMEN_OK;
}

limen_status limen__node_lookup_const(const limen_scene *s, limen_node n, unsigned kinds,
                                      const limen__node **out)
{
    *out = NULL;
    if (!s)
        return LIMEN_ERR_ARG;
    const limen__node *node = limen__node_get(s, n);
    if (!node || (kinds && !(kinds & LIMEN__KIND(node->kind))))
        return LIMEN_ERR_HANDLE;
    *out = node;
    return LIMEN_OK;
}

/* Message prefix for a node: "label: kind 'name'" ("label: kind" if it has no name). */
static void node_desc(const limen__node *node, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s%s%s%s", node->label, node->label[0] ? ": " : "",
             limen__kind_name(node->kind), node->name[0] ? " '" : "", node->name,
             node->name[0] ? "'" : "");
}

/* ------------------------------------------------------------------ scene */

limen_status limen_scene_create(const limen_scene_desc *desc, limen_scene **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    *out = NULL;
    int max_nodes = desc && desc->max_nodes > 0 ? desc->max_nodes : 0;
    if (desc && desc->max_nodes < 0)
        return LIMEN_ERR_ARG;
    limen_scene *s = calloc(1, sizeof *s);
    if (!s)
        return LIMEN_ERR_NOMEM;
    s->max_nodes = max_nodes;
    s->ambient = 0.2f;
    *out = s;
    return LIMEN_OK;
}

void limen_scene_destroy(limen_scene *s)
{
    if (!s)
        return;
    limen__meshes_destroy(s);
    limen__textures_destroy(s);
    limen__index_free(s);
    free(s->nodes);
    free(s->free_ring);
    free(s->live);
    free(s->stale_list);
    free(s);
}

limen_status limen_scene_set_background(limen_scene *s, const float rgb[3])
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!rgb || !limen__finite3(rgb) || rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0 || rgb[0] > 1 ||
        rgb[1] > 1 || rgb[2] > 1)
        return limen__fail(s, LIMEN_ERR_ARG, "background: colour components must be in [0, 1]");
    glm_vec3_copy((float *)rgb, s->background);
    return LIMEN_OK;
}

limen_status limen_scene_set_ambient(limen_scene *s, float ambient)
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!(ambient >= 0 && ambient <= 1))
        return limen__fail(s, LIMEN_ERR_ARG, "ambient: must be in [0, 1] (got %g)", ambient);
    s->ambient = ambient;
    return LIMEN_OK;
}

void limen_scene_get_background(const limen_scene *s, float rgb[3])
{
    if (s && rgb)
        memcpy(rgb, s->background, sizeof(float) * 3);
}

float limen_scene_get_ambient(const limen_scene *s)
{
    return s ? s->ambient : 0.0f;
}

limen_status limen_scene_set_camera(limen_scene *s, limen_node camera)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, camera, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (node->kind != LIMEN_NODE_CAMERA)
        return limen__fail(s, LIMEN_ERR_HANDLE, "set_camera: node '%s' is a %s, not a camera",
                           limen__node_title(node), limen__kind_name(node->kind));
    s->camera = (uint32_t)(node - s->nodes) + 1u;
    return LIMEN_OK;
}

limen_node limen_scene_get_camera(const limen_scene *s)
{
    if (!s || !s->camera)
        return (limen_node){ 0 };
    return limen__node_handle(s, (int)s->camera - 1);
}

int limen_scene_node_count(const limen_scene *s)
{
    return s ? s->count : 0;
}

int limen_scene_nodes(const limen_scene *s, limen_node *out, int max)
{
    if (!s)
        return 0;
    int n = 0;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0)
            continue;
        if (out && n < max)
            out[n] = limen__node_handle(s, i);
        n++;
    }
    return n;
}

/* ------------------------------------------------------------------ world matrices */

/* The largest and smallest length of the world matrix's three axes. */
static void world_scale(const limen__node *n, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = 0;
    for (int c = 0; c < 3; c++) {
        double l = sqrt((double)n->world[c][0] * n->world[c][0] +
                        (double)n->world[c][1] * n->world[c][1] +
                        (double)n->world[c][2] * n->world[c][2]);
        *lo = fmin(*lo, l);
        *hi = fmax(*hi, l);
    }
}

limen_status limen__scene_check(limen_scene *s)
{
    limen__scene_refresh(s);
    if (s->dirty)
        return limen__fail(s, LIMEN_ERR_NOMEM, "out of memory");
    char title[256];
    int bad = limen__scene_bad_world(s);
    if (bad >= 0) {
        node_desc(&s->nodes[bad], title, sizeof title);
        return limen__fail(s, LIMEN_ERR_ARG,
                           "%s: its world transform is not finite (the scales along its "
                           "parent chain multiply past what a float holds)", title);
    }
    /* The views through cameras, mirrors and portals invert their world matrices; scales
     * multiplied along a parent chain past the bounds each node keeps (1e-9 three times)
     * would give view matrices out of a float's range. Planner, renderer, tracer and ray
     * casts all refuse them here, with one message. (The slack covers the rounding of
     * products of in-range scales.) */
    for (int k = 0; k < s->live_len; k++) {
        if (s->live[k] < 0)
            continue;
        const limen__node *n = &s->nodes[s->live[k]];
        if (n->kind != LIMEN_NODE_CAMERA && !limen__is_surface(n))
            continue;
        double lo, hi;
        world_scale(n, &lo, &hi);
        if (lo >= LIMEN_MIN_SIZE * (1 - 1e-6) && hi <= LIMEN_MAX_MAGNITUDE * (1 + 1e-6))
            continue;
        node_desc(n, title, sizeof title);
        return limen__fail(s, LIMEN_ERR_ARG,
                           "%s: its world transform scales it by %g (the scales along its "
                           "parent chain must keep a camera, mirror or portal between 1e-9 and "
                           "1e9)", title, lo < LIMEN_MIN_SIZE ? lo : hi);
    }
    return LIMEN_OK;
}

limen_status limen_scene_update(limen_scene *s)
{
    if (!s)
        return LIMEN_ERR_ARG;
    limen__scene_refresh(s);
    return s->dirty ? limen__fail(s, LIMEN_ERR_NOMEM, "scene_update: out of memory") : LIMEN_OK;
}

/* ------------------------------------------------------------------ nodes */

/* Names go into messages and JSON plans: well-formed UTF-8 only. */
static bool valid_utf8(const char *str)
{
    const unsigned char *p = (const unsigned char *)str;
    while (*p) {
        int n = *p < 0x80 ? 0 : (*p & 0xE0) == 0xC0 ? 1 : (*p & 0xF0) == 0xE0 ? 2
                : (*p & 0xF8) == 0xF0 ? 3 : -1;
        if (n < 0 || (n == 1 && *p < 0xC2))
            return false;
        unsigned cp = n ? *p & (0x3F >> n) : *p;
        for (int i = 1; i <= n; i++) {
            if ((p[i] & 0xC0) != 0x80)
                return false;
            cp = (cp << 6) | (p[i] & 0x3F);
        }
        if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) ||
            (cp >= 0xD800 && cp <= 0xDFFF))
            return false;
        p += n + 1;
    }
    return true;
}

static void node_defaults(limen__node *node, limen_node_kind kind)
{
    uint32_t gen = node->gen;
    memset(node, 0, sizeof *node);
    node->gen = gen;
    node->kind = kind;
    glm_vec3_one(node->scale);
    glm_mat3_identity(node->facing);
    glm_vec3_one(node->color);
    node->visible = true;
    node->tex_repeat[0] = node->tex_repeat[1] = 1.0f;
    memcpy(node->dims, limen_kind_get(kind)->dims, sizeof node->dims);
    glm_vec3_one(node->tint);
    glm_vec3_broadcast(0.5f, node->back);
    glm_vec3_zero(node->fill);
    node->max_depth = 8;
    node->fovy = glm_rad(60.0f);
    node->znear = 0.05f;
    node->zfar = 100.0f;
}

/* Doubles the pool (and the free ring, which holds at most every slot). */
static bool grow(limen_scene *s)
{
    if (s->cap >= MAX_SLOTS)
        return false;
    int cap = s->cap ? (s->cap > MAX_SLOTS / 2 ? MAX_SLOTS : s->cap * 2) : 64;
    limen__node *nodes = realloc(s->nodes, sizeof *nodes * (size_t)cap);
    if (!nodes)
        return false;
    s->nodes = nodes;
    uint32_t *ring = malloc(sizeof *ring * (size_t)cap);
    if (!ring)
        return false;
    int n = 0;
    for (int k = 0; k < s->free_count; k++)
        ring[n++] = s->free_ring[(s->free_head + k) % s->cap];
    for (int i = s->cap; i < cap; i++) {
        nodes[i].gen = 0;
        ring[n++] = (uint32_t)i;
    }
    free(s->free_ring);
    s->free_ring = ring;
    s->free_head = 0;
    s->free_count = n;
    s->cap = cap;
    return true;
}

/* Drops the holes from the live list, keeping creation order. */
static void compact_live(limen_scene *s)
{
    int n = 0;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0)
            continue;
        s->nodes[i].live_at = n;
        s->live[n++] = i;
    }
    s->live_len = n;
    s->live_holes = 0;
}

static bool push_live(limen_scene *s, int index)
{
    if (s->live_len == s->live_cap && s->live_holes)
        compact_live(s);
    if (!limen__reserve((void **)&s->live, &s->live_cap, s->live_len + 1, sizeof *s->live))
        return false;
    s->nodes[index].live_at = s->live_len;
    s->live[s->live_len++] = index;
    return true;
}

limen_status limen_node_create(limen_scene *s, limen_node_kind kind, const char *name,
                               limen_node *out)
{
    if (!s || !out)
        return LIMEN_ERR_ARG;
    out->id = 0;
    if ((unsigned)kind >= LIMEN_NODE_KIND_COUNT)
        return limen__fail(s, LIMEN_ERR_ARG, "node_create: unknown kind %d", (int)kind);
    if (name && !valid_utf8(name))
        return limen__fail(s, LIMEN_ERR_ARG, "node_create: the name is not valid UTF-8");
    if (s->max_nodes && s->count >= s->max_nodes)
        return limen__fail(s, LIMEN_ERR_NOMEM, "node_create: more than %d nodes", s->max_nodes);
    if (!s->free_count && !grow(s))
        return limen__fail(s, LIMEN_ERR_NOMEM, "node_create: out of memory (%d nodes)",
                           s->count);
    uint32_t index = s->free_ring[s->free_head];
    if (!push_live(s, (int)index))
        return limen__fail(s, LIMEN_ERR_NOMEM, "node_create: out of memory (%d nodes)",
                           s->count);
    s->free_head = (s->free_head + 1) % s->cap;
    s->free_count--;
    limen__node *node = &s->nodes[index];
    int live_at = node->live_at;
    node->gen++;    /* odd: alive, a value this slot never had */
    node_defaults(node, kind);
    node->live_at = live_at;
    if (name)
        snprintf(node->name, sizeof node->name, "%s", name);
    s->count++;
    limen__node_touch(s, node);
    limen__scene_restructure(s, (int)index);
    *out = make_handle(index, node->gen);
    return LIMEN_OK;
}

limen_status limen_node_destroy(limen_scene *s, limen_node n)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    uint32_t self = (uint32_t)(node - s->nodes) + 1u;
    for (int k = 0; k < s->live_len && node->nchildren > 0; k++) {
        int i = s->live[k];
        if (i >= 0 && s->nodes[i].parent == self) {
            s->nodes[i].parent = node->parent;
            node->nchildren--;
            if (node->parent)
                s->nodes[node->parent - 1].nchildren++;
            limen__node_touch(s, &s->nodes[i]);
        }
    }
    if (node->parent)
        s->nodes[node->parent - 1].nchildren--;
    if (node->bad_world)
        s->nbad--;
    node->bad_world = false;
    if (s->camera == self)
        s->camera = 0;
    if (node->pair)
        s->nodes[node->pair - 1].pair = 0;
    limen__mesh_release(s, node->mesh);
    node->mesh = NULL;
    limen__texture_release(s, node->texture);
    node->texture = NULL;
    s->live[node->live_at] = -1;
    if (++s->live_holes > s->count)
        compact_live(s);
    /* even: dead. The last odd value (UINT32_MAX) retires the slot: it stays dead, off the
     * free ring, so its generation never wraps back to one a handle still holds. */
    if (node->gen != UINT32_MAX) {
        node->gen++;
        s->free_ring[(s->free_head + s->free_count) % s->cap] = self - 1u;
        s->free_count++;
    } else {
        node->gen = 0;
    }
    s->count--;
    s->dirty = true;
    limen__scene_restructure(s, (int)(self - 1u));
    return LIMEN_OK;
}

int limen_node_valid(const limen_scene *s, limen_node n)
{
    return limen__node_get(s, n) != NULL;
}

limen_status limen_node_find(const limen_scene *s, const char *name, limen_node *out)
{
    if (!s || !name || !out)
        return LIMEN_ERR_ARG;
    out->id = 0;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i >= 0 && strcmp(s->nodes[i].name, name) == 0) {
            *out = limen__node_handle(s, i);
            return LIMEN_OK;
        }
    }
    return LIMEN_ERR_HANDLE;   /* a const reader: no message (see limen_scene_error) */
}

const char *limen_node_get_name(const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    return node ? node->name : NULL;
}

limen_node_kind limen_node_get_kind(const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    return node ? node->kind : LIMEN_NODE_KIND_COUNT;
}

limen_status limen_node_set_label(limen_scene *s, limen_node n, const char *label)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    snprintf(node->label, sizeof node->label, "%s", label ? label : "");
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ hierarchy */

/* Re-links a node (parent = index + 1, 0 for none), keeping the child counts that tell
 * the refresh whether a subtree moves with it. */
static void set_parent_slot(limen_scene *s, limen__node *node, uint32_t parent)
{
    if (node->parent)
        s->nodes[node->parent - 1].nchildren--;
    node->parent = parent;
    if (parent)
        s->nodes[parent - 1].nchildren++;
    limen__node_touch(s, node);
}

limen_status limen_node_set_parent(limen_scene *s, limen_node n, limen_node parent)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    uint32_t self = (uint32_t)(node - s->nodes) + 1u;
    if (!parent.id) {
        set_parent_slot(s, node, 0);
        return LIMEN_OK;
    }
    limen__node *p;
    if ((found = limen__node_lookup(s, parent, 0, NULL, "set_parent", &p)))
        return found;
    uint32_t pi = (uint32_t)(p - s->nodes) + 1u;
    for (uint32_t at = pi; at; at = s->nodes[at - 1].parent) {
        if (at == self) {
            char d[256];
            node_desc(node, d, sizeof d);
            return limen__fail(s, LIMEN_ERR_CYCLE,
                               "%s: parent '%s' would make a cycle in the parent chain", d,
                               limen__node_title(p));
        }
    }
    set_parent_slot(s, node, pi);
    return LIMEN_OK;
}

limen_node limen_node_get_parent(const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    if (!node || !node->parent)
        return (limen_node){ 0 };
    return limen__node_handle(s, (int)node->parent - 1);
}

/* ------------------------------------------------------------------ transforms */

/* One validation for C and Lua alike (the bindings call these setters): see "NUMBERS" in
 * limen.h for why the bounds are where they are. */
static limen_status check_vec(limen_scene *s, const float *v, const char *what)
{
    if (!v || !limen__finite3(v))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: needs three finite numbers", what);
    for (int i = 0; i < 3; i++)
        if (fabsf(v[i]) > LIMEN_MAX_MAGNITUDE)
            return limen__fail(s, LIMEN_ERR_ARG, "%s: components must be numbers from -1e9 to "
                               "1e9 (got %g)", what, v[i]);
    return LIMEN_OK;
}

/* n sizes (or scales, distances): positive, from LIMEN_MIN_SIZE to LIMEN_MAX_MAGNITUDE. */
static limen_status check_sizes(limen_scene *s, const float *v, int n, const char *what)
{
    if (!v)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: NULL", what);
    for (int i = 0; i < n; i++)
        if (!(v[i] >= LIMEN_MIN_SIZE && v[i] <= LIMEN_MAX_MAGNITUDE))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: must be %s from 1e-9 to 1e9 (got %g)", what,
                               n > 1 ? "positive numbers" : "a positive number", v[i]);
    return LIMEN_OK;
}

#define CHECK_VEC(s, v, what)                                                            \
    do {                                                                                 \
        limen_status st_ = check_vec((s), (v), (what));                                  \
        if (st_)                                                                         \
            return st_;                                                                  \
    } while (0)

/* Leaves TRS mode untouched but stops using an explicit local matrix. */
static void to_trs(limen_scene *s, limen__node *node)
{
    node->explicit_local = false;
    limen__node_touch(s, node);
}

limen_status limen_node_set_position(limen_scene *s, limen_node n, const float p[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    CHECK_VEC(s, p, "position");
    glm_vec3_copy((float *)p, node->pos);
    to_trs(s, node);
    return LIMEN_OK;
}

limen_status limen_node_set_rotation(limen_scene *s, limen_node n, const float xyz[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    CHECK_VEC(s, xyz, "rotation");
    glm_vec3_copy((float *)xyz, node->euler);
    to_trs(s, node);
    return LIMEN_OK;
}

/* Basis whose +Z is normal and whose +Y leans towards up. */
static limen_status facing_basis(limen_scene *s, const float normal[3], const float up[3],
                                 mat3 out)
{
    CHECK_VEC(s, normal, "normal");
    if (up)
        CHECK_VEC(s, up, "up");
    vec3 z, x, y, u;
    glm_vec3_copy((float *)normal, z);
    float len = glm_vec3_norm(z);
    if (!(len > 1e-12f))
        return limen__fail(s, LIMEN_ERR_DEGENERATE, "normal: must not be zero");
    glm_vec3_scale(z, 1.0f / len, z);
    if (up) {
        glm_vec3_copy((float *)up, u);
    } else if (fabsf(z[1]) > 0.999f) {
        glm_vec3_copy((vec3){ 0, 0, -1 }, u);
    } else {
        glm_vec3_copy((vec3){ 0, 1, 0 }, u);
    }
    glm_vec3_cross(u, z, x);
    float xl = glm_vec3_norm(x), ul = glm_vec3_norm(u);
    if (!(xl > 1e-6f * ul))
        return limen__fail(s, LIMEN_ERR_DEGENERATE,
                           "up: must not be zero or parallel to the normal");
    glm_vec3_scale(x, 1.0f / xl, x);
    glm_vec3_cross(z, x, y);
    glm_vec3_copy(x, out[0]);
    glm_vec3_copy(y, out[1]);
    glm_vec3_copy(z, out[2]);
    return LIMEN_OK;
}

limen_status limen_node_set_facing(limen_scene *s, limen_node n, const float normal[3],
                                   const float up[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    mat3 f;
    limen_status st = facing_basis(s, normal, up, f);
    if (st)
        return st;
    glm_mat3_copy(f, node->facing);
    to_trs(s, node);
    return LIMEN_OK;
}

limen_status limen_node_set_scale(limen_scene *s, limen_node n, const float xyz[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    /* positive: a mirrored node would turn its faces inside out for the renderer's culling */
    limen_status st = check_sizes(s, xyz, 3, "scale");
    if (st)
        return st;
    glm_vec3_copy((float *)xyz, node->scale);
    to_trs(s, node);
    return LIMEN_OK;
}

limen_status limen_node_set_local_matrix(limen_scene *s, limen_node n, const float m[16])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (!m)
        return limen__fail(s, LIMEN_ERR_ARG, "local matrix: NULL");
    mat4 l;
    for (int i = 0; i < 16; i++) {
        if (!isfinite(m[i]))
            return limen__fail(s, LIMEN_ERR_ARG, "local matrix: element %d is not finite", i);
        if (fabsf(m[i]) > LIMEN_MAX_MAGNITUDE)
            return limen__fail(s, LIMEN_ERR_ARG, "local matrix: element %d must be from -1e9 to "
                               "1e9 (got %g)", i, m[i]);
        l[i / 4][i % 4] = m[i];
    }
    float det = glm_mat4_det(l);
    if (fabsf(det) < 1e-12f)
        return limen__fail(s, LIMEN_ERR_DEGENERATE, "local matrix: singular");
    if (det < 0)
        return limen__fail(s, LIMEN_ERR_ARG, "local matrix: must not mirror (its determinant "
                           "is %g; scales must be positive)", det);
    glm_mat4_copy(l, node->local);
    node->explicit_local = true;
    limen__node_touch(s, node);
    return LIMEN_OK;
}

limen_status limen_node_look_at(limen_scene *s, limen_node n, const float eye[3],
                                const float target[3], const float up[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    CHECK_VEC(s, eye, "eye");
    CHECK_VEC(s, target, "target");
    vec3 back;
    glm_vec3_sub((float *)eye, (float *)target, back);
    if (!(glm_vec3_norm(back) > 1e-9f))
        return limen__fail(s, LIMEN_ERR_DEGENERATE, "look_at: eye and target coincide");
    mat3 f;
    limen_status st = facing_basis(s, back, up, f);
    if (st)
        return st;
    glm_mat3_copy(f, node->facing);
    glm_vec3_zero(node->euler);
    glm_vec3_copy((float *)eye, node->pos);
    to_trs(s, node);
    return LIMEN_OK;
}

limen_status limen_node_get_position(const limen_scene *s, limen_node n, float p[3])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!p)
        return LIMEN_ERR_ARG;
    if (node->explicit_local)
        memcpy(p, node->local[3], sizeof(float) * 3);
    else
        memcpy(p, node->pos, sizeof(float) * 3);
    return LIMEN_OK;
}

limen_status limen_node_get_rotation(const limen_scene *s, limen_node n, float xyz[3])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!xyz)
        return LIMEN_ERR_ARG;
    memcpy(xyz, node->euler, sizeof(float) * 3);
    return LIMEN_OK;
}

limen_status limen_node_get_scale(const limen_scene *s, limen_node n, float xyz[3])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!xyz)
        return LIMEN_ERR_ARG;
    memcpy(xyz, node->scale, sizeof(float) * 3);
    return LIMEN_OK;
}

static void mat_out(mat4 m, float out[16])
{
    for (int i = 0; i < 16; i++)
        out[i] = m[i / 4][i % 4];
}

limen_status limen_node_get_local_matrix(limen_scene *s, limen_node n, float m[16])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (!m)
        return LIMEN_ERR_ARG;
    limen__node_compose_local(node);
    mat_out(node->local, m);
    return LIMEN_OK;
}

limen_status limen_node_world_matrix(limen_scene *s, limen_node n, float m[16])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (!m)
        return LIMEN_ERR_ARG;
    limen__scene_refresh(s);
    if (s->dirty)
        return limen__fail(s, LIMEN_ERR_NOMEM, "world matrix: out of memory");
    mat_out(node->world, m);
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ appearance */

limen_status limen_node_set_dims(limen_scene *s, limen_node n, const float dims[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    CHECK_VEC(s, dims, "dims");
    int used = limen_kind_get(node->kind)->size;
    if (!used)
        return limen__fail(s, LIMEN_ERR_ARG, "dims: a %s has no size",
                           limen__kind_name(node->kind));
    for (int i = 0; i < used; i++)
        if (!(dims[i] >= LIMEN_MIN_SIZE && dims[i] <= LIMEN_MAX_MAGNITUDE))
            return limen__fail(s, LIMEN_ERR_ARG, "dims: %s size %d must be a positive number "
                               "from 1e-9 to 1e9 (got %g)", limen__kind_name(node->kind), i,
                               dims[i]);
    for (int i = 0; i < 3; i++)
        node->dims[i] = i < used ? dims[i] : 0.0f;
    limen__node_touch(s, node);     /* its bounds changed */
    return LIMEN_OK;
}

limen_status limen_node_get_dims(const limen_scene *s, limen_node n, float dims[3])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!dims)
        return LIMEN_ERR_ARG;
    memcpy(dims, node->dims, sizeof(float) * 3);
    return LIMEN_OK;
}

static limen_status check_color(limen_scene *s, const float rgb[3], bool unit, const char *what)
{
    CHECK_VEC(s, rgb, what);
    for (int i = 0; i < 3; i++)
        if (rgb[i] < 0 || (unit && rgb[i] > 1))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: components must be in [0, %s] (got %g)",
                               what, unit ? "1" : "1e9", rgb[i]);
    return LIMEN_OK;
}

limen_status limen_node_set_color(limen_scene *s, limen_node n, const float rgb[3])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    limen_status st = check_color(s, rgb, !limen_kind_get(node->kind)->light, "color");
    if (st)
        return st;
    glm_vec3_copy((float *)rgb, node->color);
    return LIMEN_OK;
}

limen_status limen_node_get_color(const limen_scene *s, limen_node n, float rgb[3])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!rgb)
        return LIMEN_ERR_ARG;
    memcpy(rgb, node->color, sizeof(float) * 3);
    return LIMEN_OK;
}

limen_status limen_node_set_checker(limen_scene *s, limen_node n, const float a[3],
                                    const float b[3], float cell)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (!(cell == 0 || (cell >= LIMEN_MIN_SIZE && cell <= LIMEN_MAX_MAGNITUDE)))
        return limen__fail(s, LIMEN_ERR_ARG, "checker: cell size must be 0 or a positive number "
                           "from 1e-9 to 1e9 (got %g)", cell);
    if (cell == 0) {
        node->checker_cell = 0;
        return LIMEN_OK;
    }
    limen_status st = check_color(s, a, true, "checker colour a");
    if (!st)
        st = check_color(s, b, true, "checker colour b");
    if (st)
        return st;
    glm_vec3_copy((float *)a, node->color);
    glm_vec3_copy((float *)b, node->checker_b);
    node->checker_cell = cell;
    return LIMEN_OK;
}

limen_status limen_node_set_texture_repeat(limen_scene *s, limen_node n, const float repeat[2])
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    limen_status st = check_sizes(s, repeat, 2, "texture repeat");
    if (st)
        return st;
    node->tex_repeat[0] = repeat[0];
    node->tex_repeat[1] = repeat[1];
    return LIMEN_OK;
}

limen_status limen_node_get_texture_repeat(const limen_scene *s, limen_node n, float repeat[2])
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!repeat)
        return LIMEN_ERR_ARG;
    repeat[0] = node->tex_repeat[0];
    repeat[1] = node->tex_repeat[1];
    return LIMEN_OK;
}

limen_status limen_node_set_texture_filter(limen_scene *s, limen_node n,
                                          limen_texture_filter filter)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (filter != LIMEN_FILTER_TRILINEAR && filter != LIMEN_FILTER_LINEAR &&
        filter != LIMEN_FILTER_NEAREST)
        return limen__fail(s, LIMEN_ERR_ARG, "texture filter: %d is not one of "
                           "LIMEN_FILTER_TRILINEAR, LINEAR, NEAREST", (int)filter);
    node->tex_filter = filter;
    return LIMEN_OK;
}

limen_status limen_node_get_texture_filter(const limen_scene *s, limen_node n,
                                          limen_texture_filter *filter)
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (!filter)
        return LIMEN_ERR_ARG;
    *filter = node->tex_filter;
    return LIMEN_OK;
}

limen_status limen_node_get_checker(const limen_scene *s, limen_node n, float a[3], float b[3],
                                    float *cell)
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, 0, &node);
    if (found)
        return found;
    if (a)
        memcpy(a, node->color, sizeof(float) * 3);
    if (b)
        memcpy(b, node->checker_b, sizeof(float) * 3);
    if (cell)
        *cell = node->checker_cell;
    return LIMEN_OK;
}

limen_status limen_node_set_visible(limen_scene *s, limen_node n, int visible)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    node->visible = visible != 0;
    return LIMEN_OK;
}

int limen_node_get_visible(const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    return node ? node->visible : 0;
}

limen_status limen_light_set_range(limen_scene *s, limen_node n, float range)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (node->kind != LIMEN_NODE_LIGHT)
        return limen__fail(s, LIMEN_ERR_HANDLE, "range: '%s' is a %s, not a light",
                           limen__node_title(node), limen__kind_name(node->kind));
    if (!(range == 0 || (range >= LIMEN_MIN_SIZE && range <= LIMEN_MAX_MAGNITUDE)))
        return limen__fail(s, LIMEN_ERR_ARG, "range: must be 0 (none) or a positive number "
                           "from 1e-9 to 1e9 (got %g)", range);
    node->range = range;
    return LIMEN_OK;
}

float limen_light_get_range(const limen_scene *s, limen_node n)
{
    const limen__node *node = limen__node_get(s, n);
    return node && node->kind == LIMEN_NODE_LIGHT ? node->range : 0.0f;
}

/* ------------------------------------------------------------------ cameras */

limen_status limen_camera_set_lens(limen_scene *s, limen_node cam, float fovy, float znear,
                                   float zfar)
{
    limen__node *node;
    limen_status found = limen__node_lookup(s, cam, 0, NULL, __func__, &node);
    if (found)
        return found;
    if (node->kind != LIMEN_NODE_CAMERA)
        return limen__fail(s, LIMEN_ERR_HANDLE, "camera lens: '%s' is not a camera",
                           limen__node_title(node));
    if (!(fovy > 0 && fovy < GLM_PIf))
        return limen__fail(s, LIMEN_ERR_ARG, "fov: must be in (0, 180) degrees (got %g)",
                           glm_deg(fovy));
    limen_status st = check_sizes(s, &znear, 1, "near");
    if (!st)
        st = check_sizes(s, &zfar, 1, "far");
    if (st)
        return st;
    if (!(zfar > znear))
        return limen__fail(s, LIMEN_ERR_ARG, "far: must be greater than near (got %g, near %g)",
                           zfar, znear);
    node->fovy = fovy;
    node->znear = znear;
    node->zfar = zfar;
    return LIMEN_OK;
}

limen_status limen_camera_get_lens(const limen_scene *s, limen_node cam, float *fovy,
                                   float *znear, float *zfar)
{
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, cam, 0, &node);
    if (found)
        return found;
    if (fovy)
        *fovy = node->fovy;
    if (znear)
        *znear = node->znear;
    if (zfar)
        *zfar = node->zfar;
    return LIMEN_OK;
}

limen_status limen_camera_matrices(limen_scene *s, float aspect, limen_depth_range range,
                                   float view[16], float proj[16])
{
    if (!s || !view || !proj)
        return LIMEN_ERR_ARG;
    if (!s->camera)
        return limen__fail(s, LIMEN_ERR_ARG, "scene has no camera (add s:camera{...})");
    limen__node *cam = &s->nodes[s->camera - 1];
    limen__scene_refresh(s);
    mat4 v;
    glm_mat4_inv(cam->world, v);
    mat_out(v, view);
    limen_status st = limen_perspective(cam->fovy, aspect, cam->znear, cam->zfar, range, proj);
    if (st)
        return limen__fail(s, st, "camera: cannot form its projection (aspect %g)", aspect);
    return LIMEN_OK;
}
