/* l_scene.c - scene userdata: limen.scene{}, the node constructors (s:box{}, ...), the
 * scene's fields and methods, and luaopen_limen. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/mesh.h"
#include "core/texture.h"
#include "core/model.h"
#include "core/confine.h"
#include "lua/l_api.h"

/* ------------------------------------------------------------------ C-side memory */

/* Counts what ls's scene will hold in C with `count` nodes against the memory cap of the
 * script (a script could otherwise fill and empty scene after scene); past the cap, raises
 * the memory error, as an allocation would. */
void limen__lua_hold_scene(lua_State *L, lscene *ls, int count)
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

lscene *limen__lua_check_scene(lua_State *L, int i)
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

/* ------------------------------------------------------------------ node constructors */

/* s:<kind> { fields }: checks every field, then makes the node. */
static int make_node(lua_State *L, limen_node_kind kind)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    limen__lua_table_arg(L, 2);
    const char *name = limen__lua_kind_name(kind);
    spec sp;
    limen__lua_read_ctor(L, 2, 1, kind, limen__lua_kind_fields(kind), name, ls->s, &sp);
    char label[LABEL_LEN];
    limen__lua_where(L, label);
    limen__lua_create_node(L, 1, kind, &sp, name, label, (limen_node){ 0 });
    return 1;
}

/* After a file's load under the script's limits (limen__lua_load_begin / _end): on failure
 * the node made for it goes and the scene's message is raised (with what memory would have
 * allowed it); the time the load took is charged either way; on success the bytes it holds
 * join the script's (within what was left: never refused). */
static void loaded(lua_State *L, lscene *ls, limen_node n, const char *what, const char *label,
                   limen_status st, size_t charged)
{
    if (st) {
        limen__lua_want(L, limen__scene_take_wanted(ls->s));
        limen__lua_forget_node(L, 1, n);
        limen__lua_check_time(L);
        limen__lua_c_error(L, ls->s, what, label);
        return;
    }
    limen__lua_check_time(L);
    limen__lua_hold(L, (ptrdiff_t)charged);
    ls->assets += charged;
}

/* s:mesh { file = "bunny.glb", smooth, color, checker, pos, rotate, scale, ... }: the file's
 * triangles (shared with every node of the scene that loads it), its memory counted against
 * the script's cap. */
static int l_scene_mesh(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    spec sp;
    limen__lua_read_ctor(L, 2, 1, LIMEN_NODE_MESH, limen__lua_kind_fields(LIMEN_NODE_MESH),
                         "mesh", ls->s, &sp);
    if (!sp.file)
        return luaL_error(L, "mesh: field 'file' is required");
    char path[1200], label[LABEL_LEN];
    limen__lua_script_path(L, "mesh", sp.file, path, sizeof path);
    limen__lua_where(L, label);
    limen_node n = limen__lua_create_node(L, 1, LIMEN_NODE_MESH, &sp, "mesh", label,
                                          (limen_node){ 0 });
    size_t charged;
    limen__load ld;     /* the script's folder and limits (core/confine.h) */
    limen__lua_load_begin(L, ls->s, &ld);
    limen_status st = limen__mesh_load(ls->s, n, path, limen__lua_mem_left(L), &charged);
    limen__lua_load_end(L, ls->s, &ld);
    loaded(L, ls, n, "mesh", label, st, charged);
    return 1;
}

/* ------------------------------------------------------------------ models */

/* s:model { file = "level.glb", cameras = false, lights = false, name, pos, rotate, scale,
 * ... } -> a group holding the file's hierarchy (limen_model_load); its meshes' memory
 * counted against the script's cap. */
