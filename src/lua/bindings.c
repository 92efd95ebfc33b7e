/* bindings.c - the Lua module "limen": scenes and nodes as userdata (Lua's liolib.c and
 * LÖVR's api/ are the models). Every constructor and every assignment checks all of its
 * fields before it changes anything, and its errors name the constructor and the field:
 *
 *     scenes/x.lua:7: sphere: field 'radius' must be a positive number (got -1)
 *
 * Angles are degrees here and radians in the C API.
 *
 *   limen.scene { background = {r,g,b}, ambient = a, max_nodes = n }
 *   s:group / box / sphere / cylinder / plane / mirror / portal / light / camera { ... }
 *       every node: name parent pos rotate scale normal up visible
 *       shapes: color checker; box size{x,y,z}; sphere radius; cylinder radius height;
 *       plane size{w,h}; mirror, portal: size tint back fill max_depth; portal: link;
 *       light: color (intensity, >= 0) range; camera: look_at fov near far (becomes the scene's)
 *   s:mesh { file, smooth, color, checker, ... }: a mesh file relative to the script;
 *       plane, box, mesh: texture (an image file relative to the script)
 *   s:portal_pair({A}, {B} [, {shared}]) -> a, b       s:find(name)   s:nodes()   #s
 *   s:render { out, size, backend, time, msaa, method, clip, max_depth, max_views, depth,
 *              texture_scale } -> stats
 *   s.update = function(t) end    s.background  s.ambient  s.active_camera
 *   node fields: the constructor's (but normal, up, look_at, link) plus kind, label,
 *   partner; node:destroy() node:world() node:face(n [, up]) node:look_at(p [, up])
 *   portal:link(other) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <limits.h>
#include <stdbool.h>

#include "core/mesh.h"
#include "core/texture.h"
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

static const char *const kind_names[LIMEN_NODE_KIND_COUNT] = {
    "group", "box", "sphere", "cylinder", "plane", "mirror", "portal", "light", "camera", "mesh"
};

/* ------------------------------------------------------------------ fields */

enum field {
    F_NAME, F_PARENT, F_POS, F_ROTATE, F_SCALE, F_NORMAL, F_UP, F_VISIBLE, F_COLOR,
    F_SIZE, F_RADIUS, F_HEIGHT, F_CHECKER, F_LOOK_AT, F_FOV, F_NEAR, F_FAR,
    F_TINT, F_BACK, F_FILL, F_MAX_DEPTH, F_LINK, F_FILE, F_SMOOTH, F_RANGE, F_TEXTURE, F_COUNT
};

static const char *const field_names[F_COUNT] = {
    "name", "parent", "pos", "rotate", "scale", "normal", "up", "visible", "color",
    "size", "radius", "height", "checker", "look_at", "fov", "near", "far",
    "tint", "back", "fill", "max_depth", "link", "file", "smooth", "range", "texture"
};

#define BIT(f) (1u << (f))
#define F_TRANSFORM (BIT(F_NAME) | BIT(F_PARENT) | BIT(F_POS) | BIT(F_ROTATE) | BIT(F_SCALE) | \
                     BIT(F_NORMAL) | BIT(F_UP) | BIT(F_VISIBLE))
#define F_SHAPE (F_TRANSFORM | BIT(F_COLOR) | BIT(F_CHECKER))
#define F_SURFACE (F_TRANSFORM | BIT(F_SIZE) | BIT(F_TINT) | BIT(F_BACK) | BIT(F_FILL) | \
                   BIT(F_MAX_DEPTH))

/* Which constructor fields each kind takes. */
static const unsigned kind_fields[LIMEN_NODE_KIND_COUNT] = {
    [LIMEN_NODE_GROUP] = F_TRANSFORM,
    [LIMEN_NODE_BOX] = F_SHAPE | BIT(F_SIZE) | BIT(F_TEXTURE),
    [LIMEN_NODE_SPHERE] = F_SHAPE | BIT(F_RADIUS),
    [LIMEN_NODE_CYLINDER] = F_SHAPE | BIT(F_RADIUS) | BIT(F_HEIGHT),
    [LIMEN_NODE_QUAD] = F_SHAPE | BIT(F_SIZE) | BIT(F_TEXTURE),
    [LIMEN_NODE_MIRROR] = F_SURFACE,
    [LIMEN_NODE_PORTAL] = F_SURFACE | BIT(F_LINK),
    [LIMEN_NODE_LIGHT] = F_TRANSFORM | BIT(F_COLOR) | BIT(F_RANGE),
    [LIMEN_NODE_CAMERA] = F_TRANSFORM | BIT(F_LOOK_AT) | BIT(F_FOV) | BIT(F_NEAR) | BIT(F_FAR),
    [LIMEN_NODE_MESH] = F_SHAPE | BIT(F_FILE) | BIT(F_SMOOTH) | BIT(F_TEXTURE),
};

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
    float fov, znear, zfar, range;
    float tint[3], back[3], fill[3];
    int max_depth, visible, smooth;
    const char *file;
    char texture[1200];         /* the image file to open (relative to the script's folder) */
} spec;

#define HAVE(sp, f) (((sp)->have & BIT(f)) != 0)

static int field_index(const char *key)
{
    for (int f = 0; f < F_COUNT; f++)
        if (strcmp(key, field_names[f]) == 0)
            return f;
    return -1;
}

/* Edit distance, for "did you mean" (names here are short). */
static int distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 31 || lb > 31)
        return 99;
    int d[32][32];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++)
        d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        for (size_t j = 1; j <= lb; j++) {
            int best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < best)
                best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best)
                best = d[i][j - 1] + 1;
            /* a swap of two neighbours counts as one edit (raduis -> radius) */
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    }
    return d[la][lb];
}

/* The closest of `names` to key, or NULL if none is close. */
static const char *suggest(const char *key, const char *const *names, int count)
{
    const char *best = NULL;
    int bestd = 3;
    if (strcmp(key, "colour") == 0)
        key = "color";
    for (int i = 0; i < count; i++) {
        if (!names[i])
            continue;
        int d = distance(key, names[i]);
        if (d < bestd && (size_t)d < strlen(names[i])) {
            best = names[i];
            bestd = d;
        }
    }
    return best;
}

/* Raises "ctx: unknown field 'key' (did you mean 'x'?)" among the allowed names. */
static int unknown_field(lua_State *L, const char *ctx, const char *what, const char *key,
                         const char *const *names, int count)
{
    const char *s = suggest(key, names, count);
    if (s)
        return luaL_error(L, "%s: %s '%s' (did you mean '%s'?)", ctx, what, key, s);
    return luaL_error(L, "%s: %s '%s'", ctx, what, key);
}

static int unknown_node_field(lua_State *L, const char *ctx, const char *what, const char *key,
                              unsigned allowed)
{
    const char *names[F_COUNT];
    for (int f = 0; f < F_COUNT; f++)
        names[f] = allowed & BIT(f) ? field_names[f] : NULL;
    return unknown_field(L, ctx, what, key, names, F_COUNT);
}

/* ------------------------------------------------------------------ C-side memory */

/* Counts what ls's scene will hold in C with `count` nodes against the memory cap of the
 * script (a script could otherwise fill and empty scene after scene); past the cap, raises
 * the memory error, as an allocation would. */
static void hold_scene(lua_State *L, lscene *ls, int count)
{
    size_t slots = count > 0 ? FIRST_SLOTS : 0;
    while (slots && slots < (size_t)count)
        slots *= 2;
    if (slots > (size_t)ls->max_nodes)
        slots = (size_t)ls->max_nodes;
    size_t want = SCENE_BYTES + slots * SLOT_BYTES;
    if (want <= ls->held)
        return;
    if (!limen__lua_hold(L, (ptrdiff_t)(want - ls->held))) {
        limen__lua_note_line(L);
        lua_pushliteral(L, "not enough memory");   /* lua_error makes it a memory error */
        lua_error(L);
    }
    ls->held = want;
}

/* ------------------------------------------------------------------ userdata access */

static lscene *check_scene(lua_State *L, int i)
{
    lscene *ls = luaL_checkudata(L, i, SCENE_MT);
    if (!ls->s)
        luaL_error(L, "scene: used after it was collected");
    return ls;
}

limen_scene *limen__lua_toscene(lua_State *L, int idx)
{
    lscene *ls = luaL_testudata(L, idx, SCENE_MT);
    return ls ? ls->s : NULL;
}

int limen__lua_push_update(lua_State *L, int idx)
{
    if (!luaL_testudata(L, idx, SCENE_MT)) {
        lua_pushnil(L);
        return LUA_TNIL;
    }
    lua_getiuservalue(L, idx, 1);
    int t = lua_getfield(L, -1, "update");
    lua_remove(L, -2);
    return t;
}

/* "sphere 'ball'" or "sphere" for an unnamed node. */
static const char *node_ctx(const lnode *nd, char *buf, size_t size)
{
    if (nd->name[0])
        snprintf(buf, size, "%s '%s'", kind_names[nd->kind], nd->name);
    else
        snprintf(buf, size, "%s", kind_names[nd->kind]);
    return buf;
}

