/* script.c - runs a Lua scene script in its own state (the limen_script_* API), within limits.
 *
 * Each script has its own lua_State, and in it:
 *   - a memory cap: the state's allocator (script_alloc) counts the bytes it holds and refuses
 *     an allocation that would take it past the cap; Lua turns that into "not enough memory".
 *     The bindings count the scenes' C-side node slots too (limen__lua_hold);
 *   - an instruction budget per load and per update call: a count hook (script_hook) adds up
 *     VM instructions, and the allocator charges one instruction per ALLOC_BYTES allocated
 *     (copying a long string is work too). Library functions whose work grows with their
 *     arguments charge it themselves (safe.c, limen__lua_charge);
 *   - a time limit that follows from the budget (NS_PER_INSTRUCTION each, at least a
 *     second), for the few VM instructions whose time grows with their operands: comparing
 *     two distinct 32 MiB strings is one instruction. The hook reads a monotonic clock; on a
 *     thread whose instructions turn out slow it comes every SLOW_EVERY instructions.
 * Once a call runs out of budget, every later instruction of the state raises the error again,
 * so a script cannot catch it with pcall and go on; the error reaches the caller and the
 * script is stopped for good (further updates fail at once with the same message). A call
 * that fails for want of memory stops it too.
 * By default the script gets the safe standard library of safe.c; desc->trusted opens all.
 * Errors read "path:line: message" (lua.c's message handler, without the traceback: the
 * program prints one line), on one line, with control bytes and invalid UTF-8 escaped. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lualib.h>

#include "lua/lua_internal.h"

#define ERR_MAX 1024
#define WHERE_MAX 256
#define DEFAULT_BUDGET 50000000
#define DEFAULT_MEMORY (64 << 20)
#define HOOK_EVERY 1000         /* instructions between two calls of the count hook */
#define ALLOC_BYTES 32          /* bytes allocated that cost one instruction */
#define NS_PER_INSTRUCTION 100  /* time limit per instruction of budget; ten times the usual */
#define SLOW_EVERY 16           /* hook interval on a thread whose instructions are slow */

struct limen_script {
    lua_State *L;
    limen_scene *scene;         /* owned by the scene userdata, which the registry keeps */
    int scene_ref;
    char *path;                 /* for messages that have no line */

    /* limits (see the top of the file) */
    int64_t budget;             /* instructions per call; < 0: none */
    size_t mem_cap;             /* bytes; 0: none */
    size_t mem_used;
    int hook_every;
    int running;                /* a load or an update is under way: charge the budget */
    int64_t spent;              /* instructions charged to this call */
    double time_limit;          /* seconds per call; 0: none */
    double started, last_hook;  /* monotonic clock at the start of the call, at the last hook */
    int over_budget;            /* this call ran out of instructions (or time) */
    int over_time;              /* ... of time */
    int mem_refused;            /* the cap refused an allocation during this call */
    int tracking;               /* line hook on: the state holds over half its cap */
    int stopped;                /* a limit stopped the script: update fails at once */
    char where[WHERE_MAX];      /* "file:line" where a limit was hit, if known */
    char line[WHERE_MAX];       /* "file:line" last seen by the line hook */
    char err[ERR_MAX];
};

/* ------------------------------------------------------------------ messages */

/* Length of the valid UTF-8 sequence at s (at most n bytes), 0 if there is none. */
size_t limen__lua_utf8_char(const unsigned char *s, size_t n)
{
    if (n == 0)
        return 0;
    if (s[0] < 0x80)
        return 1;
    size_t len = s[0] >= 0xC2 && s[0] <= 0xDF ? 2 : s[0] >= 0xE0 && s[0] <= 0xEF ? 3 :
                 s[0] >= 0xF0 && s[0] <= 0xF4 ? 4 : 0;
    if (len == 0 || len > n)
        return 0;
    for (size_t i = 1; i < len; i++)
        if ((s[i] & 0xC0) != 0x80)
            return 0;
    /* overlong forms, surrogates and code points past U+10FFFF */
    if ((s[0] == 0xE0 && s[1] < 0xA0) || (s[0] == 0xED && s[1] >= 0xA0) ||
        (s[0] == 0xF0 && s[1] < 0x90) || (s[0] == 0xF4 && s[1] >= 0x90))
        return 0;
    return len;
}

/* Copies msg into the script's message on one line: control bytes and bytes that are not
 * UTF-8 become \n, \t, \xNN, so that a message is always one printable line. */
