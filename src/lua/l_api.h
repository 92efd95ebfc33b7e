/* l_api.h - what the files of the Lua bindings (l_fields.c, l_node.c, l_scene.c,
 * l_render.c) share: the userdata types, the field table, and the functions one file
 * offers the others. Not part of the public API. The module as a script sees it is in
 * docs/lua.md (tests/sh/docs.sh checks that every name registered here is there).
 *
 * Every constructor and every assignment checks all of its fields before it changes
 * anything, and its errors name the constructor and the field:
 *
 *     scenes/x.lua:7: sphere: field 'radius' must be a positive number (got -1)
 *
 * Angles are degrees here and radians in the C API. */
#ifndef LIMEN_L_API_H
#define LIMEN_L_API_H

#include "lua/lua_internal.h"

#define SCENE_MT "limen.scene"
#define NODE_MT "limen.node"
#define NAME_MAX_LEN 63     /* the core keeps 64 bytes with the terminator */
#define LABEL_LEN 96
#define CTX_LEN 96          /* "kind 'name'" */
#define DEG (3.14159265358979323846 / 180.0)
/* Coordinates, sizes, scales and distances stay within [-MAX_MAGNITUDE, MAX_MAGNITUDE] and
 * sizes above MIN_SIZE: a float holds up to 3.4e38, and the maths squares and multiplies
 * these (1e30 squared is infinite), so larger values overflow into Inf and NaN, and a scene
 * drawn with them shows nothing. Within these bounds a product of four stays finite. */
#define MAX_MAGNITUDE 1e9
#define MIN_SIZE 1e-9

/* A scene userdata owns its limen_scene. User values: 1 = table of Lua-side fields
 * (update), 2 = table handle id -> node userdata, so that a node has one userdata and
 * s:find("a") == a. */
typedef struct lscene {
    limen_scene *s;             /* NULL once collected */
    lua_Integer seq;            /* creation counter, orders s:nodes() */
    int max_nodes;
    size_t held;                /* C-side bytes counted against the script's memory cap */
    size_t assets;              /* ... and those of its meshes and images */
} lscene;

/* What the core keeps in C for a scene: the scene, and node slots (a node and its free-list
 * entry, 500 bytes) in an array that doubles from 64 and stays when nodes go. */
#define SCENE_BYTES 1024
#define SLOT_BYTES 512
#define FIRST_SLOTS 64

/* A node userdata: the handle plus what error messages need after the node has gone.
 * User value 1 = its scene userdata, which it keeps alive. */
typedef struct lnode {
    limen_node n;
    limen_node_kind kind;
    lua_Integer seq;
    char name[NAME_MAX_LEN + 1];
    char label[LABEL_LEN];
} lnode;

/* ------------------------------------------------------------------ fields */

enum field {
    F_NAME, F_PARENT, F_POS, F_ROTATE, F_SCALE, F_NORMAL, F_UP, F_VISIBLE, F_COLOR,
    F_SIZE, F_RADIUS, F_HEIGHT, F_CHECKER, F_LOOK_AT, F_FOV, F_NEAR, F_FAR,
    F_TINT, F_BACK, F_FILL, F_MAX_DEPTH, F_LINK, F_FILE, F_SMOOTH, F_RANGE, F_TEXTURE,
    F_TEXTURE_REPEAT, F_FILTER, F_COUNT
};

#define BIT(f) (1u << (f))
#define F_TRANSFORM (BIT(F_NAME) | BIT(F_PARENT) | BIT(F_POS) | BIT(F_ROTATE) | BIT(F_SCALE) | \
                     BIT(F_NORMAL) | BIT(F_UP) | BIT(F_VISIBLE))
#define F_SHAPE (F_TRANSFORM | BIT(F_COLOR) | BIT(F_CHECKER))
#define F_SURFACE (F_TRANSFORM | BIT(F_SIZE) | BIT(F_TINT) | BIT(F_BACK) | BIT(F_FILL) | \
                   BIT(F_MAX_DEPTH))

/* Fields that only a constructor takes: after it, normal/up/look_at go through
 * node:face() and node:look_at(), and link through node:link(). */
