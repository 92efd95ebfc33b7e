/* script.c - runs a Lua scene script in its own state (the limen_script_* API), within limits.
 *
 * Each script has its own lua_State, and in it, counted for the script as a whole (the main
 * thread and every coroutine share one budget and one clock):
 *   - a memory cap: the state's allocator (script_alloc) counts the bytes it holds and refuses
 *     an allocation that would take it past the cap; Lua turns that into "not enough memory".
 *     The bindings count the scenes' C-side node slots too (limen__lua_hold);
 *   - an instruction budget per load and per update call: a count hook (script_hook) adds up
 *     VM instructions, and the allocator charges one instruction per ALLOC_BYTES allocated
 *     (copying a long string is work too). Library functions whose work grows with their
 *     arguments charge it themselves (safe.c, limen__lua_charge), in slices when it is long;
 *   - a time limit that follows from the budget (NS_PER_INSTRUCTION each, at least a
 *     second), on the processor time of the calling thread (a busy machine does not make a
 *     script fail), for the VM instructions whose time grows with their operands: comparing
 *     two long strings is one instruction. The clock is read at every hook, at every switch
 *     between coroutines and every HOOK_EVERY instructions charged by library functions; the
 *     hook comes every HOOK_EVERY instructions, or fewer when an instruction may be slow
 *     (measured, or foreseen from the longest string the script holds), so that a slice of
 *     the limit passes between two looks at the clock at most.
 * Coroutines: every thread gets the hook (safe.c's coroutine functions arm it on creation
 * and resume), and pays its interval in advance when armed, so that the instructions a
 * thread runs after its last hook (a coroutine that lives for fewer than an interval) are
 * never free.
 * A limit, once hit, stops the script for good: every later instruction of every thread raises
 * the error again, the catchers (pcall, xpcall, coroutine.resume/wrap/close, load: safe.c)
 * raise it again instead of returning it, so the error reaches the caller; further updates
 * fail at once with the same message. The memory cap is hit when an allocation it refused
 * ends in a memory error (not when an emergency collection makes room).
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

#include "core/confine.h"
#include "core/internal.h"
#include "lua/lua_internal.h"

#define ERR_MAX 1024
#define PRINT_MAX 1024         /* bytes of a printed line handed to the host, with its end */
#define WHERE_MAX 256
#define HOOK_EVERY 1000         /* instructions between two calls of the count hook */
#define CO_EVERY 100            /* ... at most, in a coroutine (what arming it costs) */
#define ALLOC_BYTES 32          /* bytes allocated that cost one instruction */
#define NS_PER_INSTRUCTION 100  /* time limit per instruction of budget; ten times the usual */
#define SLICES 16               /* looks at the clock per time limit, at least */
#define BIG_STRING (16 << 10)   /* strings this long make instructions that may be slow */
#define BIG_SLOTS 32            /* the longest strings held, followed one by one */
#define NS_PER_BYTE 8           /* worst time per byte of a string operation (string <) */

enum { LIMIT_NONE, LIMIT_BUDGET, LIMIT_TIME, LIMIT_MEMORY };

struct limen_script {
    lua_State *L;
    limen_scene *scene;         /* owned by the scene userdata, which the registry keeps */
    int scene_ref;
    char *path;                 /* for messages that have no line */
    limen_script_print_fn print;
    void *print_user;

