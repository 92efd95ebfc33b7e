/* l_node.c - node userdata: making nodes from checked fields, reading and assigning their
 * fields, and their methods (destroy, world, face, look_at, link, move). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/texture.h"
#include "core/confine.h"
#include "lua/l_api.h"

/* "sphere 'ball'" or "sphere" for an unnamed node. */
const char *limen__lua_node_ctx(const lnode *nd, char *buf, size_t size)
{
    if (nd->name[0])
        snprintf(buf, size, "%s '%s'", limen__lua_kind_name(nd->kind), nd->name);
    else
        snprintf(buf, size, "%s", limen__lua_kind_name(nd->kind));
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
        luaL_error(L, "%s: its scene was collected", limen__lua_node_ctx(nd, ctx, sizeof ctx));
    if (!limen_node_valid(ls->s, nd->n))
        luaL_error(L, "%s has been destroyed", limen__lua_node_ctx(nd, ctx, sizeof ctx));
    *sp = ls->s;
    return nd;
}

/* Pushes the userdata of node n of the scene at scene_idx (nil for the zero handle),
 * making one if the node has none yet. */
void limen__lua_push_node(lua_State *L, int scene_idx, limen_node n)
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
    const char *name = limen_node_get_name(ls->s, n);
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
void limen__lua_forget_node(lua_State *L, int scene_idx, limen_node n)
{
    lscene *ls = lua_touserdata(L, scene_idx);
    lua_getiuservalue(L, scene_idx, 2);
    lua_pushnil(L);
    lua_rawseti(L, -2, (lua_Integer)n.id);
    lua_pop(L, 1);
    limen_node_destroy(ls->s, n);
}

/* ------------------------------------------------------------------ node constructors */

/* "file:line" of the script line that called the running C function. */
void limen__lua_where(lua_State *L, char label[LABEL_LEN])
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
limen_node limen__lua_create_node(lua_State *L, int scene_idx, limen_node_kind kind, const spec *sp,
                                  const char *ctx, const char *label, limen_node also)
{
    lscene *ls = lua_touserdata(L, scene_idx);
    limen_node n;
    limen__lua_hold_scene(L, ls, limen_scene_node_count(ls->s) + 1);
    limen_status st = limen_node_create(ls->s, kind, sp->name, &n);
    if (st == LIMEN_ERR_NOMEM) {
        int count = limen_scene_node_count(ls->s);
        if (also.id)
            limen__lua_forget_node(L, scene_idx, also);
        luaL_error(L, "%s: the scene is full: it has %d nodes (limen.scene{max_nodes = n} "
                      "allows more)", ctx, count);
    }
    if (!st) {
        st = limen_node_set_label(ls->s, n, label);
        if (!st)
            st = limen__lua_apply_spec(ls->s, n, sp);
        if (!st && kind == LIMEN_NODE_CAMERA)
            st = limen_scene_set_camera(ls->s, n);
        size_t charged = 0;     /* an image, counted against the script's memory cap */
        if (!st && sp->texture[0]) {
            limen__load ld;     /* the script's folder and limits (core/confine.h) */
            limen__lua_load_begin(L, ls->s, &ld);
            st = limen__node_texture(ls->s, n, sp->texture, limen__lua_mem_left(L), &charged);
            limen__lua_load_end(L, ls->s, &ld);
            if (!st) {
                limen__lua_hold(L, (ptrdiff_t)charged);
                ls->assets += charged;
            }
        }
        if (st) {
            limen__lua_want(L, limen__scene_take_wanted(ls->s));
            limen_node_destroy(ls->s, n);   /* leaves the message alone */
        }
    }
    if (st) {
        if (also.id)
            limen__lua_forget_node(L, scene_idx, also);
        limen__lua_check_time(L);   /* a contained decode's time may have hit the limit */
        limen__lua_spec_error(L, ls->s, ctx, label, sp);
    }
    limen__lua_check_time(L);
    limen__lua_push_node(L, scene_idx, n);
    lnode *nd = lua_touserdata(L, -1);
    snprintf(nd->label, sizeof nd->label, "%s", label);
    return n;
}

/* ------------------------------------------------------------------ node fields */

/* Raises the error for a field that node nd cannot read or assign. */
static int field_access_error(lua_State *L, const lnode *nd, const char *ctx, const char *key,
                              int f, const char *unknown)
{
    unsigned allowed = limen__lua_kind_fields(nd->kind) & ~F_CONSTRUCT_ONLY;
    if (f == F_FILE || (f == F_TEXTURE && (limen__lua_kind_fields(nd->kind) & BIT(f))))
        return luaL_error(L, "%s: field '%s' is only taken by the constructor", ctx, key);
    if (f >= 0 && (limen__lua_kind_fields(nd->kind) & BIT(f)))
        return luaL_error(L, "%s: field '%s' is only taken by the constructor (see %s)", ctx, key,
                          f == F_LINK ? "node:link(other)" :
                          f == F_LOOK_AT ? "node:look_at(target, up)" : "node:face(normal, up)");
    if (f >= 0)
        return luaL_error(L, "%s: field '%s' does not apply to a %s", ctx, key,
                          limen__lua_kind_name(nd->kind));
    return limen__lua_unknown_node_field(L, ctx, unknown, key, allowed);
}