static void set_error(limen_script *sc, const char *msg)
{
    const unsigned char *s = (const unsigned char *)(msg ? msg : "unknown error");
    size_t n = strlen((const char *)s), o = 0;
    char *out = sc->err;
    while (n && o + 5 < ERR_MAX) {
        size_t len = limen__lua_utf8_char(s, n);
        if (len == 1 && (s[0] < 0x20 || s[0] == 0x7F))
            len = 0;
        if (len) {
            if (o + len >= ERR_MAX)
                break;
            memcpy(out + o, s, len);
            o += len;
        } else if (s[0] == '\n') {
            o += (size_t)snprintf(out + o, ERR_MAX - o, "\\n");
            len = 1;
        } else if (s[0] == '\t') {
            o += (size_t)snprintf(out + o, ERR_MAX - o, "\\t");
            len = 1;
        } else {
            o += (size_t)snprintf(out + o, ERR_MAX - o, "\\x%02X", s[0]);
            len = 1;
        }
        s += len;
        n -= len;
    }
    out[o] = '\0';
}

/* Built-in Lua (limen.kit) is not where a script goes wrong: positions pass over it. */
static int builtin(const lua_Debug *ar)
{
    return strcmp(ar->source, LIMEN__KIT_CHUNK) == 0;
}

/* "file:line" of the innermost Lua function running at or above `level` outside the
 * built-in kit (inside it if nothing else runs), or "" if none. */
static void lua_where(lua_State *L, int level, char *buf, size_t size)
{
    lua_Debug ar;
    buf[0] = '\0';
    for (int pass = 0; pass < 2 && !buf[0]; pass++) {
        for (int l = level; lua_getstack(L, l, &ar); l++) {
            lua_getinfo(L, "Sl", &ar);
            if (ar.currentline > 0 && (pass == 1 || !builtin(&ar))) {
                snprintf(buf, size, "%s:%d", ar.short_src, ar.currentline);
                break;
            }
        }
    }
}

/* Does msg start with a position ("chunk:12: ")? */
static int has_position(const char *msg)
{
    for (const char *p = msg; *p && *p != '\n'; p++) {
        if (p[0] != ':' || p[1] < '0' || p[1] > '9')
            continue;
        const char *q = p + 1;
        while (*q >= '0' && *q <= '9')
            q++;
        if (*q == ':')
            return 1;
    }
    return 0;
}

static limen_script *script_of(lua_State *L);

/* lua.c's msghandler without the traceback: makes any error object a string, and gives it
 * the place where it was raised if it has none (error({}), error("x", 0)). When a limit was
 * hit it only notes where: allocating could fail again, and the message is made afterwards. */
static int msghandler(lua_State *L)
{
    limen_script *sc = script_of(L);
    if (sc && (sc->over_budget || sc->mem_refused)) {
        if (!sc->where[0])
            lua_where(L, 1, sc->where, sizeof sc->where);
        return 1;
    }
    const char *msg;
    if (lua_type(L, 1) == LUA_TSTRING)
        msg = lua_tostring(L, 1);
    else if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING)
        msg = lua_tostring(L, -1);
    else
        msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    char where[WHERE_MAX];
    if (!has_position(msg)) {
        lua_where(L, 1, where, sizeof where);
        if (where[0])
            msg = lua_pushfstring(L, "%s: %s", where, msg);
    }
    return 1;
}

/* ------------------------------------------------------------------ limits */

static void script_hook(lua_State *L, lua_Debug *ar);

/* Arms the hook of the main thread for what the script needs now. */
static void set_hook(limen_script *sc, int count)
{
    int mask = (sc->budget >= 0 ? LUA_MASKCOUNT : 0) | (sc->tracking ? LUA_MASKLINE : 0);
    lua_sethook(sc->L, mask ? script_hook : NULL, mask, count);
}

/* Follows the lines from now on (sc->line), so that a limit met where no hook can look
 * (in the allocator, whose failure Lua reports with no place) can still say where. */
static void follow_lines(limen_script *sc)
{
    if (sc->tracking)
        return;
    sc->tracking = 1;
    int count = lua_gethookcount(sc->L);
    set_hook(sc, count > 0 ? count : sc->hook_every);
}

/* Near the end of the budget: time to follow the lines. */
static int near_budget(const limen_script *sc)
{
    return sc->budget >= 0 && sc->spent > sc->budget - sc->budget / 64;
}