    /* limits (see the top of the file) */
    int64_t budget;             /* instructions per call; < 0: none */
    size_t mem_cap;             /* bytes; 0: none */
    size_t mem_used;
    int hook_every;             /* the longest hook interval (less for a tiny budget) */
    int every;                  /* the hook interval now: shorter while instructions are slow */
    int running;                /* a load or an update is under way: charge the budget */
    lua_State *current;         /* the thread running now (the main one, or a coroutine) */
    int64_t spent;              /* instructions charged to this call */
    double time_limit;          /* seconds of processor time per call; 0: none */
    double started_cpu;         /* thread processor time at the start of the call */
    double cpu_check_at;        /* monotonic time before which the limit cannot have passed */
    double clock_at;            /* monotonic clock at the last look, and spent then */
    int64_t spent_at;
    int limit;                  /* LIMIT_*: the limit this call hit; it stops the script */
    int mem_refused;            /* the cap refused an allocation during this call */
    uint64_t mem_wanted;        /* what this call's refused request would have held in all */
    int tracking;               /* line hook on: the state holds over half its cap */
    int stopped;                /* a limit stopped the script: update fails at once */
    const void *big[BIG_SLOTS]; /* the longest strings held (BIG_STRING bytes or more) */
    size_t big_size[BIG_SLOTS];
    size_t big_floor;           /* the longest of those that no longer fit in big[] */
    char where[WHERE_MAX];      /* "file:line" where a limit was hit, if known */
    char line[WHERE_MAX];       /* "file:line" last seen by the line hook */
    char err[ERR_MAX];
    limen__confine box;         /* where a safe script reads: its own folder (core/confine.c) */
    char *files;                /* the modules it required from its folder ("a\0b\0") */
    size_t files_len;
    double extra_cpu;           /* processor time spent in children (contained imports) */
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

/* Copies the n bytes at s into out (size bytes) on one line: control bytes and bytes that are
 * not UTF-8 become \n, \t, \xNN, so that the result is always one printable line; what does
 * not fit is left out. */
static void escape_line(char *out, size_t size, const char *text, size_t n)
{
    const unsigned char *s = (const unsigned char *)text;
    size_t o = 0;
    while (n && o + 5 < size) {
        size_t len = limen__lua_utf8_char(s, n);
        if (len == 1 && (s[0] < 0x20 || s[0] == 0x7F))
            len = 0;
        if (len) {
            if (o + len >= size)
                break;
            memcpy(out + o, s, len);
            o += len;
        } else if (s[0] == '\n') {
            o += (size_t)snprintf(out + o, size - o, "\\n");
            len = 1;
        } else if (s[0] == '\t') {
            o += (size_t)snprintf(out + o, size - o, "\\t");
            len = 1;
        } else {
            o += (size_t)snprintf(out + o, size - o, "\\x%02X", s[0]);
            len = 1;
        }
        s += len;
        n -= len;
    }
    out[o] = '\0';
}

static void set_error(limen_script *sc, const char *msg)
{
    msg = msg ? msg : "unknown error";
    escape_line(sc->err, ERR_MAX, msg, strlen(msg));
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
    if (sc && (sc->limit || sc->mem_refused)) {
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
    limen__lua_safe_hint(L, msg);
    return 1;
}

/* ------------------------------------------------------------------ limits */

static void script_hook(lua_State *L, lua_Debug *ar);
/* The error object raised when a limit stops the script, made when the state is (raising it
 * must not need memory). Nothing in the script sees it: the caller gets the limit's message. */
static const char limit_key = 0;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Processor time of the calling thread: a system call, slow on some machines, so it is read
 * only when the monotonic clock says the limit may have passed (see look_at_clock). */
static double thread_time(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The hook a thread needs now: counting while there is a budget, lines while tracking. */
static int hook_mask(const limen_script *sc)
{
    return (sc->budget >= 0 ? LUA_MASKCOUNT : 0) | (sc->tracking ? LUA_MASKLINE : 0);
}

/* The hook interval of thread T: a coroutine's is short, as arming it costs its interval. */
static int interval_of(const limen_script *sc, lua_State *T)
{
    return T == sc->L || sc->every < CO_EVERY ? sc->every : CO_EVERY;
}

static void set_hook(limen_script *sc, lua_State *T, int count)
{
    int mask = hook_mask(sc);
    lua_sethook(T, mask ? script_hook : NULL, mask, count);
}

/* Arms thread T's hook if it is not armed as it should be, charging its interval: the
 * instructions T runs after its last hook (before it dies, or is armed again) are never
 * counted otherwise. */
static void arm(limen_script *sc, lua_State *T)
{
    int k = interval_of(sc, T);
    if (lua_gethook(T) == script_hook && lua_gethookmask(T) == hook_mask(sc) &&
        lua_gethookcount(T) == k)
        return;
    if (sc->budget >= 0 && T != sc->L)
        sc->spent += k;
    set_hook(sc, T, k);
}

/* Follows the lines from now on (sc->line), so that a limit met where no hook can look
 * (in the allocator, whose failure Lua reports with no place) can still say where. */
static void follow_lines(limen_script *sc)
{
    if (sc->tracking)
        return;
    sc->tracking = 1;
    set_hook(sc, sc->L, interval_of(sc, sc->L));
    if (sc->current && sc->current != sc->L)
        set_hook(sc, sc->current, interval_of(sc, sc->current));
}

/* Near the end of the budget: time to follow the lines. */
static int near_budget(const limen_script *sc)
{
    return sc->budget >= 0 && sc->spent > sc->budget - sc->budget / 64;
}

/* The call hit a limit: the running thread and the main one raise at their next instruction
 * (lua_sethook may be called at any moment, even from a signal handler, lua.c shows); a
 * coroutine raises when it is resumed, and a catcher when it catches (limen__lua_caught). */
static void hit(limen_script *sc, int limit)
{
    if (!sc->limit)
        sc->limit = limit;
    lua_sethook(sc->L, script_hook, LUA_MASKCOUNT, 1);
    if (sc->current && sc->current != sc->L)
        lua_sethook(sc->current, script_hook, LUA_MASKCOUNT, 1);
}

/* Raises the limit's error in L, where the script is (it becomes the message in the end). */
static int raise_limit(lua_State *L, limen_script *sc)
{
    if (!sc->where[0])
        lua_where(L, 0, sc->where, sizeof sc->where);
    lua_sethook(L, script_hook, LUA_MASKCOUNT, 1);
    lua_rawgetp(L, LUA_REGISTRYINDEX, &limit_key);
    return lua_error(L);
}

/* The longest string the script holds (of BIG_STRING bytes or more; 0 if none). */
static size_t longest_string(const limen_script *sc)
{
    size_t m = sc->big_floor;
    for (int i = 0; i < BIG_SLOTS; i++)
        if (sc->big[i] && sc->big_size[i] > m)
            m = sc->big_size[i];
    return m;
}

/* Instructions that may run before the next look at the clock: so many that a slice of the
 * time limit passes at most, whether they take `per` seconds each (as measured) or as long as
 * an operation on the longest string held. */
static int interval(const limen_script *sc, double per)
{
    double slice = sc->time_limit / SLICES;
    double worst = fmax(per, (double)longest_string(sc) * NS_PER_BYTE * 1e-9);
    double k = worst > 0 ? slice / worst : sc->hook_every;
    return k >= sc->hook_every ? sc->hook_every : k < 1 ? 1 : (int)k;
}

/* A string of `size` bytes at p was made: a long one shortens the hook interval now (the
 * running thread looks again at its next instruction). */
static void note_string(limen_script *sc, const void *p, size_t size)
{
    int slot = -1;
    for (int i = 0; i < BIG_SLOTS && slot < 0; i++)
        if (!sc->big[i])
            slot = i;
    if (slot < 0) {     /* all taken: the shortest goes to the floor */
        slot = 0;
        for (int i = 1; i < BIG_SLOTS; i++)
            if (sc->big_size[i] < sc->big_size[slot])
                slot = i;
        size_t out = sc->big_size[slot] < size ? sc->big_size[slot] : size;
        if (out > sc->big_floor)
            sc->big_floor = out;
        if (out == size)
            goto shorten;
    }
    sc->big[slot] = p;
    sc->big_size[slot] = size;
shorten:
    if (sc->running && sc->budget >= 0 && sc->time_limit > 0 && sc->current &&
        interval(sc, 0) < sc->every) {
        sc->every = interval(sc, 0);
        lua_sethook(sc->current, script_hook, hook_mask(sc), 1);
    }
}

/* A block of `size` bytes (BIG_STRING or more) at p was freed: if it was a string followed,
 * it is no longer held. */
static void forget_block(limen_script *sc, const void *p)
{
    for (int i = 0; i < BIG_SLOTS; i++)
        if (sc->big[i] == p)
            sc->big[i] = NULL;
}

/* The allocator: counts what the state holds, enforces the cap, charges the budget. */
static void *script_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    limen_script *sc = ud;
    int kind = ptr ? -1 : (int)osize;
    if (!ptr)
        osize = 0;      /* then osize told the kind of object, not a size */
    if (ptr && osize >= BIG_STRING)
        forget_block(sc, ptr);   /* strings are never resized: only freed */
    if (nsize == 0) {
        free(ptr);
        sc->mem_used -= osize;
        return NULL;
    }
    if (nsize > osize) {
        size_t grow = nsize - osize;
        if (sc->mem_cap && (grow > sc->mem_cap || sc->mem_used > sc->mem_cap - grow)) {
            sc->mem_refused = 1;
            sc->mem_wanted = (uint64_t)sc->mem_used + grow;
            return NULL;
        }
        if (sc->running && sc->budget >= 0) {
            if (sc->limit)
                return NULL;
            sc->spent += (int64_t)(nsize / ALLOC_BYTES);
            if (sc->spent > sc->budget) {
                hit(sc, LIMIT_BUDGET);
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
    if (kind == LUA_TSTRING && nsize >= BIG_STRING)
        note_string(sc, p, nsize);
    /* near the cap, follow the lines, so that "not enough memory" can say where */
    if (sc->running && sc->mem_cap && sc->mem_used > sc->mem_cap / 2 && !sc->limit)
        follow_lines(sc);
    return p;
}

static limen_script *script_of(lua_State *L)
{
    void *ud;
    return lua_getallocf(L, &ud) == script_alloc ? ud : NULL;
}

/* Looks at the clock: hits the time limit if the call's processor time has passed it.
 * Returns the seconds per instruction charged since the last look (0 if none was). */
static double look_at_clock(limen_script *sc)
{
    if (sc->time_limit <= 0)
        return 0;
    double t = now();
    int64_t n = sc->spent - sc->spent_at;
    double per = n > 0 ? (t - sc->clock_at) / (double)n : 0;
    sc->clock_at = t;
    sc->spent_at = sc->spent;
    /* the thread's processor time runs no faster than the monotonic clock */
    if (t >= sc->cpu_check_at) {
        double used = thread_time() - sc->started_cpu + sc->extra_cpu;
        if (used > sc->time_limit)
            hit(sc, LIMIT_TIME);
        else
            sc->cpu_check_at = t + (sc->time_limit - used);
    }
    return per;
}

static void note_where(char *buf, lua_State *L, lua_Debug *ar)
{
    lua_getinfo(L, "Sl", ar);
    if (builtin(ar))
        lua_where(L, 0, buf, WHERE_MAX);
    else if (ar->currentline > 0)
        snprintf(buf, WHERE_MAX, "%s:%d", ar->short_src, ar->currentline);
}

/* Every interval of instructions of every thread, and on each new line while tracking. */
static void script_hook(lua_State *L, lua_Debug *ar)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    if (!sc->limit && ar->event == LUA_HOOKLINE) {
        note_where(sc->line, L, ar);
        return;
    }
    if (!sc->limit && ar->event == LUA_HOOKCOUNT) {
        int count = lua_gethookcount(L);
        sc->spent += count;
        if (near_budget(sc))
            follow_lines(sc);
        if (sc->spent > sc->budget)
            hit(sc, LIMIT_BUDGET);
        else
            sc->every = interval(sc, look_at_clock(sc));
        if (!sc->limit) {
            int k = interval_of(sc, L);
            if (k != count) {
                if (k > count && L != sc->L)
                    sc->spent += k - count;   /* the longer interval is paid in advance too */
                set_hook(sc, L, k);
            }
            return;
        }
    }
    if (!sc->limit)
        return;
    if (!sc->where[0])
        note_where(sc->where, L, ar);
    raise_limit(L, sc);
}

void limen__lua_charge(lua_State *L, double steps)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running || sc->budget < 0)
        return;
    if (!sc->limit && steps > (double)(sc->budget - sc->spent))
        hit(sc, LIMIT_BUDGET);
    if (!sc->limit) {
        sc->spent += (int64_t)steps;
        if (near_budget(sc))
            follow_lines(sc);
        if (sc->spent - sc->spent_at >= sc->hook_every)
            look_at_clock(sc);
    }
    if (sc->limit)
        raise_limit(L, sc);
}

/* Did the error of this status, its object on top of T, come from a refused allocation? */
static int memory_error(lua_State *T, int status)
{
    /* lauxlib's buffers report one as a plain error of this message */
    return status == LUA_ERRMEM ||
           (status == LUA_ERRRUN && lua_type(T, -1) == LUA_TSTRING &&
            strcmp(lua_tostring(T, -1), "not enough memory") == 0);
}

/* An error of this status (its object on top of T) ended Lua code run for L: if the memory cap
 * caused it, the cap is hit; a limit hit raises in L. */
static void check_caught(lua_State *L, lua_State *T, int status)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    if (memory_error(T, status) && sc->mem_refused && !sc->limit) {
        hit(sc, LIMIT_MEMORY);
        /* where the memory ran out (followed near the cap), not where it was caught */
        if (!sc->where[0])
            memcpy(sc->where, sc->line, sizeof sc->where);
    }
    if (sc->limit)
        raise_limit(L, sc);
}

void limen__lua_enter(lua_State *L, lua_State *co)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    if (!sc->limit)
        look_at_clock(sc);
    if (!sc->limit && sc->budget >= 0 && sc->spent > sc->budget)
        hit(sc, LIMIT_BUDGET);
    if (sc->limit)
        raise_limit(L, sc);
    arm(sc, co);
    sc->current = co;
}