/* node.bounds -> { lo = {x, y, z}, hi = {x, y, z} }: the world box of what it and the nodes
 * below it show (limen_node_get_bounds), or nil where they show nothing. */
static int push_bounds(lua_State *L, limen_scene *s, limen_node n)
{
    float lo[3], hi[3];
    if (limen_node_get_bounds(s, n, lo, hi) != LIMEN_OK) {
        lua_pushnil(L);
        return 1;
    }
    lua_createtable(L, 0, 2);
    limen__lua_push_vec(L, lo, 3, 1);
    lua_setfield(L, -2, "lo");
    limen__lua_push_vec(L, hi, 3, 1);
    lua_setfield(L, -2, "hi");
    return 1;
}

int limen__lua_node_index(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    lua_settop(L, 2);
    char ctx[CTX_LEN];
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    const char *key = limen__lua_check_key(L, 2, ctx, "no field");
    if (lua_getfield(L, lua_upvalueindex(1), key) != LUA_TNIL)
        return 1;   /* a method */
    lua_pop(L, 1);
    /* these stay readable after destroy(), for messages and for tostring */
    if (strcmp(key, "kind") == 0) {
        lua_pushstring(L, limen__lua_kind_name(nd->kind));
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
    int f = limen__lua_field_index(key);
    unsigned allowed = limen__lua_kind_fields(nd->kind) & ~F_CONSTRUCT_ONLY;
    float v[3] = { 0, 0, 0 };
    if (strcmp(key, "partner") == 0 && nd->kind == LIMEN_NODE_PORTAL) {
        limen__lua_push_node(L, 3, limen_portal_get_partner(s, n));
        return 1;
    }
    if (strcmp(key, "bounds") == 0)
        return push_bounds(L, s, n);
    if (strcmp(key, "triangles") == 0 && nd->kind == LIMEN_NODE_MESH) {
        limen_mesh_info mi;
        lua_pushinteger(L, limen_mesh_get(s, n, &mi) == LIMEN_OK ? mi.triangle_count : 0);
        return 1;
    }
    if (f == F_CHECKER && (allowed & BIT(f)))
        return luaL_error(L, "%s: field 'checker' can be assigned but not read", ctx);
    if (f < 0 || !(allowed & BIT(f)))
        return field_access_error(L, nd, ctx, key, f, "no field");
    switch ((enum field)f) {
    case F_PARENT: limen__lua_push_node(L, 3, limen_node_get_parent(s, n)); return 1;
    case F_POS: limen_node_get_position(s, n, v); limen__lua_push_vec(L, v, 3, 1); return 1;
    case F_ROTATE:
        limen_node_get_rotation(s, n, v);
        limen__lua_push_vec(L, v, 3, 1 / DEG);
        return 1;
    case F_SCALE: limen_node_get_scale(s, n, v); limen__lua_push_vec(L, v, 3, 1); return 1;
    case F_VISIBLE: lua_pushboolean(L, limen_node_get_visible(s, n)); return 1;
    case F_COLOR: limen_node_get_color(s, n, v); limen__lua_push_vec(L, v, 3, 1); return 1;
    case F_SIZE:
        limen_node_get_dims(s, n, v);
        limen__lua_push_vec(L, v, limen_kind_get(nd->kind)->size, 1);
        return 1;
    case F_RADIUS: limen_node_get_dims(s, n, v); limen__lua_push_float(L, v[0]); return 1;
    case F_HEIGHT: limen_node_get_dims(s, n, v); limen__lua_push_float(L, v[1]); return 1;
    case F_FOV:
    case F_NEAR:
    case F_FAR: {
        float fovy, zn, zf;
        limen_camera_get_lens(s, n, &fovy, &zn, &zf);
        limen__lua_push_float(L, f == F_FOV ? (float)(fovy / DEG) : f == F_NEAR ? zn : zf);
        return 1;
    }
    case F_TINT:
    case F_BACK:
    case F_FILL: {
        float t[3], b[3], fl[3];
        int md;
        limen_surface_get(s, n, t, b, fl, &md);
        limen__lua_push_vec(L, f == F_TINT ? t : f == F_BACK ? b : fl, 3, 1);
        return 1;
    }
    case F_MAX_DEPTH: {
        int md = 0;
        limen_surface_get(s, n, NULL, NULL, NULL, &md);
        lua_pushinteger(L, md);
        return 1;
    }
    case F_RANGE: limen__lua_push_float(L, limen_light_get_range(s, n)); return 1;
    case F_TEXTURE_REPEAT:
        limen_node_get_texture_repeat(s, n, v);
        limen__lua_push_vec(L, v, 2, 1);
        return 1;
    case F_FILTER: {
        limen_texture_filter tf = LIMEN_FILTER_TRILINEAR;
        limen_node_get_texture_filter(s, n, &tf);
        lua_pushstring(L, limen__lua_filter_names[tf]);
        return 1;
    }
    case F_SMOOTH: {
        limen_mesh_info mi;
        limen_mesh_get(s, n, &mi);
        lua_pushboolean(L, mi.smooth);
        return 1;
    }
    default:
        return limen__lua_unknown_node_field(L, ctx, "no field", key, allowed);
    }
}

static int l_node_newindex(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    lua_settop(L, 3);
    char ctx[CTX_LEN];
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    const char *key = limen__lua_check_key(L, 2, ctx, "cannot set field");
    limen_scene *s;
    check_node(L, 1, &s);   /* pushes the scene userdata at 4 */
    int f = limen__lua_field_index(key);
    unsigned allowed = limen__lua_kind_fields(nd->kind) & ~F_CONSTRUCT_ONLY;
    if (f == F_NAME || strcmp(key, "kind") == 0 || strcmp(key, "label") == 0 ||
        (strcmp(key, "partner") == 0 && nd->kind == LIMEN_NODE_PORTAL))
        return luaL_error(L, "%s: field '%s' is read-only%s", ctx, key,
                          key[0] == 'p' ? " (use node:link(other))" : "");
    if (f < 0 || !(allowed & BIT(f)))
        return field_access_error(L, nd, ctx, key, f, "cannot set unknown field");
    spec sp;
    memset(&sp, 0, sizeof sp);
    limen__lua_parse_field(L, 3, f, nd->kind, 4, ctx, &sp);
    limen__lua_check_spec(L, s, nd->n, ctx, &sp);
    if (limen__lua_apply_spec(s, nd->n, &sp))
        return limen__lua_spec_error(L, s, ctx, nd->label, &sp);
    return 0;
}

/* ------------------------------------------------------------------ node methods */

static int l_node_destroy(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 1);
    lnode *nd = check_node(L, 1, &s);
    limen__lua_forget_node(L, 2, nd->n);
    return 0;
}

