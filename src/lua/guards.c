/* guards.c - what keeps a scene script's limits whole in either mode (script.c has the limits
 * themselves), and what a safe script is shown of its values:
 *   - the catchers (pcall, xpcall, coroutine.resume and wrap, coroutine.close, load) raise a
 *     limit's error again instead of returning it: the memory cap, the budget and the time
 *     limit end the script, whatever it catches; xpcall's handler does not run for one;
 *   - a coroutine runs under the script's one budget and clock: resuming it arms its hook;
 *   - load, and the script's own text, compile in slices that charge the budget and look at
 *     the clock, so that compiling a huge string is neither free nor endless;
 *   - print hands its line to the host (limen_script_desc.print), never to stdout;
 *   - a safe script sees no addresses: tostring, print and string.format show "table: #3".
 * The stock functions these replace are Lua 5.4's; they keep their messages. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include <lualib.h>

#include <sys/stat.h>
#include <unistd.h>

#include "core/confine.h"
#include "lua/lua_internal.h"

#define READER_SLOT 5           /* stack slot of load's reader keeping its last piece */
#define PIECE (64 << 10)        /* bytes of source compiled between two looks at the clock */
#define PARSE_BYTES 4           /* bytes of source compiled per instruction charged */
#define FORMAT_FLAGS "-+ #0123456789."

/* Calls the stock function kept as upvalue 1 with the arguments as they are. */
static int call_stock(lua_State *L)
{
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

/* ------------------------------------------------------------------ catchers */

/* ------------------------------------------------------------------ showing values */

/* Safe scripts see no addresses (they would help an attack on the host): a value that would
 * show one (a table, a function, a coroutine, a userdata without __tostring) shows as its type
 * and a number instead, "table: #3", the number counting the values shown so far. */
static const char ids_key = 0;

static lua_Integer value_id(lua_State *L, int idx)
{
    idx = lua_absindex(L, idx);
    if (lua_rawgetp(L, LUA_REGISTRYINDEX, &ids_key) != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_createtable(L, 0, 1);
        lua_pushliteral(L, "k");
        lua_setfield(L, -2, "__mode");
        lua_setmetatable(L, -2);
        lua_pushvalue(L, -1);
        lua_rawsetp(L, LUA_REGISTRYINDEX, &ids_key);
    }
    lua_pushvalue(L, idx);
    lua_Integer id;
    if (lua_rawget(L, -2) == LUA_TNUMBER) {
        id = lua_tointeger(L, -1);
    } else {
        lua_rawgeti(L, -2, 0);
        id = lua_tointeger(L, -1) + 1;
        lua_pop(L, 1);
        lua_pushinteger(L, id);
        lua_rawseti(L, -3, 0);
        lua_pushvalue(L, idx);
        lua_pushinteger(L, id);
        lua_rawset(L, -4);
    }
    lua_pop(L, 2);
    return id;
}

/* Would luaL_tolstring show an address for the value at idx? */
static int shows_address(lua_State *L, int idx)
{
    int t = lua_type(L, idx);
    if (t == LUA_TNIL || t == LUA_TBOOLEAN || t == LUA_TNUMBER || t == LUA_TSTRING)
        return 0;
    if (luaL_getmetafield(L, idx, "__tostring") == LUA_TNIL)
        return 1;
    lua_pop(L, 1);
    return 0;
}

/* luaL_tolstring without addresses: pushes the text of the value at idx. */
const char *limen__lua_show(lua_State *L, int idx, size_t *len)
{
    idx = lua_absindex(L, idx);
    if (!shows_address(L, idx))
        return luaL_tolstring(L, idx, len);
    lua_Integer id = value_id(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING)
        lua_pushfstring(L, "%s: #%I", lua_tostring(L, -1), (LUAI_UACINT)id);
    else
        lua_pushfstring(L, "%s: #%I", luaL_typename(L, idx), (LUAI_UACINT)id);
    if (lua_type(L, -2) == LUA_TSTRING)
        lua_remove(L, -2);
    return lua_tolstring(L, -1, len);
}

static int finish_pcall(lua_State *L, int status, lua_KContext base)
{
    if (status != LUA_OK && status != LUA_YIELD) {
        limen__lua_caught(L, status);
        lua_pushboolean(L, 0);
        lua_pushvalue(L, -2);
        return 2;
    }
    return lua_gettop(L) - (int)base;
}

/* pcall(f, ...) and xpcall(f, msgh, ...) as the stock ones (yields across them included), but
 * a limit's error goes on up. */
static int l_pcall(lua_State *L)
{
    luaL_checkany(L, 1);
    lua_pushboolean(L, 1);
    lua_insert(L, 1);
    return finish_pcall(L, lua_pcallk(L, lua_gettop(L) - 2, LUA_MULTRET, 0, 0, finish_pcall), 0);
}

/* xpcall's message handler runs where the error is raised: inside the count hook when a limit
 * raised it, where hooks are off and a loop in it would never end. So the script's handler is
 * not run for a limit's error (nothing can catch it anyway). */
static int l_handler(lua_State *L)
{
    if (limen__lua_limited(L))
        return 1;
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, 1);
    return 1;
}