void limen__lua_leave(lua_State *L, lua_State *co, int status)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    sc->current = L;
    check_caught(L, co, status);
    if (sc->every < lua_gethookcount(L))
        arm(sc, L);
    look_at_clock(sc);
    if (sc->limit)
        raise_limit(L, sc);
}

void limen__lua_caught(lua_State *L, int status)
{
    check_caught(L, L, status);
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
        sc->mem_wanted = (uint64_t)sc->mem_used + (uint64_t)bytes;
        return 0;
    }
    sc->mem_used += (size_t)bytes;
    return 1;
}

void limen__lua_note_file(lua_State *L, const char *path)
{
    limen_script *sc = script_of(L);
    if (!sc)
        return;
    size_t n = strlen(path) + 1;
    for (size_t at = 0; at < sc->files_len; at += strlen(sc->files + at) + 1)
        if (strcmp(sc->files + at, path) == 0)
            return;
    char *more = realloc(sc->files, sc->files_len + n);
    if (!more)
        return;     /* not watched: the script itself still is */
    memcpy(more + sc->files_len, path, n);
    sc->files = more;
    sc->files_len += n;
}

limen_status limen_script_get_file(const limen_script *sc, int i, char *path, size_t size)
{
    if (!sc || !path || i < 0)
        return LIMEN_ERR_ARG;
    const char *f = sc->path;
    for (size_t at = 0; i > 0; i--) {
        if (at >= sc->files_len)
            return LIMEN_ERR_ARG;
        f = sc->files + at;
        at += strlen(f) + 1;
    }
    if (!f || strlen(f) >= size)
        return LIMEN_ERR_ARG;
    memcpy(path, f, strlen(f) + 1);
    return LIMEN_OK;
}