/* The scene of a node userdata (pushed on the stack) and the node; raises a clean error if
 * the node has been destroyed. */
static lnode *check_node(lua_State *L, int i, limen_scene **sp)
{
    lnode *nd = luaL_checkudata(L, i, NODE_MT);
    lua_getiuservalue(L, i, 1);
    lscene *ls = lua_touserdata(L, -1);
    char ctx[CTX_LEN];
    if (!ls || !ls->s)
        luaL_error(L, "%s: its scene was collected", node_ctx(nd, ctx, sizeof ctx));
    if (!limen_node_valid(ls->s, nd->n))
        luaL_error(L, "%s has been destroyed", node_ctx(nd, ctx, sizeof ctx));
    *sp = ls->s;
    return nd;
}

/* Pushes the userdata of node n of the scene at scene_idx (nil for the zero handle),
 * making one if the node has none yet. */
static void push_node(lua_State *L, int scene_idx, limen_node n)
{
    if (!n.id) {
        lua_pushnil(L);
        return;
    }
    scene_idx = lua_absindex(L, scene_idx);
    lscene *ls = lua_touserdata(L, scene_idx);
    lua_getiuservalue(L, scene_idx, 2);
    if (lua_rawgeti(L, -1, (lua_Integer)n.id) != LUA_TNIL) {
        lua_remove(L, -2);
        return;
    }
    lua_pop(L, 1);
    lnode *nd = lua_newuserdatauv(L, sizeof *nd, 1);
    memset(nd, 0, sizeof *nd);
    nd->n = n;
    nd->kind = limen_node_get_kind(ls->s, n);
    nd->seq = ++ls->seq;
    const char *name = limen_node_name(ls->s, n);
    snprintf(nd->name, sizeof nd->name, "%s", name ? name : "");
    luaL_setmetatable(L, NODE_MT);
    lua_pushvalue(L, scene_idx);
    lua_setiuservalue(L, -2, 1);
    lua_pushvalue(L, -1);
    lua_rawseti(L, -3, (lua_Integer)n.id);
    lua_remove(L, -2);
}

/* Destroys node n and drops its userdata from the scene's table (destroy() leaves the
 * scene's error message alone). */
static void forget_node(lua_State *L, int scene_idx, limen_node n)
{
    lscene *ls = lua_touserdata(L, scene_idx);
    lua_getiuservalue(L, scene_idx, 2);
    lua_pushnil(L);
    lua_rawseti(L, -2, (lua_Integer)n.id);
    lua_pop(L, 1);
    limen_node_destroy(ls->s, n);
}

/* ------------------------------------------------------------------ value checks */

/* Pushes a short description of the value at idx for "(got ...)". */
static const char *got(lua_State *L, int idx)
{
    idx = lua_absindex(L, idx);
    char buf[CTX_LEN];
    switch (lua_type(L, idx)) {
    case LUA_TNUMBER:
        if (lua_isinteger(L, idx))
            return lua_pushfstring(L, "%I", (LUAI_UACINT)lua_tointeger(L, idx));
        if (isnan(lua_tonumber(L, idx)))
            return lua_pushstring(L, "nan");
        if (isinf(lua_tonumber(L, idx)))
            return lua_pushstring(L, lua_tonumber(L, idx) > 0 ? "inf" : "-inf");
        return lua_pushfstring(L, "%f", lua_tonumber(L, idx));
    case LUA_TSTRING: {
        size_t len;
        const char *s = lua_tolstring(L, idx, &len);
        snprintf(buf, sizeof buf, "\"%.32s%s\"", s, len > 32 ? "..." : "");
        return lua_pushstring(L, buf);
    }
    case LUA_TBOOLEAN:
        return lua_pushstring(L, lua_toboolean(L, idx) ? "true" : "false");
    case LUA_TUSERDATA: {
        lnode *nd = luaL_testudata(L, idx, NODE_MT);
        if (nd)
            return lua_pushstring(L, node_ctx(nd, buf, sizeof buf));
        if (luaL_testudata(L, idx, SCENE_MT))
            return lua_pushstring(L, "a scene");
        return lua_pushstring(L, "userdata");
    }
    default:
        return lua_pushstring(L, luaL_typename(L, idx));
    }
}

static int bad(lua_State *L, int idx, const char *ctx, const char *what, const char *must)
{
    const char *g = got(L, idx);
    return luaL_error(L, "%s: %s must be %s (got %s)", ctx, what, must, g);
}

#define RANGE_FINITE "a number from -1e9 to 1e9"
#define RANGE_POSITIVE "a positive number from 1e-9 to 1e9"

/* A finite number (also after conversion to float). */
static float read_number(lua_State *L, int idx, const char *ctx, const char *what)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        bad(L, idx, ctx, what, "a number");
    double d = lua_tonumber(L, idx);
    if (!isfinite((float)d))
        bad(L, idx, ctx, what, "a finite number");
    if (fabs(d) > MAX_MAGNITUDE)
        bad(L, idx, ctx, what, RANGE_FINITE);
    return (float)d;
}

static float read_positive(lua_State *L, int idx, const char *ctx, const char *what)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        bad(L, idx, ctx, what, "a positive number");
    double d = lua_tonumber(L, idx);
    if (!isfinite((float)d) || !(d > 0))
        bad(L, idx, ctx, what, "a positive number");
    if (d > MAX_MAGNITUDE || d < MIN_SIZE)
        bad(L, idx, ctx, what, RANGE_POSITIVE);
    return (float)d;
}

static int read_int(lua_State *L, int idx, const char *ctx, const char *what, int lo, int hi,
                    const char *must)
{
    int ok;
    lua_Integer v = lua_tointegerx(L, idx, &ok);
    if (lua_type(L, idx) != LUA_TNUMBER || !ok || v < lo || v > hi)
        bad(L, idx, ctx, what, must);
    return (int)v;
}

enum elem { ELEM_FINITE, ELEM_POSITIVE, ELEM_UNIT, ELEM_NONNEG };

/* A plain table of n numbers, each checked as `check` says. */
static void read_vec(lua_State *L, int idx, const char *ctx, const char *what, int n,
                     enum elem check, float *out)
{
    idx = lua_absindex(L, idx);
    static const char *const names[] = { "", "", "a table of 2 numbers", "a table of 3 numbers" };
    if (!lua_istable(L, idx))
        bad(L, idx, ctx, what, names[n]);
    lua_Unsigned len = lua_rawlen(L, idx);
    if (len != (lua_Unsigned)n)
        luaL_error(L, "%s: %s must be %s (got %I value%s)", ctx, what, names[n],
                   (LUAI_UACINT)len, len == 1 ? "" : "s");
    for (int i = 0; i < n; i++) {
        char ew[96];
        snprintf(ew, sizeof ew, "%s[%d]", what, i + 1);
        lua_rawgeti(L, idx, i + 1);
        if (lua_type(L, -1) != LUA_TNUMBER)
            bad(L, -1, ctx, ew, "a number");
        double d = lua_tonumber(L, -1);
        float v = (float)d;
        if (!isfinite(v))
            bad(L, -1, ctx, ew, "a finite number");
        if (check == ELEM_POSITIVE && !(d > 0))
            bad(L, -1, ctx, ew, "a positive number");
        if (check == ELEM_UNIT && !(v >= 0 && v <= 1))
            bad(L, -1, ctx, ew, "in [0, 1]");
        if (check == ELEM_NONNEG && !(v >= 0))
            bad(L, -1, ctx, ew, "a number >= 0");
        if (check == ELEM_POSITIVE && (d < MIN_SIZE || d > MAX_MAGNITUDE))
            bad(L, -1, ctx, ew, RANGE_POSITIVE);
        if ((check == ELEM_FINITE || check == ELEM_NONNEG) && fabs(d) > MAX_MAGNITUDE)
            bad(L, -1, ctx, ew, check == ELEM_FINITE ? RANGE_FINITE : "a number from 0 to 1e9");
        out[i] = v;
        lua_pop(L, 1);
    }
}

/* A number (uniform) or {x, y, z}, all positive. */
static void read_scale(lua_State *L, int idx, const char *ctx, const char *what, float out[3])
{
    if (lua_type(L, idx) == LUA_TNUMBER) {
        double d = lua_tonumber(L, idx);
        if (!isfinite((float)d) || !(d > 0))
            bad(L, idx, ctx, what, "a positive number or a table of 3 positive numbers");
        if (d < MIN_SIZE || d > MAX_MAGNITUDE)
            bad(L, idx, ctx, what, RANGE_POSITIVE);
        out[0] = out[1] = out[2] = (float)d;
    } else if (lua_istable(L, idx)) {
        read_vec(L, idx, ctx, what, 3, ELEM_POSITIVE, out);
    } else {
        bad(L, idx, ctx, what, "a positive number or a table of 3 positive numbers");
    }
}