static int l_scene_model(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    /* the model's own fields here; the rest, a group's, on a copy (3) */
    const char *file = NULL;
    limen_model_desc desc = { 0 };
    lua_newtable(L);
    lua_pushnil(L);
    while (lua_next(L, 2)) {
        const char *k = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "";
        if (strcmp(k, "file") == 0) {
            size_t len = 0;
            file = lua_type(L, -1) == LUA_TSTRING ? lua_tolstring(L, -1, &len) : NULL;
            if (!file || len == 0 || len > 1000 || strlen(file) != len)
                luaL_error(L, "model: field 'file' must be a file name (1 to 1000 bytes, no "
                              "zeros)");
        } else if (strcmp(k, "cameras") == 0 || strcmp(k, "lights") == 0) {
            if (!lua_isboolean(L, -1))
                limen__lua_bad(L, -1, "model", k[0] == 'c' ? "field 'cameras'"
                                                           : "field 'lights'", "a boolean");
            *(k[0] == 'c' ? &desc.cameras : &desc.lights) = lua_toboolean(L, -1);
        } else {
            lua_pushvalue(L, -2);
            lua_insert(L, -2);
            lua_rawset(L, 3);
            continue;
        }
        lua_pop(L, 1);
    }
    if (!file)
        return luaL_error(L, "model: field 'file' is required");
    spec sp;
    limen__lua_read_ctor(L, 3, 1, LIMEN_NODE_GROUP, limen__lua_kind_fields(LIMEN_NODE_GROUP),
                         "model", ls->s, &sp);
    char path[1200], label[LABEL_LEN];
    limen__lua_script_path(L, "model", file, path, sizeof path);
    limen__lua_where(L, label);
    limen_node group = limen__lua_create_node(L, 1, LIMEN_NODE_GROUP, &sp, "model", label,
                                              (limen_node){ 0 });
    int before = limen_scene_node_count(ls->s);
    size_t charged;
    limen__load ld;     /* the script's folder and limits (core/confine.h), as for s:mesh */
    limen__lua_load_begin(L, ls->s, &ld);
    limen_status st = limen__model_load(ls->s, group, path, &desc, limen__lua_mem_left(L),
                                        &charged);
    limen__lua_load_end(L, ls->s, &ld);
    loaded(L, ls, group, "model", label, st, charged);
    /* the new nodes (the last made) join the scene's table, labelled where the script asked */
    int after = limen_scene_node_count(ls->s);
    limen_node *all = lua_newuserdatauv(L, sizeof *all * (size_t)(after > 0 ? after : 1), 0);
    int n = limen_scene_nodes(ls->s, all, after);
    for (int i = before; i < n && i < after; i++) {
        limen_node_set_label(ls->s, all[i], label);
        limen__lua_push_node(L, 1, all[i]);
        snprintf(((lnode *)lua_touserdata(L, -1))->label, LABEL_LEN, "%s", label);
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    limen__lua_hold_scene(L, ls, after);
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
    lscene *ls = limen__lua_check_scene(L, 1);
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
    unsigned one = limen__lua_kind_fields(k) & ~BIT(F_LINK);
    spec both, a, b;
    limen__lua_read_ctor(L, 4, 1, k, one & ~BIT(F_NAME), "portal_pair: shared fields", ls->s,
                         &both);
    merge_fields(L, 4, 2);  /* 5 */
    merge_fields(L, 4, 3);  /* 6 */
    limen__lua_read_ctor(L, 5, 1, k, one, "portal_pair: first portal", ls->s, &a);
    limen__lua_read_ctor(L, 6, 1, k, one, "portal_pair: second portal", ls->s, &b);
    char label[LABEL_LEN];
    limen__lua_where(L, label);
    limen_node na = limen__lua_create_node(L, 1, k, &a, "portal_pair: first portal", label,
                                           (limen_node){ 0 });
    limen_node nb = limen__lua_create_node(L, 1, k, &b, "portal_pair: second portal", label, na);
    if (limen_portal_link(ls->s, na, nb)) {
        limen__lua_forget_node(L, 1, na);
        limen__lua_forget_node(L, 1, nb);
        return limen__lua_c_error(L, ls->s, "portal_pair", label);
    }
    return 2;
}

/* s:box{}, s:sphere{}, ...: the constructor of the kind in upvalue 1. */
static int l_scene_kind(lua_State *L)
{
    return make_node(L, (limen_node_kind)lua_tointeger(L, lua_upvalueindex(1)));
}

/* A constructor per node kind, named as the kind (limen_kind_get), in the methods table on
 * top of the stack; a kind with one of its own there (s:mesh, which reads a file) keeps it. */
static void kind_constructors(lua_State *L)
{
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        const char *name = limen_kind_get((limen_node_kind)k)->name;
        if (lua_getfield(L, -1, name) == LUA_TNIL) {
            lua_pushinteger(L, k);
            lua_pushcclosure(L, l_scene_kind, 1);
            lua_setfield(L, -3, name);
        }
        lua_pop(L, 1);
    }
}

/* ------------------------------------------------------------------ scene fields */