const limen__confine *limen__lua_box(lua_State *L)
{
    limen_script *sc = script_of(L);
    return sc && sc->box.on ? &sc->box : NULL;
}

void limen__lua_load_begin(lua_State *L, limen_scene *s, limen__load *ld)
{
    limen_script *sc = script_of(L);
    memset(ld, 0, sizeof *ld);
    ld->box = limen__lua_box(L);
    ld->safe = ld->box != NULL;
    ld->max_bytes = limen__lua_mem_left(L);
    if (sc && sc->running && sc->time_limit > 0) {
        double used = thread_time() - sc->started_cpu + sc->extra_cpu;
        ld->cpu_left = used < sc->time_limit ? sc->time_limit - used : 1e-3;
    }
    s->load = ld;
}

void limen__lua_load_end(lua_State *L, limen_scene *s, limen__load *ld)
{
    limen_script *sc = script_of(L);
    s->load = NULL;
    if (sc && sc->running && ld->cpu_spent > 0) {
        sc->extra_cpu += ld->cpu_spent;
        sc->cpu_check_at = 0;   /* look at the clock at the next chance */
    }
}

void limen__lua_check_time(lua_State *L)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->running)
        return;
    if (!sc->limit) {
        sc->cpu_check_at = 0;
        look_at_clock(sc);
    }
    if (sc->limit)
        raise_limit(L, sc);
}