#define F_CONSTRUCT_ONLY (BIT(F_NORMAL) | BIT(F_UP) | BIT(F_LOOK_AT) | BIT(F_LINK) | BIT(F_FILE) | \
                          BIT(F_TEXTURE))

/* A parsed set of fields; `have` says which are present. */
typedef struct spec {
    unsigned have;
    const char *name;
    limen_node parent, link;
    float pos[3], rotate[3], scale[3], normal[3], up[3], look_at[3];
    float color[3], size[3], radius, height;
    float checker_a[3], checker_b[3], cell;
    float fov, znear, zfar, range, texture_repeat[2];
    float tint[3], back[3], fill[3];
    int max_depth, visible, smooth;
    int filter;                 /* limen_texture_filter */
    const char *file;
    char texture[1200];         /* the image file to open (relative to the script's folder) */
} spec;

#define HAVE(sp, f) (((sp)->have & BIT(f)) != 0)

extern const char *const limen__lua_filter_names[3];   /* by limen_texture_filter */

#define RANGE_FINITE "a number from -1e9 to 1e9"
#define RANGE_POSITIVE "a positive number from 1e-9 to 1e9"

enum elem { ELEM_FINITE, ELEM_POSITIVE, ELEM_UNIT, ELEM_NONNEG };

/* ------------------------------------------------------------------ l_fields.c */

/* Which constructor fields each kind takes (none out of range). */
unsigned limen__lua_kind_fields(limen_node_kind k);
/* A kind's name as scripts spell it (limen_kind_get), "node" out of range. */
static inline const char *limen__lua_kind_name(limen_node_kind k)
{
    const limen_kind_info *ki = limen_kind_get(k);
    return ki ? ki->name : "node";
}

int limen__lua_field_index(const char *key);

/* Raises "ctx: unknown field 'key' (did you mean 'x'?)" among the allowed names. */
int limen__lua_unknown_field(lua_State *L, const char *ctx, const char *what, const char *key,
                             const char *const *names, int count);

/* The key at idx as a string; for any other key raises "ctx: what <the key>". */
const char *limen__lua_check_key(lua_State *L, int idx, const char *ctx, const char *what);

/* The argument at idx must be a table or absent (an empty one is put there); the stack is
 * cut to idx. */
void limen__lua_table_arg(lua_State *L, int idx);

/* Raises for a key of the table at t that is not a string among names[0..count). */
void limen__lua_check_keys(lua_State *L, int t, const char *ctx, const char *const *names,
                           int count);

int limen__lua_unknown_node_field(lua_State *L, const char *ctx, const char *what, const char *key,
                                  unsigned allowed);

/* Pushes a short description of the value at idx for "(got ...)". */
const char *limen__lua_got(lua_State *L, int idx);

int limen__lua_bad(lua_State *L, int idx, const char *ctx, const char *what, const char *must);

float limen__lua_read_positive(lua_State *L, int idx, const char *ctx, const char *what);

int limen__lua_read_int(lua_State *L, int idx, const char *ctx, const char *what, int lo, int hi,
                        const char *must);

/* A plain table of n numbers, each checked as `check` says. */
void limen__lua_read_vec(lua_State *L, int idx, const char *ctx, const char *what, int n,
                         enum elem check, float *out);

/* A live node of the scene at scene_idx (of the given kind unless kind < 0). */
limen_node limen__lua_read_node(lua_State *L, int idx, int scene_idx, const char *ctx,
                                const char *what, int kind);

/* A mesh or image file named in the calling script: relative to the script's folder (a safe
 * script's: the top-level script's, fixed when it was loaded). A safe script may read only
 * files under that folder: no absolute path, no "..", and no link that leads out of it
 * (decided when the file is opened, core/confine.c). Writes the path to open into out, or
 * raises. */
void limen__lua_script_path(lua_State *L, const char *ctx, const char *file, char *out,
                            size_t size);

/* Parses the value at v as field f of a node of `kind` into sp. */
void limen__lua_parse_field(lua_State *L, int v, int f, limen_node_kind kind, int scene_idx,
                            const char *ctx, spec *sp);