/* s.camera is the constructor s:camera{}, so the scene camera is s.active_camera. */
static const char *const scene_fields[] = { "background", "ambient", "active_camera", "update" };

static int l_scene_index(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    lua_settop(L, 2);
    const char *key = limen__lua_check_key(L, 2, "scene", "no field");
    if (lua_getfield(L, lua_upvalueindex(1), key) != LUA_TNIL)
        return 1;
    lua_pop(L, 1);
    if (strcmp(key, "background") == 0) {
        float rgb[3];
        limen_scene_get_background(ls->s, rgb);
        limen__lua_push_vec(L, rgb, 3, 1);
    } else if (strcmp(key, "ambient") == 0) {
        limen__lua_push_float(L, limen_scene_get_ambient(ls->s));
    } else if (strcmp(key, "active_camera") == 0) {
        limen__lua_push_node(L, 1, limen_scene_get_camera(ls->s));
    } else if (strcmp(key, "update") == 0) {
        limen__lua_push_update(L, 1);
    } else {
        return limen__lua_unknown_field(L, "scene", "no field", key, scene_fields, 4);
    }
    return 1;
}

static void read_ambient(lua_State *L, int idx, const char *ctx, float *out)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        limen__lua_bad(L, idx, ctx, "field 'ambient'", "a number in [0, 1]");
    float a = (float)lua_tonumber(L, idx);
    if (!(a >= 0 && a <= 1))
        limen__lua_bad(L, idx, ctx, "field 'ambient'", "a number in [0, 1]");
    *out = a;
}

static int l_scene_newindex(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    lua_settop(L, 3);
    const char *key = limen__lua_check_key(L, 2, "scene", "cannot set field");
    if (strcmp(key, "background") == 0) {
        float rgb[3];
        limen__lua_read_vec(L, 3, "scene", "field 'background'", 3, ELEM_UNIT, rgb);
        if (limen_scene_set_background(ls->s, rgb))
            return limen__lua_c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "ambient") == 0) {
        float a;
        read_ambient(L, 3, "scene", &a);
        if (limen_scene_set_ambient(ls->s, a))
            return limen__lua_c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "active_camera") == 0) {
        limen_node cam = limen__lua_read_node(L, 3, 1, "scene", "field 'active_camera'",
                                              LIMEN_NODE_CAMERA);
        if (limen_scene_set_camera(ls->s, cam))
            return limen__lua_c_error(L, ls->s, "scene", NULL);
    } else if (strcmp(key, "update") == 0) {
        if (!lua_isnil(L, 3) && !lua_isfunction(L, 3))
            return limen__lua_bad(L, 3, "scene", "field 'update'", "a function or nil");
        lua_getiuservalue(L, 1, 1);
        lua_pushvalue(L, 3);
        lua_setfield(L, -2, "update");
    } else {
        return limen__lua_unknown_field(L, "scene", "cannot set unknown field", key, scene_fields,
                                        4);
    }
    return 0;
}

/* ------------------------------------------------------------------ scene methods */

/* s:find(name) -> the first node of that name, or nil. */
static int l_scene_find(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    const char *name = luaL_checkstring(L, 2);
    limen_node n;
    if (limen_node_find(ls->s, name, &n) != LIMEN_OK)
        n.id = 0;
    limen__lua_push_node(L, 1, n);
    return 1;
}

typedef struct node_order {
    lua_Integer seq;
    lua_Integer at;             /* index in the unsorted array */
} node_order;

static int by_seq(const void *a, const void *b)
{
    lua_Integer x = ((const node_order *)a)->seq, y = ((const node_order *)b)->seq;
    return (x > y) - (x < y);
}

/* s:nodes() -> an array of the live nodes, in the order they were made (the map's order is a
 * hash's): sorted in n log n, charged to the script's budget. */