void limen__lua_want(lua_State *L, uint64_t bytes)
{
    limen_script *sc = script_of(L);
    if (sc && sc->mem_cap && bytes)
        sc->mem_wanted = (uint64_t)sc->mem_used + bytes;
}

int64_t limen_script_memory_needed(const limen_script *sc)
{
    return sc && sc->mem_wanted <= INT64_MAX ? (int64_t)sc->mem_wanted : 0;
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
    return sc->limit ? 0 : (double)(sc->budget - sc->spent);
}

int limen__lua_limited(lua_State *L)
{
    limen_script *sc = script_of(L);
    return sc && sc->running && sc->limit;
}

size_t limen__lua_memory(lua_State *L)
{
    limen_script *sc = script_of(L);
    return sc ? sc->mem_used : (size_t)lua_gc(L, LUA_GCCOUNT) << 10;
}

static void begin_call(limen_script *sc)
{
    sc->spent = 0;
    sc->limit = LIMIT_NONE;
    sc->clock_at = now();
    sc->spent_at = 0;
    sc->started_cpu = sc->time_limit > 0 ? thread_time() : 0;
    sc->extra_cpu = 0;
    sc->cpu_check_at = sc->clock_at + sc->time_limit;
    sc->mem_refused = 0;
    sc->mem_wanted = 0;
    sc->where[0] = '\0';
    sc->line[0] = '\0';
    sc->tracking = sc->mem_cap && sc->mem_used > sc->mem_cap / 2;
    sc->running = 1;
    sc->current = sc->L;
    sc->every = sc->time_limit > 0 ? interval(sc, 0) : sc->hook_every;
    set_hook(sc, sc->L, sc->every);
}

