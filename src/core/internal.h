/* internal.h - the scene graph's data, shared by the core, the renderer and the bindings.
 * Not part of the public API. */
#ifndef LIMEN_INTERNAL_H
#define LIMEN_INTERNAL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>

#include <cglm/cglm.h>

#include "limen.h"

#define LIMEN__NAME_MAX 64
#define LIMEN__LABEL_MAX 96
#define LIMEN__ERR_MAX 512
#define LIMEN__MAX_LIGHTS LIMEN_MAX_LIGHTS

typedef struct limen__node {
    uint32_t gen;               /* generation; odd while alive */
    limen_node_kind kind;
    uint32_t parent;            /* index + 1; 0 = none */
    char name[LIMEN__NAME_MAX];
    char label[LIMEN__LABEL_MAX];

    /* local transform: T * R * F * S, or `local` as set directly */
    vec3 pos, euler, scale;
    mat3 facing;
    bool explicit_local;
    mat4 local;
    mat4 world;                 /* valid after limen__scene_refresh */

    vec3 color;                 /* albedo; light intensity */
    float range;                /* lights: where the contribution reaches 0; 0 = none */
    vec3 checker_b;
    float checker_cell;         /* 0 = plain colour (color only) */
    vec3 dims;
    bool visible;

    float fovy, znear, zfar;    /* cameras */

    vec3 tint, back, fill;      /* mirrors and portals */
    int max_depth;
    uint32_t pair;              /* portals: partner's index + 1; 0 = unpaired */

    struct limen__mesh *mesh;   /* meshes: shared geometry (core/mesh.h), or NULL */
    bool smooth;                /* meshes: interpolate vertex normals */
    struct limen__texture *texture;  /* quads, boxes, meshes: albedo = texel * colour */
} limen__node;

struct limen_scene {
    limen__node *nodes;
    int cap;                    /* slots allocated */
    int max_nodes;
    int count;                  /* live nodes */
    uint32_t *free_list;
    int free_count;
    bool dirty;                 /* world matrices need recomputing */
    vec3 background;
    float ambient;
    uint32_t camera;            /* index + 1 */
    uint32_t bad_world;         /* index + 1 of a node whose world matrix overflowed; 0 */
    void **meshes;              /* limen__mesh *: each shared by the nodes that load it */
    int nmeshes, mesh_cap;
    void **textures;            /* limen__texture *: each shared by the nodes that use it */
    int ntextures, texture_cap;
    char err[LIMEN__ERR_MAX];
};

/* Formats the scene's error message and returns st. */
limen_status limen__fail(limen_scene *s, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Writes into a fixed buffer (renderers, scripts). */
void limen__vformat(char *buf, size_t size, const char *fmt, va_list ap);

/* Live node for a handle, or NULL. */
limen__node *limen__node_get(const limen_scene *s, limen_node n);
/* Recomputes world matrices if something moved. */
void limen__scene_refresh(limen_scene *s);
/* Refreshes, then refuses a scene whose world matrices are not all finite (scales along a
 * parent chain multiplied past what a float holds), naming the node. fn prefixes nothing;
 * the message starts with the node's label. */
limen_status limen__scene_check(limen_scene *s);
/* Slot index of a handle's node (without checking that it is alive); -1 for none. */
static inline int limen__node_get_index(limen_node n)
{
    return n.id ? (int)(n.id & 0xFFFFFu) - 1 : -1;
}
/* Handle of the node in slot i. */
limen_node limen__node_handle(const limen_scene *s, int index);

static inline bool limen__is_surface(const limen__node *n)
{
    return n->kind == LIMEN_NODE_MIRROR || n->kind == LIMEN_NODE_PORTAL;
}

/* Index of a node in its scene's pool. */
static inline int limen__index(const limen_scene *s, const limen__node *n)
{
    return (int)(n - s->nodes);
}

static inline bool limen__alive(const limen__node *n)
{
    return (n->gen & 1u) != 0;
}

/* Surface matrix X (see limen_surface_matrix) in double precision; false for an unpaired
 * portal or a degenerate frame. */
bool limen__surface_matrix_d(limen_scene *s, const limen__node *n, double x[16]);
/* World-space plane (front = +Z side) and corners (counter-clockwise from the front) of a
 * quad-like node. */
void limen__surface_plane_d(const limen__node *n, double plane[4]);
void limen__surface_corners(const limen__node *n, double corners[4][3]);

/* World bounding sphere of a drawable node. */
void limen__node_bounds(const limen__node *n, double centre[3], double *radius);
/* For each node slot: the portal (slot index) a closed shape passes through, or -1;
 * portal_of has s->cap entries. Returns how many shapes pass through one. */
int limen__find_straddlers(limen_scene *s, int *portal_of);

/* A scene's list of shared assets (meshes, textures): adds one (false: out of memory), or
 * takes one out (order not kept). */
static inline bool limen__assets_add(void ***list, int *n, int *cap, void *item)
{
    if (*n == *cap) {
        int c = *cap ? *cap * 2 : 8;
        void **l = realloc(*list, sizeof *l * (size_t)c);
        if (!l)
            return false;
        *list = l;
        *cap = c;
    }
    (*list)[(*n)++] = item;
    return true;
}

static inline void limen__assets_remove(void **list, int *n, const void *item)
{
    for (int i = 0; i < *n; i++) {
        if (list[i] == item) {
            list[i] = list[--*n];
            return;
        }
    }
}

static inline bool limen__finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

#endif