/* checker = { colour a, colour b, cell size }, or false to turn it off (cell 0). */
static void read_checker(lua_State *L, int idx, const char *ctx, const char *what, spec *sp)
{
    idx = lua_absindex(L, idx);
    const char *must = "{colour a, colour b, cell size} or false";
    if (lua_isboolean(L, idx) && !lua_toboolean(L, idx)) {
        sp->cell = 0;
        return;
    }
    if (!lua_istable(L, idx))
        bad(L, idx, ctx, what, must);
    lua_Unsigned len = lua_rawlen(L, idx);
    if (len != 3)
        luaL_error(L, "%s: %s must be %s (got %I value%s)", ctx, what, must, (LUAI_UACINT)len,
                   len == 1 ? "" : "s");
    char ew[96];
    snprintf(ew, sizeof ew, "%s[1]", what);
    lua_rawgeti(L, idx, 1);
    read_vec(L, -1, ctx, ew, 3, ELEM_UNIT, sp->checker_a);
    snprintf(ew, sizeof ew, "%s[2]", what);
    lua_rawgeti(L, idx, 2);
    read_vec(L, -1, ctx, ew, 3, ELEM_UNIT, sp->checker_b);
    snprintf(ew, sizeof ew, "%s[3]", what);
    lua_rawgeti(L, idx, 3);
    sp->cell = read_positive(L, -1, ctx, ew);
    lua_pop(L, 3);
}

/* A live node of the scene at scene_idx (of the given kind unless kind < 0). */
static limen_node read_node(lua_State *L, int idx, int scene_idx, const char *ctx,
                            const char *what, int kind)
{
    idx = lua_absindex(L, idx);
    lnode *nd = luaL_testudata(L, idx, NODE_MT);
    if (!nd)
        bad(L, idx, ctx, what, kind < 0 ? "a node" : kind == LIMEN_NODE_PORTAL ? "a portal" :
                                                                        "a camera");
    lua_getiuservalue(L, idx, 1);
    int same = lua_rawequal(L, -1, scene_idx);
    lscene *ls = lua_touserdata(L, -1);
    lua_pop(L, 1);
    char buf[CTX_LEN];
    if (!same)
        luaL_error(L, "%s: %s must be a node of the same scene (got %s of another scene)", ctx,
                   what, node_ctx(nd, buf, sizeof buf));
    if (!ls->s || !limen_node_valid(ls->s, nd->n))
        luaL_error(L, "%s: %s is a destroyed node (%s)", ctx, what, node_ctx(nd, buf, sizeof buf));
    if (kind >= 0 && nd->kind != (limen_node_kind)kind)
        bad(L, idx, ctx, what, kind == LIMEN_NODE_PORTAL ? "a portal" : "a camera");
    return nd->n;
}

static void script_path(lua_State *L, const char *ctx, const char *file, char *out, size_t size);

/* Parses the value at v as field f of a node of `kind` into sp. */
static void parse_field(lua_State *L, int v, int f, limen_node_kind kind, int scene_idx,
                        const char *ctx, spec *sp)
{
    char what[48];
    snprintf(what, sizeof what, "field '%s'", field_names[f]);
    switch ((enum field)f) {
    case F_NAME: {
        size_t len;
        if (lua_type(L, v) != LUA_TSTRING)
            bad(L, v, ctx, what, "a string");
        sp->name = lua_tolstring(L, v, &len);
        if (len > NAME_MAX_LEN || strlen(sp->name) != len)
            luaL_error(L, "%s: %s must be a string of at most %d bytes without zeros", ctx,
                       what, NAME_MAX_LEN);
        /* names reach messages, plans (JSON) and terminals: UTF-8 only */
        for (size_t i = 0, n; i < len; i += n)
            if (!(n = limen__lua_utf8_char((const unsigned char *)sp->name + i, len - i)))
                luaL_error(L, "%s: %s must be UTF-8 text (byte %d is not)", ctx, what, (int)i + 1);
        break;
    }
    case F_PARENT:
        sp->parent = lua_isnil(L, v) ? (limen_node){ 0 } : read_node(L, v, scene_idx, ctx, what, -1);
        break;
    case F_POS: read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->pos); break;
    case F_ROTATE:
        read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->rotate);
        for (int i = 0; i < 3; i++)
            sp->rotate[i] = (float)(sp->rotate[i] * DEG);
        break;
    case F_SCALE: read_scale(L, v, ctx, what, sp->scale); break;
    case F_NORMAL: read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->normal); break;
    case F_UP: read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->up); break;
    case F_LOOK_AT: read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->look_at); break;
    case F_VISIBLE:
    case F_SMOOTH:
        if (!lua_isboolean(L, v))
            bad(L, v, ctx, what, "a boolean");
        *(f == F_VISIBLE ? &sp->visible : &sp->smooth) = lua_toboolean(L, v);
        break;
    case F_FILE:
    case F_TEXTURE: {
        size_t len;
        if (lua_type(L, v) != LUA_TSTRING)
            bad(L, v, ctx, what, "a string");
        const char *file = lua_tolstring(L, v, &len);
        if (len == 0 || strlen(file) != len || len > 1000)
            luaL_error(L, "%s: %s must be a file name (1 to 1000 bytes, no zeros)", ctx, what);
        if (f == F_FILE)
            sp->file = file;
        else
            script_path(L, ctx, file, sp->texture, sizeof sp->texture);
        break;
    }
    case F_COLOR:
        read_vec(L, v, ctx, what, 3, kind == LIMEN_NODE_LIGHT ? ELEM_NONNEG : ELEM_UNIT, sp->color);
        break;
    case F_SIZE:
        read_vec(L, v, ctx, what, kind == LIMEN_NODE_BOX ? 3 : 2, ELEM_POSITIVE, sp->size);
        break;
    case F_RADIUS: sp->radius = read_positive(L, v, ctx, what); break;
    case F_RANGE:
        sp->range = read_number(L, v, ctx, what);
        if (!(sp->range >= 0))
            bad(L, v, ctx, what, "a number >= 0 (0: no range)");
        break;
    case F_HEIGHT: sp->height = read_positive(L, v, ctx, what); break;
    case F_CHECKER: read_checker(L, v, ctx, what, sp); break;
    case F_FOV: {
        float deg = read_number(L, v, ctx, what);
        if (!(deg > 0 && deg < 180))
            bad(L, v, ctx, what, "in (0, 180) degrees");
        sp->fov = (float)(deg * DEG);
        break;
    }
    case F_NEAR: sp->znear = read_positive(L, v, ctx, what); break;
    case F_FAR: sp->zfar = read_positive(L, v, ctx, what); break;
    case F_TINT: read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->tint); break;
    case F_BACK: read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->back); break;
    case F_FILL: read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->fill); break;
    case F_MAX_DEPTH:
        sp->max_depth = read_int(L, v, ctx, what, 0, 255, "an integer in [0, 255]");
        break;
    case F_LINK: sp->link = read_node(L, v, scene_idx, ctx, what, LIMEN_NODE_PORTAL); break;
    case F_COUNT: break;
    }
    sp->have |= BIT(f);
}

/* Checks that need several fields or the node's current state (n may be the zero handle
 * for a node still to be made). */
static void check_spec(lua_State *L, limen_scene *s, limen_node n, const char *ctx, spec *sp)
{
    if (HAVE(sp, F_COLOR) && HAVE(sp, F_CHECKER) && sp->cell > 0)
        luaL_error(L, "%s: fields 'color' and 'checker' cannot be used together (the checker "
                      "gives both colours)", ctx);
    if (HAVE(sp, F_LOOK_AT) && HAVE(sp, F_NORMAL))
        luaL_error(L, "%s: fields 'look_at' and 'normal' cannot be used together", ctx);
    if (HAVE(sp, F_NEAR) || HAVE(sp, F_FAR)) {
        float fovy = 0, zn = 0.05f, zf = 100.0f;
        if (n.id)
            limen_camera_get_lens(s, n, &fovy, &zn, &zf);
        if (HAVE(sp, F_NEAR))
            zn = sp->znear;
        if (HAVE(sp, F_FAR))
            zf = sp->zfar;
        if (!(zf > zn))
            luaL_error(L, "%s: field 'far' (%f) must be greater than 'near' (%f)", ctx,
                       (lua_Number)zf, (lua_Number)zn);
    }
    if (HAVE(sp, F_PARENT) && n.id && sp->parent.id) {
        for (limen_node at = sp->parent; at.id; at = limen_node_get_parent(s, at))
            if (at.id == n.id)
                luaL_error(L, "%s: field 'parent' would make a cycle in the parent chain", ctx);
    }
}