static int l_xpcall(lua_State *L)
{
    int n = lua_gettop(L);
    luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_pushvalue(L, 2);
    lua_pushcclosure(L, l_handler, 1);
    lua_replace(L, 2);
    lua_pushboolean(L, 1);
    lua_pushvalue(L, 1);
    lua_rotate(L, 3, 2);        /* f, msgh, true, f, args... */
    return finish_pcall(L, lua_pcallk(L, n - 2, LUA_MULTRET, 2, 2, finish_pcall), 2);
}

/* Resumes co with the n values on top of L. Returns co's status: LUA_OK or LUA_YIELD with its
 * *nres results on top of L, or an error status with its error object there. */
static int resume(lua_State *L, lua_State *co, int n, int *nres)
{
    *nres = 0;
    if (!lua_checkstack(co, n)) {
        lua_pop(L, n);
        lua_pushliteral(L, "too many arguments to resume");
        return LUA_ERRRUN;
    }
    lua_xmove(L, co, n);
    limen__lua_enter(L, co);
    int st = lua_resume(co, L, n, nres);
    limen__lua_leave(L, co, st);
    if (st != LUA_OK && st != LUA_YIELD) {
        lua_xmove(co, L, 1);
        return st;
    }
    if (!lua_checkstack(L, *nres + 1)) {
        lua_pop(co, *nres);
        lua_pushliteral(L, "too many results to resume");
        return LUA_ERRRUN;
    }
    lua_xmove(co, L, *nres);
    return st;
}

static int l_co_resume(lua_State *L)
{
    lua_State *co = lua_tothread(L, 1);
    luaL_argexpected(L, co, 1, "coroutine");
    int nres, st = resume(L, co, lua_gettop(L) - 1, &nres);
    if (st == LUA_OK || st == LUA_YIELD) {
        lua_pushboolean(L, 1);
        lua_insert(L, -(nres + 1));
        return nres + 1;
    }
    lua_pushboolean(L, 0);
    lua_insert(L, -2);
    return 2;
}

/* Closes co's pending to-be-closed variables (Lua code that runs in co). Returns the status,
 * the error object on top of L if it is not LUA_OK. */
static int close_thread(lua_State *L, lua_State *co)
{
    limen__lua_enter(L, co);
    int st = lua_resetthread(co);
    limen__lua_leave(L, co, st);
    if (st != LUA_OK)
        lua_xmove(co, L, 1);
    return st;
}

/* The function coroutine.wrap returns: resumes its coroutine, raising its errors (with the
 * caller's position, as the stock one). */
static int l_co_call(lua_State *L)
{
    lua_State *co = lua_tothread(L, lua_upvalueindex(1));
    int nres, st = resume(L, co, lua_gettop(L), &nres);
    if (st == LUA_OK || st == LUA_YIELD)
        return nres;
    int cst = lua_status(co);
    if (cst != LUA_OK && cst != LUA_YIELD) {   /* it died of the error: close it */
        lua_pop(L, 1);
        st = close_thread(L, co);
        if (st == LUA_OK)
            lua_pushliteral(L, "cannot resume dead coroutine");
    }
    if (st != LUA_ERRMEM && lua_type(L, -1) == LUA_TSTRING) {
        luaL_where(L, 1);
        lua_insert(L, -2);
        lua_concat(L, 2);
    }
    return lua_error(L);
}

static int l_co_wrap(lua_State *L)
{
    lua_pushvalue(L, lua_upvalueindex(1));      /* the stock coroutine.create */
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, 1);
    lua_pushcclosure(L, l_co_call, 1);
    return 1;
}

/* coroutine.close(co): the stock one refuses a running or normal coroutine. */
static int l_co_close(lua_State *L)
{
    lua_State *co = lua_tothread(L, 1);
    luaL_argexpected(L, co, 1, "coroutine");
    lua_Debug ar;
    int st = lua_status(co);
    if (co == L || (st == LUA_OK && lua_getstack(co, 0, &ar)))
        return call_stock(L);
    if (close_thread(L, co) == LUA_OK) {
        lua_pushboolean(L, 1);
        return 1;
    }
    lua_pushboolean(L, 0);
    lua_insert(L, -2);
    return 2;
}

