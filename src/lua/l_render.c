/* l_render.c - what a scene looks like from Lua: s:render{} draws it with the OpenGL
 * renderer (stock Lua only), s:cast() follows a ray through mirrors and portals. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "lua/l_api.h"

/* ------------------------------------------------------------------ rendering */

static const char *const render_fields[] = { "out", "size", "backend", "time", "msaa",
                                             "method", "clip", "max_depth", "depth_override",
                                             "max_views", "depth", "texture_scale", "lod" };
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
    limen__lua_bad(L, idx, "render", what, must);
    return 0;
}

/* s:render { out = "x.png", size = {w, h}, backend = "osmesa"|"egl", time = t, ... }
 * -> stats { ms, views, fragments, samples, pixels, draw_calls, triangles }. */
int limen__lua_scene_render(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    limen__lua_table_arg(L, 2);
    if (lua_getfield(L, LUA_REGISTRYINDEX, LIMEN__LUA_SAFE) == LUA_TBOOLEAN &&
        lua_toboolean(L, -1))
        return luaL_error(L, "render: not available to a scene script run in safe mode "
                             "(the program renders it; --trusted lifts this)");
    lua_pop(L, 1);
    limen__lua_check_keys(L, 2, "render", render_fields, RENDER_FIELD_COUNT);

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
            limen__lua_bad(L, -1, "render", "field 'out'", "a file name");
        out = lua_tostring(L, -1);   /* stays alive in the table */
        size_t n = strlen(out);
        int png = n > 4 && strcasecmp(out + n - 4, ".png") == 0;
        int jpg = (n > 4 && strcasecmp(out + n - 4, ".jpg") == 0) ||
                  (n > 5 && strcasecmp(out + n - 5, ".jpeg") == 0);
        if (!png && !jpg)
            limen__lua_bad(L, -1, "render", "field 'out'", "a file name ending in .png, .jpg "
                                                           "or .jpeg");
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "size") != LUA_TNIL) {
        float wh[2];
        limen__lua_read_vec(L, -1, "render", "field 'size'", 2, ELEM_POSITIVE, wh);
        for (int i = 0; i < 2; i++) {
            lua_rawgeti(L, -1, i + 1);
            int v = limen__lua_read_int(L, -1, "render",
                                        i ? "field 'size'[2]" : "field 'size'[1]", 1, 16384,
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
            limen__lua_bad(L, -1, "render", "field 'time'", "a finite number");
        t = lua_tonumber(L, -1);
        have_time = 1;
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "msaa") != LUA_TNIL)
        rd.msaa = limen__lua_read_int(L, -1, "render", "field 'msaa'", 0, 64,
                                      "an integer in [0, 64]");
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
        ro.limits.clip = (limen_clip_method)read_choice(L, -1, "field 'clip'", clips,
                                                 "\"oblique\", \"plane\" or \"none\"");
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "max_depth") != LUA_TNIL) {
        ro.limits.depth_rule = LIMEN_DEPTH_RULE_CAP;
        ro.limits.depth = limen__lua_read_int(L, -1, "render", "field 'max_depth'", 0, 255,
                                              "an integer in [0, 255]");
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "depth_override") != LUA_TNIL) {
        if (ro.limits.depth_rule == LIMEN_DEPTH_RULE_CAP)
            return luaL_error(L, "render: fields 'max_depth' and 'depth_override' exclude "
                                 "each other");
        ro.limits.depth_rule = LIMEN_DEPTH_RULE_OVERRIDE;
        ro.limits.depth = limen__lua_read_int(L, -1, "render", "field 'depth_override'", 0, 255,
                                              "an integer in [0, 255]");
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "max_views") != LUA_TNIL)
        ro.limits.max_views = limen__lua_read_int(L, -1, "render", "field 'max_views'", 1, 1 << 20,
                                                  "a positive integer");
    lua_pop(L, 1);
    /* lod = pixels the error of a mesh's level of detail may cover (limen_limits.lod_pixels),
     * or false for the full meshes */
    if (lua_getfield(L, 2, "lod") == LUA_TBOOLEAN && !lua_toboolean(L, -1)) {
        ro.limits.lod_pixels = LIMEN_LOD_FULL;
    } else if (!lua_isnil(L, -1)) {
        lua_Number px = lua_type(L, -1) == LUA_TNUMBER ? lua_tonumber(L, -1) : -1;
        if (!(px >= 0 && px < HUGE_VAL))
            limen__lua_bad(L, -1, "render", "field 'lod'", "a number of pixels >= 0, or false");
        ro.limits.lod_pixels = (float)px;
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 2, "texture_scale") != LUA_TNIL) {
        float k = limen__lua_read_positive(L, -1, "render", "field 'texture_scale'");
        if (k > 1)
            limen__lua_bad(L, -1, "render", "field 'texture_scale'", "in (0, 1]");
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
    unsigned char *rgb = NULL;
    if (!st && out) {
        int w, h;
        limen_renderer_get_size(r, &w, &h);
        if (!(rgb = malloc((size_t)w * (size_t)h * 3)))
            st = LIMEN_ERR_NOMEM;
        else if (!(st = limen_renderer_read_rgb(r, rgb)) && limen_write_image(out, w, h, rgb))
            st = LIMEN_ERR_IO;
        free(rgb);
        if (st == LIMEN_ERR_IO) {
            limen_renderer_destroy(r);
            return luaL_error(L, "render: cannot write '%s'", out);
        }
    }
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
    lua_createtable(L, 0, 7);
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
    lua_pushinteger(L, stats.draw_calls);
    lua_setfield(L, -2, "draw_calls");
    lua_pushinteger(L, (lua_Integer)stats.triangles);
    lua_setfield(L, -2, "triangles");
    return 1;
}