/* Applies the fields of sp to node n; on failure the scene's message says why. */
static limen_status apply_spec(limen_scene *s, limen_node n, const spec *sp)
{
    limen_status st;
#define TRY(call)                                                                        \
    do {                                                                                 \
        if ((st = (call)) != LIMEN_OK)                                                   \
            return st;                                                                   \
    } while (0)
    if (HAVE(sp, F_PARENT))
        TRY(limen_node_set_parent(s, n, sp->parent));
    if (HAVE(sp, F_POS))
        TRY(limen_node_set_position(s, n, sp->pos));
    if (HAVE(sp, F_LOOK_AT)) {
        float eye[3];
        TRY(limen_node_get_position(s, n, eye));
        TRY(limen_node_look_at(s, n, eye, sp->look_at, HAVE(sp, F_UP) ? sp->up : NULL));
    } else if (HAVE(sp, F_NORMAL) || HAVE(sp, F_UP)) {
        static const float z[3] = { 0, 0, 1 };
        TRY(limen_node_set_facing(s, n, HAVE(sp, F_NORMAL) ? sp->normal : z,
                                  HAVE(sp, F_UP) ? sp->up : NULL));
    }
    if (HAVE(sp, F_ROTATE))
        TRY(limen_node_set_rotation(s, n, sp->rotate));
    if (HAVE(sp, F_SCALE))
        TRY(limen_node_set_scale(s, n, sp->scale));
    if (sp->have & (BIT(F_SIZE) | BIT(F_RADIUS) | BIT(F_HEIGHT))) {
        float d[3];
        TRY(limen_node_get_dims(s, n, d));
        if (HAVE(sp, F_SIZE))
            memcpy(d, sp->size, sizeof d);
        if (HAVE(sp, F_RADIUS))
            d[0] = sp->radius;
        if (HAVE(sp, F_HEIGHT))
            d[1] = sp->height;
        TRY(limen_node_set_dims(s, n, d));
    }
    if (HAVE(sp, F_COLOR))
        TRY(limen_node_set_color(s, n, sp->color));
    if (HAVE(sp, F_CHECKER))
        TRY(limen_node_set_checker(s, n, sp->checker_a, sp->checker_b, sp->cell));
    if (HAVE(sp, F_VISIBLE))
        TRY(limen_node_set_visible(s, n, sp->visible));
    if (sp->have & (BIT(F_FOV) | BIT(F_NEAR) | BIT(F_FAR))) {
        float fovy, zn, zf;
        TRY(limen_camera_get_lens(s, n, &fovy, &zn, &zf));
        TRY(limen_camera_set_lens(s, n, HAVE(sp, F_FOV) ? sp->fov : fovy,
                                  HAVE(sp, F_NEAR) ? sp->znear : zn,
                                  HAVE(sp, F_FAR) ? sp->zfar : zf));
    }
    if (HAVE(sp, F_TINT))
        TRY(limen_surface_set_tint(s, n, sp->tint));
    if (HAVE(sp, F_BACK))
        TRY(limen_surface_set_back(s, n, sp->back));
    if (HAVE(sp, F_FILL))
        TRY(limen_surface_set_fill(s, n, sp->fill));
    if (HAVE(sp, F_MAX_DEPTH))
        TRY(limen_surface_set_max_depth(s, n, sp->max_depth));
    if (HAVE(sp, F_LINK))
        TRY(limen_portal_link(s, n, sp->link));
    if (HAVE(sp, F_SMOOTH))
        TRY(limen_mesh_set_smooth(s, n, sp->smooth));
    if (HAVE(sp, F_RANGE))
        TRY(limen_light_set_range(s, n, sp->range));
#undef TRY
    return LIMEN_OK;
}

/* Raises "ctx: <the scene's message>" (the C library's own words). Some messages start
 * with the node's label ("file:line: "), which the Lua error already gives: drop it. */
static int c_error(lua_State *L, limen_scene *s, const char *ctx, const char *label)
{
    char msg[512];
    const char *m = limen_last_error(s);
    size_t n = label ? strlen(label) : 0;
    if (n && strncmp(m, label, n) == 0 && m[n] == ':' && m[n + 1] == ' ')
        m += n + 2;
    snprintf(msg, sizeof msg, "%s", m);
    return luaL_error(L, "%s: %s", ctx, msg);
}

/* c_error for a failed apply_spec: for look_at the core's "normal" is the view direction. */
static int spec_error(lua_State *L, limen_scene *s, const char *ctx, const char *label,
                      const spec *sp)
{
    const char *m = limen_last_error(s);
    if (HAVE(sp, F_LOOK_AT) && strstr(m, "up: must not be zero or parallel"))
        return luaL_error(L, "%s: up: must not be zero or parallel to the view direction (from "
                             "the position to look_at)", ctx);
    return c_error(L, s, ctx, label);
}

/* ------------------------------------------------------------------ node constructors */

/* Reads the constructor table at t (fields in `allowed`) into sp, checking everything;
 * leaves the stack as it found it. String fields stay alive in the table. */
static void read_ctor(lua_State *L, int t, int scene_idx, limen_node_kind kind, unsigned allowed,
                      const char *ctx, limen_scene *s, spec *sp)
{
    int top = lua_gettop(L);
    t = lua_absindex(L, t);
    /* unknown keys first, so that a typo is reported as such */
    lua_pushnil(L);
    while (lua_next(L, t)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            const char *g = got(L, -1);
            luaL_error(L, "%s: fields must be named (got a key %s)", ctx, g);
        }
        const char *key = lua_tostring(L, -1);
        int f = field_index(key);
        if (f < 0)
            unknown_node_field(L, ctx, "unknown field", key, allowed);
        if (!(allowed & BIT(f)) && (kind_fields[kind] & BIT(f)))
            luaL_error(L, "%s: field '%s' cannot be used here", ctx, key);
        if (!(allowed & BIT(f)))
            luaL_error(L, "%s: field '%s' does not apply to a %s", ctx, key, kind_names[kind]);
    }
    memset(sp, 0, sizeof *sp);
    for (int f = 0; f < F_COUNT; f++) {
        if (!(allowed & BIT(f)))
            continue;
        lua_pushstring(L, field_names[f]);
        if (lua_rawget(L, t) != LUA_TNIL)
            parse_field(L, lua_gettop(L), f, kind, scene_idx, ctx, sp);
        lua_settop(L, top);
    }
    check_spec(L, s, (limen_node){ 0 }, ctx, sp);
}

/* "file:line" of the script line that called the running C function. */
static void where(lua_State *L, char label[LABEL_LEN])
{
    luaL_where(L, 1);
    size_t len;
    const char *w = lua_tolstring(L, -1, &len);
    if (len >= 2 && w[len - 2] == ':' && w[len - 1] == ' ')
        len -= 2;
    snprintf(label, LABEL_LEN, "%.*s", (int)len, w);
    lua_pop(L, 1);
}

/* Makes a node from a checked spec and pushes it. On failure destroys it (and `also`, the
 * first half of a pair) and raises "ctx: <the core's message>". */
static limen_node create_node(lua_State *L, int scene_idx, limen_node_kind kind, const spec *sp,
                              const char *ctx, const char *label, limen_node also)
{
    lscene *ls = lua_touserdata(L, scene_idx);
    limen_node n;
    hold_scene(L, ls, limen_scene_node_count(ls->s) + 1);
    limen_status st = limen_node_create(ls->s, kind, sp->name, &n);
    if (st == LIMEN_ERR_NOMEM) {
        int count = limen_scene_node_count(ls->s);
        if (also.id)
            forget_node(L, scene_idx, also);
        luaL_error(L, "%s: the scene is full: it has %d nodes (limen.scene{max_nodes = n} "
                      "allows more)", ctx, count);
    }
    if (!st) {
        st = limen_node_set_label(ls->s, n, label);
        if (!st)
            st = apply_spec(ls->s, n, sp);
        if (!st && kind == LIMEN_NODE_CAMERA)
            st = limen_scene_set_camera(ls->s, n);
        size_t charged = 0;     /* an image, counted against the script's memory cap */
        if (!st && sp->texture[0] &&
            !(st = limen__node_texture(ls->s, n, sp->texture, limen__lua_mem_left(L), &charged))) {
            limen__lua_hold(L, (ptrdiff_t)charged);
            ls->held += charged;
        }
        if (st)
            limen_node_destroy(ls->s, n);   /* leaves the message alone */
    }
    if (st) {
        if (also.id)
            forget_node(L, scene_idx, also);
        spec_error(L, ls->s, ctx, label, sp);
    }
    push_node(L, scene_idx, n);
    lnode *nd = lua_touserdata(L, -1);
    snprintf(nd->label, sizeof nd->label, "%s", label);
    return n;
}

/* s:<kind> { fields }: checks every field, then makes the node. */
static int make_node(lua_State *L, limen_node_kind kind)
{
    lscene *ls = check_scene(L, 1);
    if (lua_isnoneornil(L, 2))
        lua_newtable(L);
    else
        luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    spec sp;
    read_ctor(L, 2, 1, kind, kind_fields[kind], kind_names[kind], ls->s, &sp);
    char label[LABEL_LEN];
    where(L, label);
    create_node(L, 1, kind, &sp, kind_names[kind], label, (limen_node){ 0 });
    return 1;
}

/* Pushes a new table holding the fields of `shared` overridden by those of `own`. */
static void merge_fields(lua_State *L, int shared, int own)
{
    lua_newtable(L);
    for (int src = 0; src < 2; src++) {
        lua_pushnil(L);
        while (lua_next(L, src ? own : shared)) {
            lua_pushvalue(L, -2);
            lua_insert(L, -2);
            lua_rawset(L, -4);
        }
    }
}

/* s:portal_pair({fields of A}, {fields of B} [, {fields for both}]) -> a, b: two portals
 * linked both ways. Both are checked in full before either is made. */