/* node:find(name) -> the first node of that name below it (limen_node_find_below), or nil. */
static int l_node_find(lua_State *L)
{
    limen_scene *s;
    lua_settop(L, 2);
    check_node(L, 1, &s);   /* pushes the scene userdata at 3 */
    lnode *nd = lua_touserdata(L, 1);
    const char *name = luaL_checkstring(L, 2);
    limen_node n;
    if (limen_node_find_below(s, nd->n, name, &n) != LIMEN_OK)
        n.id = 0;
    limen__lua_push_node(L, 3, n);
    return 1;
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
        return limen__lua_c_error(L, s, limen__lua_node_ctx(nd, ctx, sizeof ctx), nd->label);
    limen__lua_push_vec(L, m, 16, 1);
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
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    spec sp;
    memset(&sp, 0, sizeof sp);
    limen__lua_read_vec(L, 2, ctx, what, 3, ELEM_FINITE, f == F_NORMAL ? sp.normal : sp.look_at);
    sp.have = BIT(f);
    if (!lua_isnoneornil(L, 3)) {
        limen__lua_read_vec(L, 3, ctx, up_what, 3, ELEM_FINITE, sp.up);
        sp.have |= BIT(F_UP);
    }
    if (limen__lua_apply_spec(s, nd->n, &sp))
        return limen__lua_spec_error(L, s, ctx, nd->label, &sp);
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
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    if (nd->kind != LIMEN_NODE_PORTAL)
        return luaL_error(L, "%s: link: only portals can be linked", ctx);
    limen_node other = limen__lua_read_node(L, 2, 3, ctx, "link: other", LIMEN_NODE_PORTAL);
    if (other.id == nd->n.id)
        return luaL_error(L, "%s: link: a portal cannot be paired with itself", ctx);
    if (limen_portal_link(s, nd->n, other))
        return limen__lua_c_error(L, s, ctx, nd->label);
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
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    float d[3];
    if (lua_istable(L, 2)) {
        limen__lua_read_vec(L, 2, ctx, "move: displacement", 3, ELEM_FINITE, d);
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
        return limen__lua_c_error(L, s, ctx, nd->label);
    lua_pushinteger(L, mr.crossed);
    limen__lua_push_node(L, 5, mr.portal);
    limen__lua_push_vec(L, mr.matrix, 16, 1);
    return 3;
}

static int l_node_tostring(lua_State *L)
{
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    char ctx[CTX_LEN];
    lua_getiuservalue(L, 1, 1);
    lscene *ls = lua_touserdata(L, -1);
    int alive = ls && ls->s && limen_node_valid(ls->s, nd->n);
    lua_pushfstring(L, "limen.%s%s", limen__lua_node_ctx(nd, ctx, sizeof ctx),
                    alive ? "" : " (destroyed)");
    return 1;
}

const luaL_Reg limen__lua_node_methods[] = {
    { "destroy", l_node_destroy },
    { "world", l_node_world },
    { "face", l_node_face },
    { "look_at", l_node_look_at },
    { "link", l_node_link },
    { "move", l_node_move },
    { "find", l_node_find },
    { "slide", limen__lua_node_slide },
    { NULL, NULL }
};

const luaL_Reg limen__lua_node_meta[] = {
    { "__newindex", l_node_newindex },
    { "__tostring", l_node_tostring },
    { NULL, NULL }
};