/* s:cast(origin, direction [, bounces]): follows a ray through mirrors and portals (the
 * ray tracer's rules) and returns what it hits: { hit, point, normal, distance, node, color,
 * surfaces = { the mirrors and portals passed, in order }, out = { origin, direction of
 * the last segment } }. bounces: a limit on surfaces passed (default: their own limits). */
int limen__lua_scene_cast(lua_State *L)
{
    lscene *ls = limen__lua_check_scene(L, 1);
    lua_settop(L, 4);
    float o[3], d[3];
    limen__lua_read_vec(L, 2, "cast", "origin", 3, ELEM_FINITE, o);
    limen__lua_read_vec(L, 3, "cast", "direction", 3, ELEM_FINITE, d);
    limen_limits lim = { 0 };
    if (!lua_isnoneornil(L, 4)) {
        lim.depth_rule = LIMEN_DEPTH_RULE_CAP;
        lim.depth = limen__lua_read_int(L, 4, "cast", "bounces", 0, 255, "an integer in [0, 255]");
    }
    limen_hit h;
    if (limen_ray_cast(ls->s, o, d, &lim, &h))
        return luaL_error(L, "cast: %s", limen_scene_error(ls->s));
    lua_createtable(L, 0, 9);
    lua_pushboolean(L, h.hit);
    lua_setfield(L, -2, "hit");
    if (h.hit) {
        limen__lua_push_vec(L, h.point, 3, 1);
        lua_setfield(L, -2, "point");
        limen__lua_push_vec(L, h.normal, 3, 1);
        lua_setfield(L, -2, "normal");
        limen__lua_push_float(L, h.distance);
        lua_setfield(L, -2, "distance");
        limen__lua_push_node(L, 1, h.node);
        lua_setfield(L, -2, "node");
    }
    limen__lua_push_vec(L, h.color, 3, 1);
    lua_setfield(L, -2, "color");
    int n = h.surface_count < LIMEN_HIT_MAX_SURFACES ? h.surface_count : LIMEN_HIT_MAX_SURFACES;
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; i++) {
        limen__lua_push_node(L, 1, h.surfaces[i]);
        lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -2, "surfaces");
    lua_createtable(L, 0, 2);
    limen__lua_push_vec(L, h.seg_origin, 3, 1);
    lua_setfield(L, -2, "origin");
    limen__lua_push_vec(L, h.seg_dir, 3, 1);
    lua_setfield(L, -2, "direction");
    lua_setfield(L, -2, "out");
    return 1;
}