static int l_scene_portal_pair(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    luaL_checktype(L, 3, LUA_TTABLE);
    if (lua_isnoneornil(L, 4)) {
        lua_settop(L, 3);
        lua_newtable(L);
    } else {
        luaL_checktype(L, 4, LUA_TTABLE);
    }
    lua_settop(L, 4);
    const limen_node_kind k = LIMEN_NODE_PORTAL;
    unsigned one = kind_fields[k] & ~BIT(F_LINK);
    spec both, a, b;
    read_ctor(L, 4, 1, k, one & ~BIT(F_NAME), "portal_pair: shared fields", ls->s, &both);
    merge_fields(L, 4, 2);  /* 5 */
    merge_fields(L, 4, 3);  /* 6 */
    read_ctor(L, 5, 1, k, one, "portal_pair: first portal", ls->s, &a);
    read_ctor(L, 6, 1, k, one, "portal_pair: second portal", ls->s, &b);
    char label[LABEL_LEN];
    where(L, label);
    limen_node na = create_node(L, 1, k, &a, "portal_pair: first portal", label, (limen_node){ 0 });
    limen_node nb = create_node(L, 1, k, &b, "portal_pair: second portal", label, na);
    if (limen_portal_link(ls->s, na, nb)) {
        forget_node(L, 1, na);
        forget_node(L, 1, nb);
        return c_error(L, ls->s, "portal_pair", label);
    }
    return 2;
}

static int l_scene_group(lua_State *L) { return make_node(L, LIMEN_NODE_GROUP); }
static int l_scene_box(lua_State *L) { return make_node(L, LIMEN_NODE_BOX); }
static int l_scene_sphere(lua_State *L) { return make_node(L, LIMEN_NODE_SPHERE); }
static int l_scene_cylinder(lua_State *L) { return make_node(L, LIMEN_NODE_CYLINDER); }
static int l_scene_plane(lua_State *L) { return make_node(L, LIMEN_NODE_QUAD); }
static int l_scene_mirror(lua_State *L) { return make_node(L, LIMEN_NODE_MIRROR); }
static int l_scene_portal(lua_State *L) { return make_node(L, LIMEN_NODE_PORTAL); }
static int l_scene_light(lua_State *L) { return make_node(L, LIMEN_NODE_LIGHT); }
static int l_scene_camera(lua_State *L) { return make_node(L, LIMEN_NODE_CAMERA); }

/* ------------------------------------------------------------------ meshes */

/* A mesh or image file named in the calling script: relative to the script's folder. A safe
 * script may read only files under that folder: no absolute path, no "..", and no link
 * that leads out of it (checked on the resolved path). Writes the path to open into out,
 * or raises. */
static void script_path(lua_State *L, const char *ctx, const char *file, char *out, size_t size)
{
    lua_Debug ar;
    char folder[1024] = ".";
    if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "S", &ar) && ar.source[0] == '@') {
        const char *src = ar.source + 1, *slash = strrchr(src, '/');
        if (slash)
            snprintf(folder, sizeof folder, "%.*s", (int)(slash - src), src);
        if (slash == src)
            snprintf(folder, sizeof folder, "/");
    }
    bool safe = lua_getfield(L, LUA_REGISTRYINDEX, LIMEN__LUA_SAFE) == LUA_TBOOLEAN &&
                lua_toboolean(L, -1);
    lua_pop(L, 1);
    if (file[0] == '/') {
        if (safe)
            luaL_error(L, "%s: %s: a safe script reads files only under its own folder (no "
                          "absolute paths)", ctx, file);
        snprintf(out, size, "%s", file);
        return;
    }
    if ((size_t)snprintf(out, size, "%s/%s", folder, file) >= size)
        luaL_error(L, "%s: %s: path too long", ctx, file);
    if (!safe)
        return;
    for (const char *p = file; *p;) {
        size_t n = strcspn(p, "/");
        if (n == 2 && p[0] == '.' && p[1] == '.')
            luaL_error(L, "%s: %s: a safe script reads files only under its own folder (no "
                          "'..')", ctx, file);
        p += n + (p[n] == '/');
    }
    char root[PATH_MAX], real[PATH_MAX];
    if (!realpath(folder, root) || !realpath(out, real))
        return;     /* the load names what is missing */
    size_t rl = strlen(root);
    if (strncmp(real, root, rl) != 0 || (real[rl] != '/' && rl > 1))
        luaL_error(L, "%s: %s: a safe script reads files only under its own folder (it leads "
                      "out of it)", ctx, file);
}

/* s:mesh { file = "bunny.glb", smooth, color, checker, pos, rotate, scale, ... }: the file's
 * triangles (shared with every node of the scene that loads it), its memory counted against
 * the script's cap. */
static int l_scene_mesh(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    spec sp;
    read_ctor(L, 2, 1, LIMEN_NODE_MESH, kind_fields[LIMEN_NODE_MESH], "mesh", ls->s, &sp);
    if (!sp.file)
        return luaL_error(L, "mesh: field 'file' is required");
    char path[1200], label[LABEL_LEN];
    script_path(L, "mesh", sp.file, path, sizeof path);
    where(L, label);
    limen_node n = create_node(L, 1, LIMEN_NODE_MESH, &sp, "mesh", label, (limen_node){ 0 });
    size_t charged;
    limen_status st = limen__mesh_load(ls->s, n, path, limen__lua_mem_left(L), &charged);
    if (st) {
        forget_node(L, 1, n);
        return c_error(L, ls->s, "mesh", label);
    }
    limen__lua_hold(L, (ptrdiff_t)charged);   /* within what was left: never refused */
    ls->held += charged;
    return 1;
}

/* ------------------------------------------------------------------ node fields */

/* The shortest decimal that reads back as f, so that a script that set radius = 0.05
 * reads 0.05 and not 0.050000000745058 (the core stores floats). */
static lua_Number clean(float f)
{
    char buf[32];
    for (int p = 6; p <= 9; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, (double)f);
        double d = strtod(buf, NULL);
        if ((float)d == f)
            return d;
    }
    return f;
}

static void push_float(lua_State *L, float f)
{
    lua_pushnumber(L, clean(f));
}

/* A table of n floats, each multiplied by k (and rounded to float) first. */
static void push_vec(lua_State *L, const float *v, int n, double k)
{
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; i++) {
        push_float(L, (float)(v[i] * k));
        lua_rawseti(L, -2, i + 1);
    }
}

/* Raises the error for a field that node nd cannot read or assign. */
static int field_access_error(lua_State *L, const lnode *nd, const char *ctx, const char *key,
                              int f, const char *unknown)
{
    unsigned allowed = kind_fields[nd->kind] & ~F_CONSTRUCT_ONLY;
    if (f >= 0 && (kind_fields[nd->kind] & BIT(f)))
        return luaL_error(L, "%s: field '%s' is only taken by the constructor (see %s)", ctx, key,
                          f == F_LINK ? "node:link(other)" :
                          f == F_LOOK_AT ? "node:look_at(target, up)" : "node:face(normal, up)");
    if (f >= 0)
        return luaL_error(L, "%s: field '%s' does not apply to a %s", ctx, key,
                          kind_names[nd->kind]);
    return unknown_node_field(L, ctx, unknown, key, allowed);
}

static int l_node_index(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    lua_settop(L, 2);
    char ctx[CTX_LEN];
    node_ctx(nd, ctx, sizeof ctx);
    if (lua_type(L, 2) != LUA_TSTRING) {
        const char *g = got(L, 2);
        return luaL_error(L, "%s: no field %s", ctx, g);
    }
    const char *key = lua_tostring(L, 2);
    if (lua_getfield(L, lua_upvalueindex(1), key) != LUA_TNIL)
        return 1;   /* a method */
    lua_pop(L, 1);
    /* these stay readable after destroy(), for messages and for tostring */
    if (strcmp(key, "kind") == 0) {
        lua_pushstring(L, kind_names[nd->kind]);
        return 1;
    }
    if (strcmp(key, "name") == 0) {
        if (nd->name[0])
            lua_pushstring(L, nd->name);
        else
            lua_pushnil(L);
        return 1;
    }
    if (strcmp(key, "label") == 0) {
        lua_pushstring(L, nd->label);
        return 1;
    }
    limen_scene *s;
    check_node(L, 1, &s);
    limen_node n = nd->n;
    int f = field_index(key);
    unsigned allowed = kind_fields[nd->kind] & ~F_CONSTRUCT_ONLY;
    float v[3] = { 0, 0, 0 };
    if (strcmp(key, "partner") == 0 && nd->kind == LIMEN_NODE_PORTAL) {
        push_node(L, 3, limen_portal_partner(s, n));
        return 1;
    }
    if (f == F_CHECKER && (allowed & BIT(f)))
        return luaL_error(L, "%s: field 'checker' can be assigned but not read", ctx);
    if (f < 0 || !(allowed & BIT(f)))
        return field_access_error(L, nd, ctx, key, f, "no field");
    switch ((enum field)f) {
    case F_PARENT: push_node(L, 3, limen_node_get_parent(s, n)); return 1;
    case F_POS: limen_node_get_position(s, n, v); push_vec(L, v, 3, 1); return 1;
    case F_ROTATE: limen_node_get_rotation(s, n, v); push_vec(L, v, 3, 1 / DEG); return 1;
    case F_SCALE: limen_node_get_scale(s, n, v); push_vec(L, v, 3, 1); return 1;
    case F_VISIBLE: lua_pushboolean(L, limen_node_get_visible(s, n)); return 1;
    case F_COLOR: limen_node_get_color(s, n, v); push_vec(L, v, 3, 1); return 1;
    case F_SIZE:
        limen_node_get_dims(s, n, v);
        push_vec(L, v, nd->kind == LIMEN_NODE_BOX ? 3 : 2, 1);
        return 1;
    case F_RADIUS: limen_node_get_dims(s, n, v); push_float(L, v[0]); return 1;
    case F_HEIGHT: limen_node_get_dims(s, n, v); push_float(L, v[1]); return 1;
    case F_FOV:
    case F_NEAR:
    case F_FAR: {
        float fovy, zn, zf;
        limen_camera_get_lens(s, n, &fovy, &zn, &zf);
        push_float(L, f == F_FOV ? (float)(fovy / DEG) : f == F_NEAR ? zn : zf);
        return 1;
    }
    case F_TINT:
    case F_BACK:
    case F_FILL: {
        float t[3], b[3], fl[3];
        int md;
        limen_surface_get(s, n, t, b, fl, &md);
        push_vec(L, f == F_TINT ? t : f == F_BACK ? b : fl, 3, 1);
        return 1;
    }
    case F_MAX_DEPTH: {
        int md = 0;
        limen_surface_get(s, n, NULL, NULL, NULL, &md);
        lua_pushinteger(L, md);
        return 1;
    }
    case F_RANGE: push_float(L, limen_light_get_range(s, n)); return 1;
    case F_SMOOTH: {
        limen_mesh_info mi;
        limen_mesh_get(s, n, &mi);
        lua_pushboolean(L, mi.smooth);
        return 1;
    }
    default:
        return unknown_node_field(L, ctx, "no field", key, allowed);
    }
}

