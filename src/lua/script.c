/* script.c - runs a Lua scene script in its own state (the limen_script_* API).
 *
 * By default the script gets a safe standard library: base without dofile/loadfile and with
 * a load that takes text only; string, table, math, utf8, coroutine; os.clock/time/date/
 * difftime; no io, no debug; require finds only "limen" (and what is already loaded or in
 * package.preload). desc->trusted opens everything.
 * Errors read "path:line: message" (lua.c's message handler, without the traceback: the
 * program prints one line). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lualib.h>

#include "lua/lua_internal.h"

#define ERR_MAX 1024

struct limen_script {
    lua_State *L;
    limen_scene *scene;         /* owned by the scene userdata, which the registry keeps */
    int scene_ref;
    char err[ERR_MAX];
};

static void set_error(limen_script *sc, const char *msg)
{
    snprintf(sc->err, sizeof sc->err, "%s", msg ? msg : "unknown error");
}

/* lua.c's msghandler without the traceback: makes any error object a string. */
static int msghandler(lua_State *L)
{
    if (lua_type(L, 1) == LUA_TSTRING)
        return 1;
    if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING)
        return 1;
    lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    return 1;
}

/* ------------------------------------------------------------------ the safe library */

/* load(chunk [, chunkname [, mode [, env]]]) with the mode forced to text, whatever the
 * script asks: a binary chunk is refused as "attempt to load a binary chunk (mode is 't')".
 * The argument count is kept, since load tells an absent env from a nil one. */
static int l_safe_load(lua_State *L)
{
    int n = lua_gettop(L);
    if (n < 3) {
        lua_settop(L, 3);
        n = 3;
    }
    lua_pushliteral(L, "t");
    lua_replace(L, 3);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, n, LUA_MULTRET);
    return lua_gettop(L);
}

/* require(name) for modules already loaded or in package.preload; anything else is refused
 * in one line (the stock message lists every searcher, one line each). */
static int l_safe_require(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    lua_settop(L, 1);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    if (lua_getfield(L, 2, name) == LUA_TNIL && lua_getfield(L, 3, name) == LUA_TNIL)
        return luaL_error(L, "module '%s' is not available to a safe scene script", name);
    lua_settop(L, 1);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, 1, LUA_MULTRET);
    return lua_gettop(L);
}

static void remove_fields(lua_State *L, int t, const char *const *names)
{
    for (; *names; names++) {
        lua_pushnil(L);
        lua_setfield(L, t, *names);
    }
}

/* Runs in protected mode: an allocation failure here is an error, not a panic. */
static int open_safe(lua_State *L)
{
    static const luaL_Reg libs[] = {
        { LUA_GNAME, luaopen_base },
        { LUA_LOADLIBNAME, luaopen_package },
        { LUA_COLIBNAME, luaopen_coroutine },
        { LUA_TABLIBNAME, luaopen_table },
        { LUA_STRLIBNAME, luaopen_string },
        { LUA_MATHLIBNAME, luaopen_math },
        { LUA_UTF8LIBNAME, luaopen_utf8 },
        { NULL, NULL }
    };
    for (const luaL_Reg *lib = libs; lib->func; lib++) {
        luaL_requiref(L, lib->name, lib->func, 1);
        lua_pop(L, 1);
    }
    lua_pushglobaltable(L);
    int g = lua_gettop(L);
    static const char *const base_out[] = { "dofile", "loadfile", NULL };
    remove_fields(L, g, base_out);
    lua_getfield(L, g, "load");
    lua_pushcclosure(L, l_safe_load, 1);
    lua_setfield(L, g, "load");

    /* os: the clock only */
    luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
    int os = lua_gettop(L);
    lua_createtable(L, 0, 4);
    static const char *const os_in[] = { "clock", "time", "date", "difftime", NULL };
    for (const char *const *k = os_in; *k; k++) {
        lua_getfield(L, os, *k);
        lua_setfield(L, -2, *k);
    }
    lua_pushvalue(L, -1);
    lua_setfield(L, g, LUA_OSLIBNAME);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_pushvalue(L, -2);
    lua_setfield(L, -2, LUA_OSLIBNAME);
    lua_settop(L, g);

    /* package: only package.preload (limen); no file or C searchers, no loadlib */
    lua_getfield(L, g, LUA_LOADLIBNAME);
    int pkg = lua_gettop(L);
    lua_getfield(L, pkg, "searchers");
    lua_createtable(L, 1, 0);
    lua_rawgeti(L, -2, 1);      /* the preload searcher */
    lua_rawseti(L, -2, 1);
    lua_setfield(L, pkg, "searchers");
    lua_pop(L, 1);
    static const char *const pkg_out[] = { "loadlib", "searchpath", NULL };
    remove_fields(L, pkg, pkg_out);
    lua_pushliteral(L, "");
    lua_setfield(L, pkg, "path");
    lua_pushliteral(L, "");
    lua_setfield(L, pkg, "cpath");
    lua_getfield(L, g, "require");
    lua_pushcclosure(L, l_safe_require, 1);
    lua_setfield(L, g, "require");
    lua_pushboolean(L, 1);
    lua_setfield(L, LUA_REGISTRYINDEX, LIMEN__LUA_SAFE);
    lua_settop(L, 0);
    return 0;
}

