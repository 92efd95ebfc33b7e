/* lua_internal.h - what the script runner (script.c), its safe library (safe.c) and the
 * bindings (bindings.c) need from each other. Not part of the public API; src/lua is the
 * only place that includes lua.h. */
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

/* script.c: charges `steps` to the instruction budget of the running call; raises "script
 * exceeded its instruction budget" (and stops the script) if there is not that much left.
 * A no-op in a state that is not a limen_script's (a stock lua5.4 with limen.so). */
void limen__lua_charge(lua_State *L, double steps);
/* Counts `bytes` held outside the Lua state (a scene's C-side nodes) against the memory cap
 * of the script running in L, or gives them back if negative. Returns 0, counting nothing,
 * if that would pass the cap. Always 1 in a state that is not a limen_script's. */
int limen__lua_hold(lua_State *L, ptrdiff_t bytes);
/* Notes the calling script line as the place of a memory error that may follow (Lua gives
 * memory errors no place, and no message handler runs for them). */
void limen__lua_note_line(lua_State *L);
/* Instructions left to the running call (HUGE_VAL without a budget). */
double limen__lua_budget_left(lua_State *L);
/* Length of the valid UTF-8 sequence at s (at most n bytes); 0 if none starts there. */
size_t limen__lua_utf8_char(const unsigned char *s, size_t n);
/* Loads a script held in memory, as limen_script_load does a file; `name` stands for the path
 * in messages. For the fuzzer and for tests. */
limen_status limen__script_load_buffer(const char *name, const char *buf, size_t len,
                                       const limen_script_desc *desc, limen_script **out);

/* safe.c: opens the safe standard library in L (call it under lua_pcall). */
int limen__lua_open_safe(lua_State *L);

#endif