typedef struct piece_reader {
    const char *s;              /* what is left of the current string */
    size_t left;
    int fn;                     /* 1: more comes from the function at stack index 1 */
} piece_reader;

static const char *read_piece(lua_State *L, void *ud, size_t *size)
{
    piece_reader *r = ud;
    if (r->left == 0 && r->fn) {
        luaL_checkstack(L, 2, "too many nested functions");
        lua_pushvalue(L, 1);
        lua_call(L, 0, 1);
        if (lua_isnil(L, -1)) {
            lua_pop(L, 1);
            r->fn = 0;
        } else if (!lua_isstring(L, -1)) {
            luaL_error(L, "reader function must return a string");
        } else {
            lua_replace(L, READER_SLOT);
            r->s = lua_tolstring(L, READER_SLOT, &r->left);
        }
    }
    size_t n = r->left < PIECE ? r->left : PIECE;
    limen__lua_charge(L, (double)n / PARSE_BYTES);
    *size = n;
    r->s += n;
    r->left -= n;
    return n ? r->s - n : NULL;
}

int limen__lua_load_string(lua_State *L, const char *s, size_t len, const char *name,
                           const char *mode)
{
    piece_reader r = { s, len, 0 };
    return lua_load(L, read_piece, &r, name, mode);
}

typedef struct file_reader {
    FILE *f;
    int first;                  /* nothing read yet: a BOM and a '#' line may come */
    int skip_line;              /* in a first line that starts with '#' (kept as its newline) */
    char buf[16 << 10];
} file_reader;

static const char *read_file_piece(lua_State *L, void *ud, size_t *size)
{
    file_reader *r = ud;
    const char *p;
    size_t n;
    do {
        p = r->buf;
        n = fread(r->buf, 1, sizeof r->buf, r->f);
        if (r->first) {
            r->first = 0;
            if (n >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) {
                p += 3;
                n -= 3;
            }
            r->skip_line = n > 0 && *p == '#';
        }
        if (r->skip_line && n > 0) {
            const char *nl = memchr(p, '\n', n);
            r->skip_line = !nl;
            n = nl ? n - (size_t)(nl - p) : 0;
            p = nl ? nl : p;
        }
    } while (r->skip_line && !feof(r->f) && !ferror(r->f));
    limen__lua_charge(L, (double)n / PARSE_BYTES);
    *size = n;
    return n ? p : NULL;
}

int limen__lua_load_file(lua_State *L, const char *path, const char *name)
{
    file_reader *r = lua_newuserdatauv(L, sizeof *r, 0);
    /* a safe script is read through its folder's way in, like every file it names */
    char why[160];
    struct stat file;
    int fd = limen__confine_open(limen__lua_box(L), path, &file, why, sizeof why);
    r->f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!r->f) {
        if (fd >= 0) {
            snprintf(why, sizeof why, "%s", strerror(errno));
            close(fd);
        }
        lua_pushfstring(L, "cannot open %s: %s", path, why);
        return LUA_ERRFILE;
    }
    r->first = 1;
    r->skip_line = 0;
    int st = lua_load(L, read_file_piece, r, name, "t");
    int err = ferror(r->f) ? errno : 0;
    fclose(r->f);
    if (err) {
        lua_pop(L, 1);
        lua_pushfstring(L, "cannot read %s: %s", path, strerror(err));
        return LUA_ERRFILE;
    }
    lua_remove(L, -2);      /* the reader */
    return st;
}

/* load(chunk [, chunkname [, mode [, env]]]), a string or a reader function, as the stock
 * one; upvalue 1 is true in safe mode, where the mode is text whatever the script asks (a
 * binary chunk is refused as "attempt to load a binary chunk (mode is 't')"). */
static int l_load(lua_State *L)
{
    size_t len;
    const char *s = lua_tolstring(L, 1, &len);
    const char *mode = lua_toboolean(L, lua_upvalueindex(1)) ? "t" : luaL_optstring(L, 3, "bt");
    int env = lua_isnone(L, 4) ? 0 : 4;
    int st;
    if (s) {
        st = limen__lua_load_string(L, s, len, luaL_optstring(L, 2, s), mode);
    } else {
        const char *name = luaL_optstring(L, 2, "=(load)");
        luaL_checktype(L, 1, LUA_TFUNCTION);
        lua_settop(L, READER_SLOT);
        piece_reader r = { NULL, 0, 1 };
        st = lua_load(L, read_piece, &r, name, mode);
    }
    if (st == LUA_OK) {
        if (env) {
            lua_pushvalue(L, env);
            if (!lua_setupvalue(L, -2, 1))
                lua_pop(L, 1);
        }
        return 1;
    }
    limen__lua_caught(L, st);
    luaL_pushfail(L);
    lua_insert(L, -2);
    return 2;
}

