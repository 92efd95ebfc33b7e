/* internal.h - the scene graph's data, shared by the core, the renderer and the bindings.
 * Not part of the public API. */
#ifndef LIMEN_INTERNAL_H
#define LIMEN_INTERNAL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include <cglm/cglm.h>

#include "limen.h"

#define LIMEN__NAME_MAX 64
#define LIMEN__LABEL_MAX 96
#define LIMEN__ERR_MAX 512
#define LIMEN__MAX_LIGHTS LIMEN_MAX_LIGHTS

typedef struct limen__spatial limen__spatial;

typedef struct limen__node {
    uint32_t gen;               /* generation; odd while alive, never repeats for a slot */
    int live_at;                /* position in the scene's live list while alive */
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
    bool stale;                 /* on the scene's stale list: world to recompute */
    bool bad_world;             /* world not finite */
    int nchildren;              /* live nodes whose parent this is */

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
    float tex_repeat[2];        /* texture coordinates are scaled by these (1, 1) */
    limen_texture_filter tex_filter;  /* LIMEN_FILTER_TRILINEAR (0) unless set */
} limen__node;

struct limen_scene {
    limen__node *nodes;
    int cap;                    /* slots allocated */
    int max_nodes;              /* 0: as many as memory holds */
    int count;                  /* live nodes */
    /* Free slots, first freed first reused (a ring of cap entries), so that a slot's
     * generation advances as slowly as the churn allows; a slot whose generation would wrap
     * is retired instead of freed, so a stale handle never comes back. */
    uint32_t *free_ring;
    int free_head, free_count;
    /* Slot indices of the live nodes in creation order, with holes (-1) where nodes were
     * destroyed; compacted whenever the holes outnumber the live nodes, so walking it costs
     * at most twice the live count (never the pool's capacity). */
    int *live;
    int live_len, live_cap, live_holes;
    bool dirty;                 /* world matrices need recomputing */
    uint32_t *stale_list;       /* slots touched since the last refresh (core/index.c) */
    int nstale, stale_cap;
    bool all_stale;             /* recompute every world matrix (first time, no memory) */
    bool world_valid;
    int nbad;                   /* nodes whose world matrix is not finite */
    limen__spatial *index;        /* spatial index; NULL until first used */
    bool brute_force;           /* tests only: plan and trace without the index */
    long straddle_tests;        /* tests only: shape-through-portal tests made so far */
    vec3 background;
    float ambient;
    uint32_t camera;            /* index + 1 */
    unsigned test_faults;       /* LIMEN_FAULT_* bits (core/testing.h); 0 */
    uint64_t mem_wanted;        /* bytes the last load refused for the memory allowed it
                                 * would have taken (a script's host says what cap would do) */
    void **meshes;              /* limen__mesh *: each shared by the nodes that load it */
    int nmeshes, mesh_cap;
    void **textures;            /* limen__texture *: each shared by the nodes that use it */
    int ntextures, texture_cap;
    struct limen__load *load;   /* while a script loads a file: its folder and limits
                                 * (core/confine.h); NULL: trusted, no limits */
    char **warnings;            /* what loading files noticed (core/mesh.c): "file: warning: ..." */
    int nwarnings;
    char err[LIMEN__ERR_MAX];
};