static int l_node_newindex(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    lua_settop(L, 3);
    char ctx[CTX_LEN];
    node_ctx(nd, ctx, sizeof ctx);
    if (lua_type(L, 2) != LUA_TSTRING) {
        const char *g = got(L, 2);
        return luaL_error(L, "%s: cannot set field %s", ctx, g);
    }
    const char *key = lua_tostring(L, 2);
    limen_scene *s;
    check_node(L, 1, &s);   /* pushes the scene userdata at 4 */
    int f = field_index(key);
    unsigned allowed = kind_fields[nd->kind] & ~F_CONSTRUCT_ONLY;
    if (f == F_NAME || strcmp(key, "kind") == 0 || strcmp(key, "label") == 0 ||
        (strcmp(key, "partner") == 0 && nd->kind == LIMEN_NODE_PORTAL))
        return luaL_error(L, "%s: field '%s' is read-only%s", ctx, key,
                          key[0] == 'p' ? " (use node:link(other))" : "");
    if (f < 0 || !(allowed & BIT(f)))
        return field_access_error(L, nd, ctx, key, f, "cannot set unknown field");
    spec sp;
    memset(&sp, 0, sizeof sp);
    parse_field(L, 3, f, nd->kind, 4, ctx, &sp);
    check_spec(L, s, nd->n, ctx, &sp);
    if (apply_spec(s, nd->n, &sp))
        return spec_error(L, s, ctx, nd->label, &sp);
    return 0;
}

/* ------------------------------------------------------------------ node methods */

static int l_node_destroy(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 1);
    lnode *nd = check_node(L, 1, &s);
    forget_node(L, 2, nd->n);
    return 0;
}

/* node:world() -> the 16 numbers of its world matrix, column-major. */
static int l_node_world(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 1);
    lnode *nd = check_node(L, 1, &s);
    float m[16];
    char ctx[CTX_LEN];
    if (limen_node_world_matrix(s, nd->n, m))
        return c_error(L, s, node_ctx(nd, ctx, sizeof ctx), nd->label);
    push_vec(L, m, 16, 1);
    return 1;
}

/* node:face / node:look_at: a direction (labelled what, into the spec's field f) and an
 * optional up (labelled up_what), applied to the node. */
static int turn_node(lua_State *L, const char *what, const char *up_what, int f)
{
    limen_scene *s;
    lua_settop(L, 3);
    lnode *nd = check_node(L, 1, &s);
    char ctx[CTX_LEN];
    node_ctx(nd, ctx, sizeof ctx);
    spec sp;
    memset(&sp, 0, sizeof sp);
    read_vec(L, 2, ctx, what, 3, ELEM_FINITE, f == F_NORMAL ? sp.normal : sp.look_at);
    sp.have = BIT(f);
    if (!lua_isnoneornil(L, 3)) {
        read_vec(L, 3, ctx, up_what, 3, ELEM_FINITE, sp.up);
        sp.have |= BIT(F_UP);
    }
    if (apply_spec(s, nd->n, &sp))
        return spec_error(L, s, ctx, nd->label, &sp);
    return 0;
}

/* node:face(normal [, up]): turns local +Z to normal and +Y towards up. */
static int l_node_face(lua_State *L)
{
    return turn_node(L, "face: normal", "face: up", F_NORMAL);
}

/* node:look_at(target [, up]): keeps the position, turns -Z towards target. */
static int l_node_look_at(lua_State *L)
{
    return turn_node(L, "look_at: target", "look_at: up", F_LOOK_AT);
}

/* portal:link(other): pairs two portals both ways. */
static int l_node_link(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 2);
    lnode *nd = check_node(L, 1, &s);
    char ctx[CTX_LEN];
    node_ctx(nd, ctx, sizeof ctx);
    if (nd->kind != LIMEN_NODE_PORTAL)
        return luaL_error(L, "%s: link: only portals can be linked", ctx);
    limen_node other = read_node(L, 2, 3, ctx, "link: other", LIMEN_NODE_PORTAL);
    if (other.id == nd->n.id)
        return luaL_error(L, "%s: link: a portal cannot be paired with itself", ctx);
    if (limen_portal_link(s, nd->n, other))
        return c_error(L, s, ctx, nd->label);
    return 0;
}

/* node:move(dx, dy, dz) or node:move{dx, dy, dz}: moves by a world-space displacement,
 * through any portal the node's origin passes. Returns the number of portals passed, the
 * last one (or nil), and the matrix that carries vectors (velocities) the same way. */
static int l_node_move(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 4);
    lnode *nd = check_node(L, 1, &s);   /* pushes the scene userdata at 5 */
    char ctx[CTX_LEN];
    node_ctx(nd, ctx, sizeof ctx);
    float d[3];
    if (lua_istable(L, 2)) {
        read_vec(L, 2, ctx, "move: displacement", 3, ELEM_FINITE, d);
    } else {
        for (int i = 0; i < 3; i++) {
            lua_Number x = luaL_checknumber(L, 2 + i);
            if (!isfinite(x))
                return luaL_error(L, "%s: move: displacement must be finite", ctx);
            d[i] = (float)x;
        }
    }
    limen_move_result mr;
    if (limen_node_move(s, nd->n, d, &mr))
        return c_error(L, s, ctx, nd->label);
    lua_pushinteger(L, mr.crossed);
    push_node(L, 5, mr.portal);
    push_vec(L, mr.matrix, 16, 1);
    return 3;
}

static int l_node_tostring(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    char ctx[CTX_LEN];
    lua_getiuservalue(L, 1, 1);
    lscene *ls = lua_touserdata(L, -1);
    int alive = ls && ls->s && limen_node_valid(ls->s, nd->n);
    lua_pushfstring(L, "limen.%s%s", node_ctx(nd, ctx, sizeof ctx), alive ? "" : " (destroyed)");
    return 1;
}

static const luaL_Reg node_methods[] = {
    { "destroy", l_node_destroy },
    { "world", l_node_world },
    { "face", l_node_face },
    { "look_at", l_node_look_at },
    { "link", l_node_link },
    { "move", l_node_move },
    { NULL, NULL }
};

static const luaL_Reg node_meta[] = {
    { "__newindex", l_node_newindex },
    { "__tostring", l_node_tostring },
    { NULL, NULL }
};

/* ------------------------------------------------------------------ scene fields */

/* s.camera is the constructor s:camera{}, so the scene camera is s.active_camera. */
static const char *const scene_fields[] = { "background", "ambient", "active_camera", "update" };

static int l_scene_index(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    lua_settop(L, 2);
    if (lua_type(L, 2) != LUA_TSTRING) {
        const char *g = got(L, 2);
        return luaL_error(L, "scene: no field %s", g);
    }
    const char *key = lua_tostring(L, 2);
    if (lua_getfield(L, lua_upvalueindex(1), key) != LUA_TNIL)
        return 1;
    lua_pop(L, 1);
    if (strcmp(key, "background") == 0) {
        float rgb[3];
        limen_scene_get_background(ls->s, rgb);
        push_vec(L, rgb, 3, 1);
    } else if (strcmp(key, "ambient") == 0) {
        push_float(L, limen_scene_get_ambient(ls->s));
    } else if (strcmp(key, "active_camera") == 0) {
        push_node(L, 1, limen_scene_get_camera(ls->s));
    } else if (strcmp(key, "update") == 0) {
        limen__lua_push_update(L, 1);
    } else {
        return unknown_field(L, "scene", "no field", key, scene_fields, 4);
    }
    return 1;
}