/* Checks that need several fields or the node's current state (n may be the zero handle
 * for a node still to be made). */
void limen__lua_check_spec(lua_State *L, limen_scene *s, limen_node n, const char *ctx, spec *sp);

/* Applies the fields of sp to node n; on failure the scene's message says why. */
limen_status limen__lua_apply_spec(limen_scene *s, limen_node n, const spec *sp);

/* Raises "ctx: <the scene's message>" (the C library's own words). Some messages start
 * with the node's label ("file:line: "), which the Lua error already gives: drop it. */
int limen__lua_c_error(lua_State *L, limen_scene *s, const char *ctx, const char *label);

/* c_error for a failed apply_spec: for look_at the core's "normal" is the view direction. */
int limen__lua_spec_error(lua_State *L, limen_scene *s, const char *ctx, const char *label,
                          const spec *sp);

/* Reads the constructor table at t (fields in `allowed`) into sp, checking everything;
 * leaves the stack as it found it. String fields stay alive in the table. */
void limen__lua_read_ctor(lua_State *L, int t, int scene_idx, limen_node_kind kind,
                          unsigned allowed,
                          const char *ctx, limen_scene *s, spec *sp);

void limen__lua_push_float(lua_State *L, float f);

/* A table of n floats, each multiplied by k (and rounded to float) first. */
void limen__lua_push_vec(lua_State *L, const float *v, int n, double k);

/* ------------------------------------------------------------------ l_node.c */

/* "sphere 'ball'" or "sphere" for an unnamed node. */
const char *limen__lua_node_ctx(const lnode *nd, char *buf, size_t size);

/* Pushes the userdata of node n of the scene at scene_idx (nil for the zero handle),
 * making one if the node has none yet. */
void limen__lua_push_node(lua_State *L, int scene_idx, limen_node n);

/* Destroys node n and drops its userdata from the scene's table (destroy() leaves the
 * scene's error message alone). */
void limen__lua_forget_node(lua_State *L, int scene_idx, limen_node n);

/* "file:line" of the script line that called the running C function. */
void limen__lua_where(lua_State *L, char label[LABEL_LEN]);

/* Makes a node from a checked spec and pushes it. On failure destroys it (and `also`, the
 * first half of a pair) and raises "ctx: <the core's message>". */
limen_node limen__lua_create_node(lua_State *L, int scene_idx, limen_node_kind kind, const spec *sp,
                                  const char *ctx, const char *label, limen_node also);

int limen__lua_node_index(lua_State *L);

extern const luaL_Reg limen__lua_node_methods[];

extern const luaL_Reg limen__lua_node_meta[];

/* ------------------------------------------------------------------ l_scene.c */

/* Counts what ls's scene will hold in C with `count` nodes against the memory cap of the
 * script (a script could otherwise fill and empty scene after scene); past the cap, raises
 * the memory error, as an allocation would. */
void limen__lua_hold_scene(lua_State *L, lscene *ls, int count);

lscene *limen__lua_check_scene(lua_State *L, int i);

/* ------------------------------------------------------------------ l_render.c */

/* s:render { out = "x.png", size = {w, h}, backend = "osmesa"|"egl", time = t, ... }
 * -> stats { ms, views, fragments, samples, pixels }. */
int limen__lua_scene_render(lua_State *L);

/* s:cast(origin, direction [, bounces]): follows a ray through mirrors and portals (the
 * ray tracer's rules) and returns what it hits: { hit, point, normal, distance, node, color,
 * surfaces = { the mirrors and portals passed, in order }, out = { origin, direction of
 * the last segment } }. bounces: a limit on surfaces passed (default: their own limits). */
int limen__lua_scene_cast(lua_State *L);

/* ------------------------------------------------------------------ l_collide.c */

/* s:sweep { from, to, radius [, segment] [, ignore] [, depth] } -> { hit, fraction, centre,
 * point, normal, node, portals, portal, matrix, radius } (docs/lua.md). */
int limen__lua_scene_sweep(lua_State *L);

/* node:slide { by, radius [, segment] } -> { moved, contacts, normal, portals, portal, matrix,
 * radius }. */
int limen__lua_node_slide(lua_State *L);

#endif