/* print(...): one line, its values' text separated by tabs, to the host's callback (script.c);
 * upvalue 1 is true in safe mode (no addresses), where without a callback it goes nowhere.
 * Trusted without a callback keeps the stock print. */
static int l_print(lua_State *L)
{
    int n = lua_gettop(L), safe = lua_toboolean(L, lua_upvalueindex(1));
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    for (int i = 1; i <= n; i++) {
        if (i > 1)
            luaL_addchar(&b, '\t');
        if (safe)
            limen__lua_show(L, i, NULL);
        else
            luaL_tolstring(L, i, NULL);
        luaL_addvalue(&b);
    }
    luaL_pushresult(&b);
    size_t len;
    const char *line = lua_tolstring(L, -1, &len);
    limen__lua_print(L, line, len);
    return 0;
}

static int l_safe_tostring(lua_State *L)
{
    luaL_checkany(L, 1);
    limen__lua_show(L, 1, NULL);
    return 1;
}

/* string.format with %p and %s of values that would show an address: the value's number
 * instead ("#3"; "(null)" for a value that is no object, as the stock %p). */
static int l_string_format(lua_State *L)
{
    size_t flen;
    const char *f = luaL_checklstring(L, 1, &flen), *end = f + flen;
    int arg = 1, top = lua_gettop(L), any_p = 0;
    for (const char *p = f; p < end; p++) {
        if (*p != '%' || ++p >= end || *p == '%')
            continue;
        while (p < end && *p && strchr(FORMAT_FLAGS, *p))
            p++;
        if (p >= end || ++arg > top)
            break;
        if (*p == 'p') {
            any_p = 1;
            int t = lua_type(L, arg);
            if (t == LUA_TNIL || t == LUA_TBOOLEAN || t == LUA_TNUMBER)
                lua_pushliteral(L, "(null)");
            else
                lua_pushfstring(L, "#%I", (LUAI_UACINT)value_id(L, arg));
            lua_replace(L, arg);
        } else if (*p == 's' && shows_address(L, arg)) {
            limen__lua_show(L, arg, NULL);
            lua_replace(L, arg);
        }
    }
    if (any_p) {        /* the same format with %p made %s */
        luaL_Buffer b;
        luaL_buffinit(L, &b);
        for (const char *p = f; p < end; p++) {
            luaL_addchar(&b, *p);
            if (*p != '%')
                continue;
            if (p + 1 < end && p[1] == '%') {
                luaL_addchar(&b, *++p);
                continue;
            }
            while (p + 1 < end && p[1] && strchr(FORMAT_FLAGS, p[1]))
                luaL_addchar(&b, *++p);
            if (p + 1 < end && p[1] == 'p') {
                luaL_addchar(&b, 's');
                p++;
            }
        }
        luaL_pushresult(&b);
        lua_replace(L, 1);
    }
    return call_stock(L);
}

/* ------------------------------------------------------------------ opening */

/* Replaces t[name] by the C function f with upvalue `flag` (a boolean). */
static void replace(lua_State *L, int t, const char *name, lua_CFunction f, int flag)
{
    lua_pushboolean(L, flag);
    lua_pushcclosure(L, f, 1);
    lua_setfield(L, t, name);
}

/* Replaces t[name] by f with the stock function as upvalue 1. */
static void wrap_stock(lua_State *L, int t, const char *name, lua_CFunction f)
{
    lua_getfield(L, t, name);
    lua_pushcclosure(L, f, 1);
    lua_setfield(L, t, name);
}

void limen__lua_open_guards(lua_State *L, int safe, int print)
{
    lua_pushglobaltable(L);
    int g = lua_gettop(L);
    replace(L, g, "pcall", l_pcall, 0);
    replace(L, g, "xpcall", l_xpcall, 0);
    replace(L, g, "load", l_load, safe);
    if (print || safe)
        replace(L, g, "print", l_print, safe);
    if (safe) {
        lua_pushcfunction(L, l_safe_tostring);
        lua_setfield(L, g, "tostring");
        if (lua_getfield(L, g, LUA_STRLIBNAME) == LUA_TTABLE)
            wrap_stock(L, lua_gettop(L), "format", l_string_format);
        lua_settop(L, g);
    }
    if (lua_getfield(L, g, LUA_COLIBNAME) == LUA_TTABLE) {
        int co = lua_gettop(L);
        replace(L, co, "resume", l_co_resume, 0);
        wrap_stock(L, co, "close", l_co_close);
        lua_getfield(L, co, "create");
        lua_pushcclosure(L, l_co_wrap, 1);      /* wrap is create, then a resumer */
        lua_setfield(L, co, "wrap");
    }
    lua_settop(L, g - 1);
}