static int open_trusted(lua_State *L)
{
    luaL_openlibs(L);
    return 0;
}

/* package.preload.limen = luaopen_limen, in either mode. */
static int preload_limen(lua_State *L)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_limen);
    lua_setfield(L, -2, "limen");
    lua_settop(L, 0);
    return 0;
}

/* ------------------------------------------------------------------ API */

static limen_status fail(limen_script *sc, limen_status st, const char *msg)
{
    set_error(sc, msg);
    return st;
}

limen_status limen_script_load(const char *path, const limen_script_desc *desc,
                               limen_script **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    limen_script *sc = calloc(1, sizeof *sc);
    *out = sc;
    if (!sc)
        return LIMEN_ERR_NOMEM;
    sc->scene_ref = LUA_NOREF;
    if (!path)
        return fail(sc, LIMEN_ERR_ARG, "limen_script_load: no script path");
    lua_State *L = sc->L = luaL_newstate();
    if (!L)
        return fail(sc, LIMEN_ERR_NOMEM, "cannot create a Lua state: out of memory");
    int trusted = desc && desc->trusted;
    lua_pushcfunction(L, trusted ? open_trusted : open_safe);
    if (lua_pcall(L, 0, 0, 0) != LUA_OK)
        return fail(sc, LIMEN_ERR_NOMEM, lua_tostring(L, -1));
    lua_pushcfunction(L, preload_limen);
    if (lua_pcall(L, 0, 0, 0) != LUA_OK)
        return fail(sc, LIMEN_ERR_NOMEM, lua_tostring(L, -1));

    lua_pushcfunction(L, msghandler);
    int st = luaL_loadfilex(L, path, "t");
    if (st != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        limen_status ls = st == LUA_ERRFILE ? LIMEN_ERR_IO :
                          st == LUA_ERRMEM ? LIMEN_ERR_NOMEM : LIMEN_ERR_SCRIPT;
        /* syntax errors carry "path:line:"; the text-only refusal says nothing of where */
        size_t plen = strlen(path);
        if (st == LUA_ERRSYNTAX && msg && strncmp(msg, path, plen) != 0 &&
            strncmp(msg, "...", 3) != 0)
            msg = lua_pushfstring(L, "%s: %s", path, msg);
        return fail(sc, ls, msg);
    }
    st = lua_pcall(L, 0, 1, 1);
    if (st != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        if (msg && strncmp(msg, "(error object", 13) == 0)
            msg = lua_pushfstring(L, "%s: %s", path, msg);
        return fail(sc, st == LUA_ERRMEM ? LIMEN_ERR_NOMEM : LIMEN_ERR_SCRIPT, msg);
    }
    sc->scene = limen__lua_toscene(L, -1);
    if (!sc->scene) {
        char msg[ERR_MAX];
        snprintf(msg, sizeof msg, "%s: script must return a scene (limen.scene{...})", path);
        return fail(sc, LIMEN_ERR_SCRIPT, msg);
    }
    sc->scene_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    lua_settop(L, 0);
    return LIMEN_OK;
}

void limen_script_destroy(limen_script *sc)
{
    if (!sc)
        return;
    if (sc->L)
        lua_close(sc->L);   /* collects the scene userdata, which destroys the scene */
    free(sc);
}

const char *limen_script_error(const limen_script *sc)
{
    return sc ? sc->err : "no script";
}

limen_scene *limen_script_scene(limen_script *sc)
{
    return sc ? sc->scene : NULL;
}

int limen_script_animated(const limen_script *sc)
{
    if (!sc || !sc->scene)
        return 0;
    lua_State *L = sc->L;
    lua_rawgeti(L, LUA_REGISTRYINDEX, sc->scene_ref);
    int t = limen__lua_push_update(L, -1);
    lua_pop(L, 2);
    return t == LUA_TFUNCTION;
}

limen_status limen_script_update(limen_script *sc, double t)
{
    if (!sc)
        return LIMEN_ERR_ARG;
    if (!sc->scene)
        return LIMEN_ERR_SCRIPT;   /* it never loaded; the message says why */
    lua_State *L = sc->L;
    lua_settop(L, 0);
    lua_pushcfunction(L, msghandler);
    lua_rawgeti(L, LUA_REGISTRYINDEX, sc->scene_ref);
    if (limen__lua_push_update(L, 2) != LUA_TFUNCTION) {
        lua_settop(L, 0);
        sc->err[0] = '\0';
        return LIMEN_OK;
    }
    lua_remove(L, 2);
    lua_pushnumber(L, t);
    int st = lua_pcall(L, 1, 0, 1);
    limen_status ls = LIMEN_OK;
    if (st != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        if (msg && strncmp(msg, "(error object", 13) == 0)
            msg = lua_pushfstring(L, "update: %s", msg);
        ls = fail(sc, st == LUA_ERRMEM ? LIMEN_ERR_NOMEM : LIMEN_ERR_SCRIPT, msg);
    } else {
        sc->err[0] = '\0';
    }
    lua_settop(L, 0);
    return ls;
}
