/* l_collide.c - collision from scripts: s:sweep{...} (a sphere or a capsule swept through the
 * scene and its portals) and node:slide{...} (collide and slide). */
#include <stdbool.h>
#include <stdio.h>
#include <math.h>
#include <string.h>

#include "lua/l_api.h"

/* Sets what a sweep and a slide both tell of the portals crossed in the table on top of the
 * stack: portals (how many), portal (the last, a node of the scene at index `scene`), matrix
 * (the move through them) and radius (the radius on the far side). */
static void set_crossing(lua_State *L, int scene, int crossed, limen_node portal,
                         const float matrix[16], float radius)
{
    lua_pushinteger(L, crossed);
    lua_setfield(L, -2, "portals");
    limen__lua_push_node(L, scene, portal);
    lua_setfield(L, -2, "portal");
    limen__lua_push_vec(L, matrix, 16, 1);
    lua_setfield(L, -2, "matrix");
    limen__lua_push_float(L, radius);
    lua_setfield(L, -2, "radius");
}

/* s:sweep { from = {x, y, z}, to = {x, y, z}, radius = r [, segment = {x, y, z}]
 *           [, ignore = node] [, depth = n] }
 * -> { hit, fraction, centre, point, normal, node, portals, portal, matrix, radius } */
int limen__lua_scene_sweep(lua_State *L)
{
    static const char *const keys[] = { "from", "to", "radius", "segment", "ignore", "depth" };
    lscene *ls = limen__lua_check_scene(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    limen__lua_check_keys(L, 2, "sweep", keys, 6);
    float from[3], to[3], seg[3] = { 0, 0, 0 }, radius;
    lua_getfield(L, 2, "from");
    limen__lua_read_vec(L, -1, "sweep", "field 'from'", 3, ELEM_FINITE, from);
    lua_getfield(L, 2, "to");
    limen__lua_read_vec(L, -1, "sweep", "field 'to'", 3, ELEM_FINITE, to);
    lua_getfield(L, 2, "radius");
    radius = limen__lua_read_positive(L, -1, "sweep", "field 'radius'");
    bool capsule = lua_getfield(L, 2, "segment") != LUA_TNIL;
    if (capsule)
        limen__lua_read_vec(L, -1, "sweep", "field 'segment'", 3, ELEM_FINITE, seg);
    limen_sweep_opts opts = { 0 };
    if (lua_getfield(L, 2, "ignore") != LUA_TNIL)
        opts.ignore = limen__lua_read_node(L, -1, 1, "sweep", "field 'ignore'", -1);
    if (lua_getfield(L, 2, "depth") != LUA_TNIL) {
        opts.limits.depth_rule = LIMEN_DEPTH_RULE_CAP;
        opts.limits.depth = limen__lua_read_int(L, -1, "sweep", "field 'depth'", 0, 255,
                                                "an integer in [0, 255]");
    }
    limen_sweep_result r;
    limen_status st;
    if (capsule) {
        float a[3], b[3], d[3];
        for (int k = 0; k < 3; k++) {
            a[k] = from[k] - 0.5f * seg[k];
            b[k] = from[k] + 0.5f * seg[k];
            d[k] = to[k] - from[k];
        }
        st = limen_sweep_capsule(ls->s, a, b, radius, d, &opts, &r);
    } else {
        st = limen_sweep_sphere(ls->s, from, to, radius, &opts, &r);
    }
    if (st)
        return luaL_error(L, "sweep: %s", limen_scene_error(ls->s));
    lua_createtable(L, 0, 10);
    lua_pushboolean(L, r.hit);
    lua_setfield(L, -2, "hit");
    limen__lua_push_float(L, r.fraction);
    lua_setfield(L, -2, "fraction");
    limen__lua_push_vec(L, r.centre, 3, 1);
    lua_setfield(L, -2, "centre");
    if (r.hit) {
        limen__lua_push_vec(L, r.point, 3, 1);
        lua_setfield(L, -2, "point");
        limen__lua_push_vec(L, r.normal, 3, 1);
        lua_setfield(L, -2, "normal");
        limen__lua_push_node(L, 1, r.node);
        lua_setfield(L, -2, "node");
    }
    set_crossing(L, 1, r.portals, r.portal, r.matrix, r.radius);
    return 1;
}

/* node:slide { by = {dx, dy, dz}, radius = r [, segment = {x, y, z}] }
 * -> { moved, contacts, normal, portals, portal, matrix, radius } */
int limen__lua_node_slide(lua_State *L)
{
    static const char *const keys[] = { "by", "radius", "segment" };
    lnode *nd = luaL_checkudata(L, 1, NODE_MT);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_settop(L, 2);
    lua_getiuservalue(L, 1, 1);     /* the scene userdata, at 3 */
    lscene *ls = lua_touserdata(L, 3);
    char ctx[CTX_LEN];
    limen__lua_node_ctx(nd, ctx, sizeof ctx);
    if (!ls || !ls->s)
        return luaL_error(L, "%s: its scene was collected", ctx);
    if (!limen_node_valid(ls->s, nd->n))
        return luaL_error(L, "%s has been destroyed", ctx);
    char what[CTX_LEN + 16];
    snprintf(what, sizeof what, "%s: slide", ctx);
    limen__lua_check_keys(L, 2, what, keys, 3);
    float by[3], radius;
    lua_getfield(L, 2, "by");
    limen__lua_read_vec(L, -1, what, "field 'by'", 3, ELEM_FINITE, by);
    lua_getfield(L, 2, "radius");
    radius = limen__lua_read_positive(L, -1, what, "field 'radius'");
    float seg[3];
    bool capsule = lua_getfield(L, 2, "segment") != LUA_TNIL;
    if (capsule)
        limen__lua_read_vec(L, -1, what, "field 'segment'", 3, ELEM_FINITE, seg);
    limen_slide_result r;
    if (capsule ? limen_node_slide_capsule(ls->s, nd->n, by, radius, seg, &r)
                : limen_node_slide(ls->s, nd->n, by, radius, &r))
        return limen__lua_c_error(L, ls->s, ctx, nd->label);
    lua_createtable(L, 0, 7);
    limen__lua_push_vec(L, r.moved, 3, 1);
    lua_setfield(L, -2, "moved");
    lua_pushinteger(L, r.contacts);
    lua_setfield(L, -2, "contacts");
    limen__lua_push_vec(L, r.normal, 3, 1);
    lua_setfield(L, -2, "normal");
    set_crossing(L, 3, r.crossed, r.portal, r.matrix, r.radius);
    return 1;
}