/* The call has run out of instructions: stop at the next instruction of the main thread
 * (lua_sethook may be called at any moment, even from a signal handler, lua.c shows). */
static void run_out(limen_script *sc)
{
    sc->over_budget = 1;
    lua_sethook(sc->L, script_hook, LUA_MASKCOUNT, 1);
}

/* The allocator: counts what the state holds, enforces the cap, charges the budget. */
static void *script_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    limen_script *sc = ud;
    if (!ptr)
        osize = 0;      /* then osize tells the kind of object, not a size */
    if (nsize == 0) {
        free(ptr);
        sc->mem_used -= osize;
        return NULL;
    }
    if (nsize > osize) {
        size_t grow = nsize - osize;
        if (sc->mem_cap && (grow > sc->mem_cap || sc->mem_used > sc->mem_cap - grow)) {
            sc->mem_refused = 1;
            return NULL;
        }
        if (sc->running && sc->budget >= 0) {
            if (sc->over_budget)
                return NULL;
            sc->spent += (int64_t)(nsize / ALLOC_BYTES);
            if (sc->spent > sc->budget) {
                run_out(sc);
                return NULL;
            }
            if (near_budget(sc))
                follow_lines(sc);
        }
    }
    void *p = realloc(ptr, nsize);
    if (!p)
        return NULL;
    sc->mem_used = sc->mem_used - osize + nsize;
    /* near the cap, follow the lines, so that "not enough memory" can say where */
    if (sc->running && sc->mem_cap && sc->mem_used > sc->mem_cap / 2 && !sc->over_budget)
        follow_lines(sc);
    return p;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static limen_script *script_of(lua_State *L)
{
    void *ud;
    return lua_getallocf(L, &ud) == script_alloc ? ud : NULL;
}

static void note_where(char *buf, lua_State *L, lua_Debug *ar)
{
    lua_getinfo(L, "Sl", ar);
    if (builtin(ar))
        lua_where(L, 0, buf, WHERE_MAX);
    else if (ar->currentline > 0)
        snprintf(buf, WHERE_MAX, "%s:%d", ar->short_src, ar->currentline);
}

/* Raises the budget error where the script is (it becomes the message in the end). */
static int budget_error(lua_State *L, limen_script *sc)
{
    if (!sc->where[0])
        lua_where(L, 0, sc->where, sizeof sc->where);
    lua_pushliteral(L, "script exceeded its instruction budget");
    return lua_error(L);
}

/* Every hook_every instructions of every thread (coroutines inherit the hook), and on each
 * new line while tracking. */
static void script_hook(lua_State *L, lua_Debug *ar)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    if (ar->event == LUA_HOOKLINE) {
        if (!sc->over_budget) {
            note_where(sc->line, L, ar);
            return;
        }
    } else if (!sc->over_budget) {
        sc->spent += lua_gethookcount(L);
        if (near_budget(sc))
            follow_lines(sc);
        if (sc->spent > sc->budget) {
            run_out(sc);
        } else if (sc->time_limit > 0) {
            double t = now();
            if (t - sc->started <= sc->time_limit) {
                /* slow instructions (a hundred times the usual): look at the clock more often
                 * on this thread, until they are fast again */
                int count = lua_gethookcount(L);
                double per = (t - sc->last_hook) / count;
                if (count > SLOW_EVERY && per > 1e-6)
                    lua_sethook(L, script_hook, lua_gethookmask(L), SLOW_EVERY);
                else if (count == SLOW_EVERY && per < 1e-7)
                    lua_sethook(L, script_hook, lua_gethookmask(L), sc->hook_every);
                sc->last_hook = t;
                return;
            }
            sc->over_time = 1;
            run_out(sc);
        } else {
            return;
        }
    }
    /* out of budget: this thread too raises at every instruction from now on */
    lua_sethook(L, script_hook, LUA_MASKCOUNT, 1);
    if (!sc->where[0])
        note_where(sc->where, L, ar);
    budget_error(L, sc);
}

void limen__lua_charge(lua_State *L, double steps)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running || sc->budget < 0)
        return;
    if (sc->over_budget || steps > (double)(sc->budget - sc->spent)) {
        run_out(sc);
        budget_error(L, sc);
    }
    sc->spent += (int64_t)steps;
}