static void end_call(limen_script *sc)
{
    sc->running = 0;
    sc->tracking = 0;
    sc->current = NULL;
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
    if (!sc->limit && sc->mem_refused && (st == LUA_ERRMEM || st == LUA_ERRERR ||
                                          (msg && strcmp(msg, "not enough memory") == 0)))
        sc->limit = LIMIT_MEMORY;
    if (sc->limit) {
        if (sc->limit == LIMIT_TIME) {
            snprintf(buf, sizeof buf, "%s: script exceeded its time limit (%.3g s, set by its "
                     "instruction budget)", where, sc->time_limit);
        } else if (sc->limit == LIMIT_BUDGET) {
            snprintf(buf, sizeof buf, "%s: script exceeded its instruction budget (%lld)",
                     where, (long long)sc->budget);
        } else {
            format_bytes(size, sizeof size, sc->mem_cap);
            snprintf(buf, sizeof buf, "%s: not enough memory (script memory cap %s)", where,
                     size);
        }
        sc->stopped = 1;
        set_error(sc, buf);
        return LIMEN_ERR_SCRIPT;
    }
    if (!msg) {
        /* only when the message handler could not run, or chose not to (a limit was near);
         * made without the state's memory, which may be all taken */
        char what[64];
        snprintf(what, sizeof what, "(error object is a %s value)", luaL_typename(L, -1));
        snprintf(buf, sizeof buf, "%s: %s", sc->where[0] ? sc->where : sc->path,
                 st == LUA_ERRMEM ? "not enough memory" :
                 st == LUA_ERRERR ? "error in error handling" : what);
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
    limen_script *sc = script_of(L);
    limen__lua_open_guards(L, 0, sc && sc->print);
    return 0;
}

int limen__lua_print(lua_State *L, const char *text, size_t len)
{
    limen_script *sc = script_of(L);
    if (!sc || !sc->print)
        return 0;
    char line[PRINT_MAX];
    escape_line(line, sizeof line, text, len);
    sc->print(sc->print_user, line);
    return 1;
}

/* package.preload.limen = luaopen_limen and package.preload["limen.kit"], in either mode. Also
 * keeps the string Lua makes when a message handler fails, and the error object of a limit, so
 * that making them never needs memory: the first is made after the protected call has
 * returned, where an allocation failure would be fatal. */
static int preload_limen(lua_State *L)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_limen);
    lua_setfield(L, -2, "limen");
    lua_settop(L, 0);
    limen__lua_preload_kit(L);
    lua_pushliteral(L, "error in error handling");
    lua_setfield(L, LUA_REGISTRYINDEX, "limen.errerr");
    lua_pushliteral(L, "script stopped by a limit");
    lua_rawsetp(L, LUA_REGISTRYINDEX, &limit_key);
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
    int st = c->buf ? limen__lua_load_string(L, c->buf, c->len, name, "t")
                    : limen__lua_load_file(L, sc->path, name);
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
    sc->box.dir = -1;
    sc->scene_ref = LUA_NOREF;
    if (!path)
        return fail(sc, LIMEN_ERR_ARG, "limen_script_load: no script path");
    if (!(sc->path = strdup(path)))
        return fail(sc, LIMEN_ERR_NOMEM, "out of memory");
    limen_script_desc filled = limen_script_desc_defaults(desc);
    int64_t budget = filled.instruction_budget, cap = filled.memory_cap;
    sc->budget = budget < 0 ? -1 : budget;
    sc->mem_cap = cap < 0 ? 0 : (uint64_t)cap > SIZE_MAX ? SIZE_MAX : (size_t)cap;
    sc->hook_every = sc->budget >= 0 && sc->budget < HOOK_EVERY ? (int)(sc->budget + 1) :
                     HOOK_EVERY;
    sc->every = sc->hook_every;
    sc->print = desc ? desc->print : NULL;
    sc->print_user = desc ? desc->print_user : NULL;
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
    if (trusted)
        sc->box.dir = -1;
    else
        limen__confine_init(&sc->box, sc->path);
    lua_pushcfunction(L, trusted ? open_trusted : limen__lua_open_safe);
    int st = lua_pcall(L, 0, 0, 0);
    if (st == LUA_OK) {
        lua_pushcfunction(L, preload_limen);
        st = lua_pcall(L, 0, 0, 0);
    }
    if (st != LUA_OK) {
        char size[32], msg[ERR_MAX];
        format_bytes(size, sizeof size, sc->mem_cap);
        /* made without the state's memory: outside a protected call, a failing allocation
         * would end the program */
        const char *why = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "unknown error";
        if (st == LUA_ERRMEM && sc->mem_refused)
            snprintf(msg, sizeof msg, "%.900s: cannot open the standard library: not enough "
                     "memory (script memory cap %s)", sc->path, size);
        else
            snprintf(msg, sizeof msg, "%.800s: cannot open the standard library: %.100s",
                     sc->path, why);
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
    limen__confine_close(&sc->box);
    free(sc->files);
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