static void read_ambient(lua_State *L, int idx, const char *ctx, float *out)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        bad(L, idx, ctx, "field 'ambient'", "a number in [0, 1]");
    float a = (float)lua_tonumber(L, idx);
    if (!(a >= 0 && a <= 1))
        bad(L, idx, ctx, "field 'ambient'", "a number in [0, 1]");
    *out = a;
}

static int l_scene_newindex(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    lua_settop(L, 3);
    if (lua_type(L, 2) != LUA_TSTRING) {
        const char *g = got(L, 2);
        return luaL_error(L, "scene: cannot set field %s", g);
    }
    const char *key = lua_tostring(L, 2);
    if (strcmp(key, "background") == 0) {
        float rgb[3];
        read_vec(L, 3, "scene", "field 'background'", 3, ELEM_UNIT, rgb);
        if (limen_scene_set_background(ls->s, rgb))
            return c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "ambient") == 0) {
        float a;
        read_ambient(L, 3, "scene", &a);
        if (limen_scene_set_ambient(ls->s, a))
            return c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "active_camera") == 0) {
        limen_node cam = read_node(L, 3, 1, "scene", "field 'active_camera'", LIMEN_NODE_CAMERA);
        if (limen_scene_set_camera(ls->s, cam))
            return c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "update") == 0) {
        if (!lua_isnil(L, 3) && !lua_isfunction(L, 3))
            return bad(L, 3, "scene", "field 'update'", "a function or nil");
        lua_getiuservalue(L, 1, 1);
        lua_pushvalue(L, 3);
        lua_setfield(L, -2, "update");
    } else {
        return unknown_field(L, "scene", "cannot set unknown field", key, scene_fields, 4);
    }
    return 0;
}

/* ------------------------------------------------------------------ scene methods */

/* s:find(name) -> the first node of that name, or nil. */
static int l_scene_find(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    const char *name = luaL_checkstring(L, 2);
    limen_node n;
    if (limen_node_find(ls->s, name, &n) != LIMEN_OK)
        n.id = 0;
    push_node(L, 1, n);
    return 1;
}

/* s:nodes() -> an array of the live nodes, in the order they were made. */
static int l_scene_nodes(lua_State *L)
{
    check_scene(L, 1);
    lua_settop(L, 1);
    lua_getiuservalue(L, 1, 2);
    lua_newtable(L);
    lua_Integer k = 0;
    lua_pushnil(L);
    while (lua_next(L, 2)) {
        lua_rawseti(L, 3, ++k);
    }
    /* insertion sort by creation order (the map's order is a hash's) */
    for (lua_Integer i = 2; i <= k; i++) {
        lua_rawgeti(L, 3, i);
        const lnode *x = lua_touserdata(L, -1);
        lua_Integer j = i;
        for (; j > 1; j--) {
            lua_rawgeti(L, 3, j - 1);
            const lnode *y = lua_touserdata(L, -1);
            if (y->seq < x->seq) {
                lua_pop(L, 1);
                break;
            }
            lua_rawseti(L, 3, j);
        }
        lua_rawseti(L, 3, j);
    }
    return 1;
}

static int l_scene_len(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    lua_pushinteger(L, limen_scene_node_count(ls->s));
    return 1;
}

static int l_scene_tostring(lua_State *L)
{
    lscene *ls = luaL_checkudata(L, 1, SCENE_MT);
    if (!ls->s)
        lua_pushliteral(L, "limen.scene (collected)");
    else
        lua_pushfstring(L, "limen.scene (%d node%s)", limen_scene_node_count(ls->s),
                        limen_scene_node_count(ls->s) == 1 ? "" : "s");
    return 1;
}

static int l_scene_gc(lua_State *L)
{
    lscene *ls = luaL_checkudata(L, 1, SCENE_MT);
    limen_scene_destroy(ls->s);
    ls->s = NULL;
    limen__lua_hold(L, -(ptrdiff_t)ls->held);
    ls->held = 0;
    return 0;
}

/* ------------------------------------------------------------------ rendering */

static const char *const render_fields[] = { "out", "size", "backend", "time", "msaa",
                                             "method", "clip", "max_depth", "max_views",
                                             "depth", "texture_scale" };
#define RENDER_FIELD_COUNT ((int)(sizeof render_fields / sizeof render_fields[0]))

/* Looks a string field up in a NULL-ended list of choices; returns its index. */
static int read_choice(lua_State *L, int idx, const char *what, const char *const *choices,
                       const char *must)
{
    if (lua_type(L, idx) == LUA_TSTRING) {
        const char *v = lua_tostring(L, idx);
        for (int i = 0; choices[i]; i++)
            if (strcmp(v, choices[i]) == 0)
                return i;
    }
    bad(L, idx, "render", what, must);
    return 0;
}

/* s:render { out = "x.png", size = {w, h}, backend = "osmesa"|"egl", time = t, ... }
 * -> stats { ms, views, fragments, samples, pixels }. */
static int l_scene_render(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    if (lua_isnoneornil(L, 2))
        lua_newtable(L);
    else
        luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    if (lua_getfield(L, LUA_REGISTRYINDEX, LIMEN__LUA_SAFE) == LUA_TBOOLEAN &&
        lua_toboolean(L, -1))
        return luaL_error(L, "render: not available to a scene script run in safe mode "
                             "(the program renders it; --trusted lifts this)");
    lua_pop(L, 1);
    lua_pushnil(L);
    while (lua_next(L, 2)) {
        lua_pop(L, 1);
        int known = 0;
        if (lua_type(L, -1) == LUA_TSTRING)
            for (int i = 0; i < RENDER_FIELD_COUNT; i++)
                known |= strcmp(lua_tostring(L, -1), render_fields[i]) == 0;
        if (!known) {
            if (lua_type(L, -1) != LUA_TSTRING) {
                const char *g = got(L, -1);
                return luaL_error(L, "render: fields must be named (got a key %s)", g);
            }
            return unknown_field(L, "render", "unknown field", lua_tostring(L, -1),
                                 render_fields, RENDER_FIELD_COUNT);
        }
    }

    limen_renderer_desc rd = { 0 };
    limen_render_opts ro = { 0 };
    const char *out = NULL;
    int have_time = 0;
    double t = 0;
    static const char *const backends[] = { "osmesa", "egl", NULL };
    static const char *const methods[] = { "stencil", "texture", NULL };
    static const char *const clips[] = { "oblique", "plane", "none", NULL };
    static const char *const depths[] = { "no", "zo", "zo_reversed", NULL };
    if (lua_getfield(L, 2, "out") != LUA_TNIL) {
        if (lua_type(L, -1) != LUA_TSTRING)
            bad(L, -1, "render", "field 'out'", "a file name");
        out = lua_tostring(L, -1);   /* stays alive in the table */
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "size") != LUA_TNIL) {
        float wh[2];
        read_vec(L, -1, "render", "field 'size'", 2, ELEM_POSITIVE, wh);
        for (int i = 0; i < 2; i++) {
            lua_rawgeti(L, -1, i + 1);
            int v = read_int(L, -1, "render", i ? "field 'size'[2]" : "field 'size'[1]", 1, 16384,
                             "an integer in [1, 16384]");
            *(i ? &rd.height : &rd.width) = v;
            lua_pop(L, 1);
        }
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "backend") != LUA_TNIL)
        rd.backend = (limen_backend)read_choice(L, -1, "field 'backend'", backends,
                                                "\"osmesa\" or \"egl\"");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "time") != LUA_TNIL) {
        if (lua_type(L, -1) != LUA_TNUMBER || !isfinite(lua_tonumber(L, -1)))
            bad(L, -1, "render", "field 'time'", "a finite number");
        t = lua_tonumber(L, -1);
        have_time = 1;
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "msaa") != LUA_TNIL)
        rd.msaa = read_int(L, -1, "render", "field 'msaa'", 0, 64, "an integer in [0, 64]");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "depth") != LUA_TNIL)
        rd.depth_range = (limen_depth_range)read_choice(L, -1, "field 'depth'", depths,
                                                        "\"no\", \"zo\" or \"zo_reversed\"");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "method") != LUA_TNIL)
        ro.method = (limen_method)read_choice(L, -1, "field 'method'", methods,
                                              "\"stencil\" or \"texture\"");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "clip") != LUA_TNIL)
        ro.clip = (limen_clip_method)read_choice(L, -1, "field 'clip'", clips,
                                                 "\"oblique\", \"plane\" or \"none\"");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "max_depth") != LUA_TNIL) {
        ro.limit_depth = 1;
        ro.max_depth = read_int(L, -1, "render", "field 'max_depth'", 0, 255,
                                "an integer in [0, 255]");
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "max_views") != LUA_TNIL)
        ro.max_views = read_int(L, -1, "render", "field 'max_views'", 1, 1 << 20,
                                "a positive integer");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "texture_scale") != LUA_TNIL) {
        float k = read_positive(L, -1, "render", "field 'texture_scale'");
        if (k > 1)
            bad(L, -1, "render", "field 'texture_scale'", "in (0, 1]");
        ro.texture_scale = k;
    }
    lua_pop(L, 1);

    if (have_time && limen__lua_push_update(L, 1) == LUA_TFUNCTION) {
        lua_pushnumber(L, t);
        lua_call(L, 1, 0);   /* its errors are the script's own */
    } else if (have_time) {
        lua_pop(L, 1);
    }

    /* From here on the renderer must be destroyed before any error is raised. */
    limen_renderer *r = NULL;
    limen_frame_stats stats;
    memset(&stats, 0, sizeof stats);
    limen_status st = limen_renderer_create(&rd, &r);
    if (!st)
        st = limen_render_frame(r, ls->s, &ro, &stats);
    if (!st && out)
        st = limen_renderer_write_png(r, out);
    if (st) {
        luaL_where(L, 1);
        lua_pushfstring(L, "render: %s",
                        r && limen_renderer_error(r)[0] ? limen_renderer_error(r) :
                                                          limen_status_string(st));
        lua_concat(L, 2);
        limen_renderer_destroy(r);
        return lua_error(L);
    }
    limen_renderer_destroy(r);
    lua_createtable(L, 0, 5);
    lua_pushnumber(L, stats.ms);
    lua_setfield(L, -2, "ms");
    lua_pushinteger(L, stats.views);
    lua_setfield(L, -2, "views");
    lua_pushinteger(L, (lua_Integer)stats.fragments);
    lua_setfield(L, -2, "fragments");
    lua_pushinteger(L, (lua_Integer)stats.samples);
    lua_setfield(L, -2, "samples");
    lua_pushinteger(L, (lua_Integer)stats.pixels);
    lua_setfield(L, -2, "pixels");
    return 1;
}