int limen__lua_hold(lua_State *L, ptrdiff_t bytes)
{
    limen_script *sc = script_of(L);
    if (!sc)
        return 1;
    if (bytes < 0) {
        sc->mem_used -= (size_t)-bytes;
        return 1;
    }
    if (sc->mem_cap &&
        ((size_t)bytes > sc->mem_cap || sc->mem_used > sc->mem_cap - (size_t)bytes)) {
        sc->mem_refused = 1;
        return 0;
    }
    sc->mem_used += (size_t)bytes;
    return 1;
}

size_t limen__lua_mem_left(lua_State *L)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->mem_cap)
        return SIZE_MAX;
    return sc->mem_used >= sc->mem_cap ? 0 : sc->mem_cap - sc->mem_used;
}

void limen__lua_note_line(lua_State *L)
{
    limen_script *sc = script_of(L);
    if (sc && sc->running)
        lua_where(L, 1, sc->line, sizeof sc->line);
}

double limen__lua_budget_left(lua_State *L)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running || sc->budget < 0)
        return HUGE_VAL;
    return sc->over_budget ? 0 : (double)(sc->budget - sc->spent);
}

static void begin_call(limen_script *sc)
{
    sc->spent = 0;
    sc->over_budget = 0;
    sc->over_time = 0;
    sc->started = sc->last_hook = sc->time_limit > 0 ? now() : 0;
    sc->mem_refused = 0;
    sc->where[0] = '\0';
    sc->line[0] = '\0';
    sc->tracking = sc->mem_cap && sc->mem_used > sc->mem_cap / 2;
    sc->running = 1;
    set_hook(sc, sc->hook_every);
}

static void end_call(limen_script *sc)
{
    sc->running = 0;
    sc->tracking = 0;
    lua_sethook(sc->L, NULL, 0, 0);
}

static void format_bytes(char *buf, size_t size, size_t bytes)
{
    if (bytes % (1u << 20) == 0)
        snprintf(buf, size, "%zu MiB", bytes >> 20);
    else if (bytes % 1024 == 0)
        snprintf(buf, size, "%zu KiB", bytes >> 10);
    else
        snprintf(buf, size, "%zu bytes", bytes);
}

/* Makes the message of a failed protected call (its error object on top) and returns the
 * status. A call stopped by a limit stops the script. */
static limen_status call_failed(limen_script *sc, int st, int load_status)
{
    lua_State *L = sc->L;
    const char *msg = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : NULL;
    char buf[ERR_MAX], size[32];
    const char *where = sc->where[0] ? sc->where : sc->line[0] ? sc->line : sc->path;
    if (sc->over_time) {
        snprintf(buf, sizeof buf, "%s: script exceeded its time limit (%.3g s, set by its "
                 "instruction budget)", where, sc->time_limit);
        sc->stopped = 1;
        set_error(sc, buf);
        return LIMEN_ERR_SCRIPT;
    }
    if (sc->over_budget) {
        snprintf(buf, sizeof buf, "%s: script exceeded its instruction budget (%lld)", where,
                 (long long)sc->budget);
        sc->stopped = 1;
        set_error(sc, buf);
        return LIMEN_ERR_SCRIPT;
    }
    if (sc->mem_refused && (st == LUA_ERRMEM || st == LUA_ERRERR ||
                            (msg && strcmp(msg, "not enough memory") == 0))) {
        format_bytes(size, sizeof size, sc->mem_cap);
        snprintf(buf, sizeof buf, "%s: not enough memory (script memory cap %s)", where, size);
        sc->stopped = 1;
        set_error(sc, buf);
        return LIMEN_ERR_SCRIPT;
    }
    if (!msg) {
        /* only when the message handler could not run, or chose not to (a limit was near) */
        snprintf(buf, sizeof buf, "%s: %s", sc->where[0] ? sc->where : sc->path,
                 st == LUA_ERRMEM ? "not enough memory" :
                 st == LUA_ERRERR ? "error in error handling" :
                 lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, -1)));
        msg = buf;
    } else if (load_status != LUA_ERRFILE && !has_position(msg) &&
               strncmp(msg, sc->path, strlen(sc->path)) != 0) {
        snprintf(buf, sizeof buf, "%s: %s", sc->path, msg);
        msg = buf;
    }
    set_error(sc, msg);
    if (load_status == LUA_ERRFILE)
        return LIMEN_ERR_IO;
    return st == LUA_ERRMEM ? LIMEN_ERR_NOMEM : LIMEN_ERR_SCRIPT;
}