static int l_scene_nodes(lua_State *L)
{
    limen__lua_check_scene(L, 1);
    lua_settop(L, 1);
    lua_getiuservalue(L, 1, 2);
    lua_newtable(L);
    lua_Integer k = 0;
    lua_pushnil(L);
    while (lua_next(L, 2)) {
        lua_rawseti(L, 3, ++k);
    }
    if (k > 1)
        limen__lua_charge(L, (double)k * log2((double)k));
    node_order *order = lua_newuserdatauv(L, (size_t)(k > 0 ? k : 1) * sizeof *order, 0);
    for (lua_Integer i = 1; i <= k; i++) {
        lua_rawgeti(L, 3, i);
        order[i - 1].seq = ((const lnode *)lua_touserdata(L, -1))->seq;
        order[i - 1].at = i;
        lua_pop(L, 1);
    }
    qsort(order, (size_t)k, sizeof *order, by_seq);
    lua_createtable(L, (int)(k < 1 << 24 ? k : 0), 0);
    for (lua_Integer i = 1; i <= k; i++) {
        lua_rawgeti(L, 3, order[i - 1].at);
        lua_rawseti(L, -2, i);
    }
    return 1;
}

static int l_scene_len(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    lua_pushinteger(L, limen_scene_node_count(ls->s));
    return 1;
}

/* s:warnings(): what loading its files noticed, a list of "file: warning: text" lines. */
static int l_scene_warnings(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    int n = limen_scene_warning_count(ls->s);
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; i++) {
        lua_pushstring(L, limen_scene_warning(ls->s, i));
        lua_rawseti(L, -2, i + 1);
    }
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
    limen__lua_hold(L, -(ptrdiff_t)(ls->held + ls->assets));
    ls->held = ls->assets = 0;
    return 0;
}

static const luaL_Reg scene_methods[] = {
    { "cast", limen__lua_scene_cast },
    { "mesh", l_scene_mesh },
    { "model", l_scene_model },
    { "portal_pair", l_scene_portal_pair },     /* and s:<kind> (kind_constructors) */
    { "find", l_scene_find },
    { "nodes", l_scene_nodes },
    { "render", limen__lua_scene_render },
    { "warnings", l_scene_warnings },
    { "sweep", limen__lua_scene_sweep },
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
    limen__lua_table_arg(L, 1);
    limen__lua_check_keys(L, 1, "scene", scene_ctor_fields, 3);
    float bg[3] = { 0, 0, 0 }, ambient = 0.2f;
    limen_scene_desc desc = { 0 };
    if (lua_getfield(L, 1, "background") != LUA_TNIL)
        limen__lua_read_vec(L, -1, "scene", "field 'background'", 3, ELEM_UNIT, bg);
    lua_pop(L, 1);
    if (lua_getfield(L, 1, "ambient") != LUA_TNIL)
        read_ambient(L, -1, "scene", &ambient);
    lua_pop(L, 1);
    if (lua_getfield(L, 1, "max_nodes") != LUA_TNIL)
        desc.max_nodes = limen__lua_read_int(L, -1, "scene", "field 'max_nodes'", 1, 1 << 19,
                                             "an integer in [1, 524288]");
    lua_pop(L, 1);

    lscene *ls = lua_newuserdatauv(L, sizeof *ls, 2);
    ls->s = NULL;
    ls->seq = 0;
    ls->max_nodes = desc.max_nodes ? desc.max_nodes : INT_MAX;   /* the pool grows */
    ls->held = ls->assets = 0;
    luaL_setmetatable(L, SCENE_MT);   /* from here __gc frees whatever is made */
    limen__lua_hold_scene(L, ls, 0);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 2);
    limen_status st = limen_scene_create(&desc, &ls->s);
    if (st)
        return luaL_error(L, "scene: %s", limen_status_string(st));
    if (limen_scene_set_background(ls->s, bg) || limen_scene_set_ambient(ls->s, ambient))
        return limen__lua_c_error(L, ls->s, "scene", NULL);
    return 1;
}

/* Sets meta's fields and an __index closure over a table of methods (which `more`, unless
 * NULL, adds to). */
static void new_type(lua_State *L, const char *name, const luaL_Reg *meta,
                     const luaL_Reg *methods, lua_CFunction index, void (*more)(lua_State *))
{
    luaL_newmetatable(L, name);
    luaL_setfuncs(L, meta, 0);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    if (more)
        more(L);
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
    new_type(L, SCENE_MT, scene_meta, scene_methods, l_scene_index, kind_constructors);
    new_type(L, NODE_MT, limen__lua_node_meta, limen__lua_node_methods, limen__lua_node_index,
             NULL);
    lua_createtable(L, 0, 2);
    lua_pushcfunction(L, l_scene_new);
    lua_setfield(L, -2, "scene");
    lua_pushliteral(L, LIMEN_VERSION);
    lua_setfield(L, -2, "version");
    return 1;
}