/* s:cast(origin, direction [, bounces]): follows a ray through mirrors and portals (the
 * ray tracer's rules) and returns what it hits: { hit, point, normal, distance, node, color,
 * surfaces = { the mirrors and portals passed, in order }, out = { origin, direction of
 * the last segment } }. bounces: a limit on surfaces passed (default: their own limits). */
static int l_scene_cast(lua_State *L)
{
    lscene *ls = check_scene(L, 1);
    lua_settop(L, 4);
    float o[3], d[3];
    read_vec(L, 2, "cast", "origin", 3, ELEM_FINITE, o);
    read_vec(L, 3, "cast", "direction", 3, ELEM_FINITE, d);
    int bounces = -1;
    if (!lua_isnoneornil(L, 4))
        bounces = read_int(L, 4, "cast", "bounces", 0, 255, "an integer in [0, 255]");
    limen_hit h;
    if (limen_ray_cast(ls->s, o, d, bounces, &h))
        return luaL_error(L, "cast: %s", limen_last_error(ls->s));
    lua_createtable(L, 0, 9);
    lua_pushboolean(L, h.hit);
    lua_setfield(L, -2, "hit");
    if (h.hit) {
        push_vec(L, h.point, 3, 1);
        lua_setfield(L, -2, "point");
        push_vec(L, h.normal, 3, 1);
        lua_setfield(L, -2, "normal");
        push_float(L, h.distance);
        lua_setfield(L, -2, "distance");
        push_node(L, 1, h.node);
        lua_setfield(L, -2, "node");
    }
    push_vec(L, h.color, 3, 1);
    lua_setfield(L, -2, "color");
    int n = h.surface_count < LIMEN_HIT_MAX_SURFACES ? h.surface_count : LIMEN_HIT_MAX_SURFACES;
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; i++) {
        push_node(L, 1, h.surfaces[i]);
        lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -2, "surfaces");
    lua_createtable(L, 0, 2);
    push_vec(L, h.seg_origin, 3, 1);
    lua_setfield(L, -2, "origin");
    push_vec(L, h.seg_dir, 3, 1);
    lua_setfield(L, -2, "direction");
    lua_setfield(L, -2, "out");
    return 1;
}

static const luaL_Reg scene_methods[] = {
    { "cast", l_scene_cast },
    { "group", l_scene_group },
    { "box", l_scene_box },
    { "sphere", l_scene_sphere },
    { "cylinder", l_scene_cylinder },
    { "plane", l_scene_plane },
    { "mirror", l_scene_mirror },
    { "portal", l_scene_portal },
    { "portal_pair", l_scene_portal_pair },
    { "light", l_scene_light },
    { "camera", l_scene_camera },
    { "mesh", l_scene_mesh },
    { "find", l_scene_find },
    { "nodes", l_scene_nodes },
    { "render", l_scene_render },
    { NULL, NULL }
};

static const luaL_Reg scene_meta[] = {
    { "__newindex", l_scene_newindex },
    { "__len", l_scene_len },
    { "__tostring", l_scene_tostring },
    { "__gc", l_scene_gc },
    { NULL, NULL }
};

/* ------------------------------------------------------------------ module */

static const char *const scene_ctor_fields[] = { "background", "ambient", "max_nodes" };

/* limen.scene { background = {r, g, b}, ambient = a, max_nodes = n } */
static int l_scene_new(lua_State *L)
{
    if (lua_isnoneornil(L, 1))
        lua_newtable(L);
    else
        luaL_checktype(L, 1, LUA_TTABLE);
    lua_settop(L, 1);
    lua_pushnil(L);
    while (lua_next(L, 1)) {
        lua_pop(L, 1);
        int known = 0;
        if (lua_type(L, -1) == LUA_TSTRING)
            for (int i = 0; i < 3; i++)
                known |= strcmp(lua_tostring(L, -1), scene_ctor_fields[i]) == 0;
        if (!known) {
            if (lua_type(L, -1) != LUA_TSTRING) {
                const char *g = got(L, -1);
                return luaL_error(L, "scene: fields must be named (got a key %s)", g);
            }
            return unknown_field(L, "scene", "unknown field", lua_tostring(L, -1),
                                 scene_ctor_fields, 3);
        }
    }
    float bg[3] = { 0, 0, 0 }, ambient = 0.2f;
    limen_scene_desc desc = { 0 };
    if (lua_getfield(L, 1, "background") != LUA_TNIL)
        read_vec(L, -1, "scene", "field 'background'", 3, ELEM_UNIT, bg);
    lua_pop(L, 1);
    if (lua_getfield(L, 1, "ambient") != LUA_TNIL)
        read_ambient(L, -1, "scene", &ambient);
    lua_pop(L, 1);
    if (lua_getfield(L, 1, "max_nodes") != LUA_TNIL)
        desc.max_nodes = read_int(L, -1, "scene", "field 'max_nodes'", 1, 1 << 19,
                                  "an integer in [1, 524288]");
    lua_pop(L, 1);

    lscene *ls = lua_newuserdatauv(L, sizeof *ls, 2);
    ls->s = NULL;
    ls->seq = 0;
    ls->max_nodes = desc.max_nodes ? desc.max_nodes : 4096;
    ls->held = 0;
    luaL_setmetatable(L, SCENE_MT);   /* from here __gc frees whatever is made */
    hold_scene(L, ls, 0);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 2);
    limen_status st = limen_scene_create(&desc, &ls->s);
    if (st)
        return luaL_error(L, "scene: %s", limen_status_string(st));
    if (limen_scene_set_background(ls->s, bg) || limen_scene_set_ambient(ls->s, ambient))
        return c_error(L, ls->s, "scene", NULL);
    return 1;
}

/* Sets meta's fields and an __index closure over a table of methods. */
static void new_type(lua_State *L, const char *name, const luaL_Reg *meta,
                     const luaL_Reg *methods, lua_CFunction index)
{
    luaL_newmetatable(L, name);
    luaL_setfuncs(L, meta, 0);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_pushcclosure(L, index, 1);
    lua_setfield(L, -2, "__index");
    lua_pushboolean(L, 0);
    lua_setfield(L, -2, "__metatable");   /* scripts cannot swap it (or call __gc) */
    lua_pop(L, 1);
}

/* package.preload["limen.kit"]: runs the built-in lua/limen/kit.lua (text, never bytecode)
 * and returns its table. */
static int load_kit(lua_State *L)
{
    if (luaL_loadbufferx(L, (const char *)limen__lua_kit, limen__lua_kit_len,
                         LIMEN__KIT_CHUNK, "t") != LUA_OK)
        return lua_error(L);
    lua_pushstring(L, "limen.kit");
    lua_call(L, 1, 1);
    return 1;
}

void limen__lua_preload_kit(lua_State *L)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, load_kit);
    lua_setfield(L, -2, "limen.kit");
    lua_pop(L, 1);
}

LIMEN_API int luaopen_limen(lua_State *L)
{
    limen__lua_preload_kit(L);
    new_type(L, SCENE_MT, scene_meta, scene_methods, l_scene_index);
    new_type(L, NODE_MT, node_meta, node_methods, l_node_index);
    lua_createtable(L, 0, 2);
    lua_pushcfunction(L, l_scene_new);
    lua_setfield(L, -2, "scene");
    lua_pushliteral(L, LIMEN_VERSION);
    lua_setfield(L, -2, "version");
    return 1;
}