/* ------------------------------------------------------------------ running scripts */

static int open_trusted(lua_State *L)
{
    luaL_openlibs(L);
    return 0;
}

/* package.preload.limen = luaopen_limen and package.preload["limen.kit"], in either mode. Also keeps the string Lua makes
 * when a message handler fails, so that making it never needs memory: it is made after the
 * protected call has returned, where an allocation failure would be fatal. */
static int preload_limen(lua_State *L)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_limen);
    lua_setfield(L, -2, "limen");
    lua_settop(L, 0);
    limen__lua_preload_kit(L);
    lua_pushliteral(L, "error in error handling");
    lua_setfield(L, LUA_REGISTRYINDEX, "limen.errerr");
    lua_settop(L, 0);
    return 0;
}

typedef struct chunk {
    limen_script *sc;
    const char *buf;            /* NULL: read sc->path */
    size_t len;
    int load_status;            /* of luaL_load*: LUA_ERRFILE, LUA_ERRSYNTAX, ... */
} chunk;

/* "nothing", "a number", "limen.sphere 'ball'", ... for "it returned ...". */
static const char *returned(lua_State *L, int idx)
{
    switch (lua_type(L, idx)) {
    case LUA_TNONE: return "nothing";
    case LUA_TNIL: return "nil";
    case LUA_TUSERDATA: return luaL_tolstring(L, idx, NULL);   /* our types say what they are */
    default: return lua_pushfstring(L, "a %s", luaL_typename(L, idx));
    }
}

/* Protected: compiles the chunk, runs it and keeps the scene it returns. */
static int run_chunk(lua_State *L)
{
    chunk *c = lua_touserdata(L, 1);
    limen_script *sc = c->sc;
    lua_settop(L, 0);
    const char *name = lua_pushfstring(L, "@%s", sc->path);
    int st = c->buf ? luaL_loadbufferx(L, c->buf, c->len, name, "t")
                    : luaL_loadfilex(L, sc->path, "t");
    if (st != LUA_OK) {
        c->load_status = st;
        const char *msg = lua_tostring(L, -1);
        /* syntax errors carry "path:line:"; the text-only refusal says nothing of where */
        size_t plen = strlen(sc->path);
        if (st == LUA_ERRSYNTAX && msg && strncmp(msg, sc->path, plen) != 0 &&
            strncmp(msg, "...", 3) != 0)
            lua_pushfstring(L, "%s: %s", sc->path, msg);
        return lua_error(L);
    }
    lua_call(L, 0, LUA_MULTRET);
    sc->scene = lua_gettop(L) >= 2 ? limen__lua_toscene(L, 2) : NULL;
    if (!sc->scene)
        return luaL_error(L, "%s: script must return a scene (limen.scene{...}); it returned %s",
                          sc->path, returned(L, 2));
    lua_settop(L, 2);
    sc->scene_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    return 0;
}

static limen_status fail(limen_script *sc, limen_status st, const char *msg)
{
    set_error(sc, msg);
    return st;
}