/* Formats the scene's error message and returns st. */
limen_status limen__fail(limen_scene *s, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Writes into a fixed buffer (renderers, scripts). */
void limen__vformat(char *buf, size_t size, const char *fmt, va_list ap);

/* limits.c: checks in (NULL: all defaults) and fills out with its defaults
 * (limen_limits_defaults: max_views, lod_pixels, depth 0 under DEPTH_RULE_OWN, and a frame
 * budget for a 640 x 480 image, where in has none: the planner fills its own size's first,
 * through limen_plan_desc_defaults); a bad field fails with a message that starts "who: ". */
limen_status limen__limits_resolve(limen_scene *s, const char *who, const limen_limits *in,
                                   limen_limits *out);
/* The deepest view a surface whose own max_depth is surface_max may have under resolved
 * limits: a view of depth d through it exists only if d <= this. */
int limen__limits_depth(const limen_limits *l, int surface_max);
/* lod.c: limen_limits.lod_pixels with its default filled in (0 -> LIMEN_LOD_DEFAULT, an
 * eighth of a pixel); the one place that default lives, for limen__limits_resolve and
 * limen_view_mesh_lod. */
float limen__lod_pixels(float pixels);

/* jpeg.c: writes 8-bit RGB as a JPEG of the given quality (1 to 100); IO if it cannot. */
limen_status limen__write_jpeg(const char *path, int width, int height,
                               const unsigned char *rgb, int quality);

/* The live node of handle n, or NULL (a null, stale or foreign handle), for readers: const
 * from a const scene. Callers that write the node look it up with limen__node_lookup. */
const limen__node *limen__node_get(const limen_scene *s, limen_node n);
/* Bit of a node kind in a set of kinds (limen__node_lookup's kinds). */
#define LIMEN__KIND(k) (1u << (unsigned)(k))
/* The live node of handle n, looked up for an edit or a call that may write the scene:
 * LIMEN_OK and *out; LIMEN_ERR_ARG without a scene; LIMEN_ERR_HANDLE for a null, stale or
 * foreign handle, or a node whose kind is not in `kinds` (LIMEN__KIND bits; 0: any kind),
 * with a message "fn: null node handle", "fn: stale or foreign node handle" or
 * "fn: 'title' is not <what>". *out is NULL on failure. */
limen_status limen__node_lookup(limen_scene *s, limen_node n, unsigned kinds, const char *what,
                                const char *fn, limen__node **out);
/* The same for const readers, which never write the scene (not even its message): only the
 * status. */
limen_status limen__node_lookup_const(const limen_scene *s, limen_node n, unsigned kinds,
                                      const limen__node **out);
/* Recomputes the world matrices of the nodes touched since the last call and of their
 * descendants (core/index.c). */
void limen__scene_refresh(limen_scene *s);
/* Sets node->local from its position, rotation, facing and scale (unless set directly). */
void limen__node_compose_local(limen__node *node);
/* Marks a node whose transform, parent or size changed. */
void limen__node_touch(limen_scene *s, limen__node *node);
/* The node in `slot` was created or destroyed: the spatial index inserts or removes its leaf
 * on its next use (core/index.c). */
void limen__scene_restructure(limen_scene *s, int slot);
void limen__index_free(limen_scene *s);
/* Slot of the node where a non-finite world matrix starts, or -1. */
int limen__scene_bad_world(const limen_scene *s);
/* Refreshes, then refuses a scene whose world matrices are not all finite (scales along a
 * parent chain multiplied past what a float holds), naming the node. fn prefixes nothing;
 * the message starts with the node's label. */
limen_status limen__scene_check(limen_scene *s);
/* Slot index of a handle's node (without checking that it is alive); -1 for none. */
static inline int limen__node_get_index(limen_node n)
{
    return n.id ? (int)((uint32_t)n.id - 1u) : -1;
}
/* Handle of the node in slot i. */
limen_node limen__node_handle(const limen_scene *s, int index);
/* The drawable of the live node in `slot`, as limen_drawables_build lists it (drawables.c). */
void limen__drawable_read(const limen_scene *s, int slot, limen_drawable *it);

/* How messages name a node: its name, or where it was made ("scenes/x.lua:7") when it has
 * none, or "unnamed". */
static inline const char *limen__node_title(const limen__node *n)
{
    return n->name[0] ? n->name : n->label[0] ? n->label : "unnamed";
}

static inline bool limen__is_surface(const limen__node *n)
{
    return limen_kind_get(n->kind)->surface;     /* core/kinds.c */
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

/* A file written whole or not at all (core/file.c): open, write to o->f, then close (which
 * flushes, syncs and renames into place) or abort. Any failure is LIMEN_ERR_IO; a path
 * with no room for the temporary name beside it is LIMEN_ERR_ARG. */
typedef struct limen__out {
    FILE *f;
    bool direct;                /* the target is a device or a pipe: written in place */
    char path[4096];
    char tmp[4096];
} limen__out;
limen_status limen__out_open(limen__out *o, const char *path);
limen_status limen__out_close(limen__out *o);
void limen__out_abort(limen__out *o);

/* limen_read_png on bytes in memory (which it may rearrange). */
limen_status limen__png_decode(unsigned char *buf, size_t len, int *width, int *height,
                               unsigned char **rgb);

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
