/* lua_internal.h - what the script runner (script.c) needs from the bindings (bindings.c).
 * Not part of the public API; src/lua is the only place that includes lua.h. */
#ifndef LIMEN_LUA_INTERNAL_H
#define LIMEN_LUA_INTERNAL_H

#include <lauxlib.h>
#include <lua.h>

#include "limen.h"

/* Registry field set to true in a state that runs an untrusted script: s:render refuses to
 * write files there. */
#define LIMEN__LUA_SAFE "limen.safe"

/* Opens the module: returns the table { scene = ..., version = ... }. Exported so that a
 * stock lua5.4 can `require "limen"` from limen.so. */
LIMEN_API int luaopen_limen(lua_State *L);

/* The scene owned by the scene userdata at idx, or NULL if idx holds something else. */
limen_scene *limen__lua_toscene(lua_State *L, int idx);

/* Pushes the update function of the scene userdata at idx (nil if none); returns its type. */
int limen__lua_push_update(lua_State *L, int idx);

#endif