static limen_status script_load(const char *path, const char *buf, size_t len,
                                const limen_script_desc *desc, limen_script **out)
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
    if (!(sc->path = strdup(path)))
        return fail(sc, LIMEN_ERR_NOMEM, "out of memory");
    int64_t budget = desc ? desc->instruction_budget : 0;
    int64_t cap = desc ? desc->memory_cap : 0;
    sc->budget = budget == 0 ? DEFAULT_BUDGET : budget < 0 ? -1 : budget;
    sc->mem_cap = cap == 0 ? (size_t)DEFAULT_MEMORY : cap < 0 ? 0 :
                  (uint64_t)cap > SIZE_MAX ? SIZE_MAX : (size_t)cap;
    sc->hook_every = sc->budget >= 0 && sc->budget < HOOK_EVERY ? (int)(sc->budget + 1) :
                     HOOK_EVERY;
    sc->time_limit = sc->budget < 0 ? 0 :
                     fmax(1.0, (double)sc->budget * NS_PER_INSTRUCTION * 1e-9);

    lua_State *L = sc->L = lua_newstate(script_alloc, sc);
    if (!L) {
        char size[32], msg[ERR_MAX];
        format_bytes(size, sizeof size, sc->mem_cap);
        snprintf(msg, sizeof msg, "%.900s: not enough memory for a Lua state (script memory cap "
                 "%s)", sc->path, size);
        return fail(sc, LIMEN_ERR_NOMEM, msg);
    }
    int trusted = desc && desc->trusted;
    lua_pushcfunction(L, trusted ? open_trusted : limen__lua_open_safe);
    int st = lua_pcall(L, 0, 0, 0);
    if (st == LUA_OK) {
        lua_pushcfunction(L, preload_limen);
        st = lua_pcall(L, 0, 0, 0);
    }
    if (st != LUA_OK) {
        char size[32], msg[ERR_MAX];
        format_bytes(size, sizeof size, sc->mem_cap);
        snprintf(msg, sizeof msg, "%.900s: cannot open the standard library: %s", sc->path,
                 st == LUA_ERRMEM && sc->mem_refused ?
                 lua_pushfstring(L, "not enough memory (script memory cap %s)", size) :
                 lua_tostring(L, -1));
        return fail(sc, st == LUA_ERRMEM ? LIMEN_ERR_NOMEM : LIMEN_ERR_SCRIPT, msg);
    }

    chunk c = { sc, buf, len, LUA_OK };
    begin_call(sc);
    lua_pushcfunction(L, msghandler);
    lua_pushcfunction(L, run_chunk);
    lua_pushlightuserdata(L, &c);
    st = lua_pcall(L, 1, 0, 1);
    end_call(sc);
    if (st != LUA_OK) {
        sc->scene = NULL;
        limen_status ls = call_failed(sc, st, c.load_status);
        lua_settop(L, 0);
        return ls;
    }
    lua_settop(L, 0);
    return LIMEN_OK;
}

limen_status limen_script_load(const char *path, const limen_script_desc *desc,
                               limen_script **out)
{
    return script_load(path, NULL, 0, desc, out);
}

limen_status limen__script_load_buffer(const char *name, const char *buf, size_t len,
                                       const limen_script_desc *desc, limen_script **out)
{
    if (!buf && out) {
        *out = NULL;
        return LIMEN_ERR_ARG;
    }
    return script_load(name, buf ? buf : "", len, desc, out);
}

void limen_script_destroy(limen_script *sc)
{
    if (!sc)
        return;
    if (sc->L)
        lua_close(sc->L);   /* collects the scene userdata, which destroys the scene */
    free(sc->path);
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

/* Protected (its string keys may need memory): pushes whether the scene has an update. */
static int has_update(lua_State *L)
{
    limen_script *sc = lua_touserdata(L, 1);
    lua_rawgeti(L, LUA_REGISTRYINDEX, sc->scene_ref);
    lua_pushboolean(L, limen__lua_push_update(L, -1) == LUA_TFUNCTION);
    return 1;
}

int limen_script_animated(const limen_script *sc)
{
    if (!sc || !sc->scene)
        return 0;
    lua_State *L = sc->L;
    lua_settop(L, 0);
    lua_pushcfunction(L, has_update);
    lua_pushlightuserdata(L, (void *)sc);
    int t = lua_pcall(L, 1, 1, 0) == LUA_OK && lua_toboolean(L, -1);
    lua_settop(L, 0);
    return t;
}

/* Protected: calls the scene's update(t) if it has one. */
static int call_update(lua_State *L)
{
    limen_script *sc = lua_touserdata(L, 1);
    lua_Number t = lua_tonumber(L, 2);
    lua_settop(L, 0);
    lua_rawgeti(L, LUA_REGISTRYINDEX, sc->scene_ref);
    if (limen__lua_push_update(L, 1) != LUA_TFUNCTION)
        return 0;
    lua_pushnumber(L, t);
    lua_call(L, 1, 0);
    return 0;
}

limen_status limen_script_update(limen_script *sc, double t)
{
    if (!sc)
        return LIMEN_ERR_ARG;
    if (!sc->scene || sc->stopped)
        return LIMEN_ERR_SCRIPT;   /* it never loaded, or a limit stopped it: the message says */
    lua_State *L = sc->L;
    lua_settop(L, 0);
    begin_call(sc);
    lua_pushcfunction(L, msghandler);
    lua_pushcfunction(L, call_update);
    lua_pushlightuserdata(L, sc);
    lua_pushnumber(L, t);
    int st = lua_pcall(L, 2, 0, 1);
    end_call(sc);
    limen_status ls = LIMEN_OK;
    if (st != LUA_OK)
        ls = call_failed(sc, st, LUA_OK);
    else
        sc->err[0] = '\0';
    lua_settop(L, 0);
    return ls;
}
