/* safe.c - the standard library of a scene script run in safe mode (the default).
 *
 * What it has: base without dofile/loadfile, with a load that takes text only (guards.c), a
 * setmetatable that refuses __gc, a print that reaches the host's callback only and a
 * tostring that shows no address (guards.c); string, table, math, utf8, coroutine;
 * os.clock/time/date/difftime; no io, no debug; require finds "limen", what is already
 * loaded or in package.preload, and modules of the script's own folder and below.
 *
 * Why __gc is refused: Lua runs finalizers with hooks turned off, so a finalizer would run
 * outside the instruction budget (script.c), and a loop in one would hang the program.
 *
 * Metered functions: the budget counts VM instructions, but some library functions do work
 * that grows with their arguments and allocates nothing that the allocator could charge:
 * string.rep("", 1e15) loops 1e15 times, table.insert on a table whose __len says 1e15 shifts
 * 1e15 slots, and a backtracking pattern can take n^k steps on a subject of n bytes. Their
 * wrappers charge that work to the budget before calling the stock function (which runs in
 * the wrapper's own frame, so that its errors still name it and the script's line). A
 * pattern whose worst case is more than the budget left is refused before it runs, and the
 * estimate itself is charged as it goes. table.sort charges its comparisons, by the length of
 * its longest string when it compares strings itself; collectgarbage a collection's visit of
 * the memory held. */
#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <lualib.h>

#include <stdlib.h>
#include <sys/stat.h>

#include "core/confine.h"
#include "lua/lua_internal.h"

#define PATTERN_STEPS 4         /* worst-case pattern steps that cost one instruction */
#define ESTIMATE_STEPS 8        /* steps of the pattern estimator that cost one instruction */
#define ESTIMATE_SLICE (1 << 16) /* ... charged this many at a time */
#define GC_BYTES 32             /* bytes held that a full collection visits per instruction */
#define SORT_BYTES 32           /* bytes compared per instruction, sorting strings */

/* Calls the stock C function kept as upvalue 1 with the arguments as they are. The stock
 * functions wrapped here have no upvalues of their own. */
static int call_stock(lua_State *L)
{
    return lua_tocfunction(L, lua_upvalueindex(1))(L);
}

/* An integer argument, or `def` where it is absent; NAN where it is not an integer (the
 * stock function then raises the error). */
static double opt_int(lua_State *L, int i, double def)
{
    if (lua_isnoneornil(L, i))
        return def;
    int ok;
    lua_Integer v = lua_tointegerx(L, i, &ok);
    return ok ? (double)v : NAN;
}

/* #t of a table argument (calling __len, as the stock function will); NAN if it is not a
 * table or its length is not an integer. Leaves the stack as it was. */
static double table_len(lua_State *L, int i)
{
    if (lua_type(L, i) != LUA_TTABLE)
        return NAN;
    int top = lua_gettop(L);
    lua_len(L, i);
    int ok;
    lua_Integer n = lua_tointegerx(L, -1, &ok);
    lua_settop(L, top);
    return ok ? (double)n : NAN;
}

/* Charges n steps if n is a positive number (NAN and negatives: the stock function raises
 * or does nothing). */
static void charge(lua_State *L, double n)
{
    if (n > 0)
        limen__lua_charge(L, n);
}

/* ------------------------------------------------------------------ base */

static int l_safe_setmetatable(lua_State *L)
{
    if (lua_type(L, 2) == LUA_TTABLE) {
        lua_pushliteral(L, "__gc");
        int gc = lua_rawget(L, 2) != LUA_TNIL;   /* Lua looks __gc up raw, and only now */
        lua_pop(L, 1);
        if (gc)
            return luaL_error(L, "setmetatable: __gc metamethods are not available to a safe "
                                 "scene script (finalizers run outside its instruction budget)");
    }
    return call_stock(L);
}

/* package.searchers[2] of a safe script: module "a.b" is the file a/b.lua beneath the
 * folder of the top-level script, read through the same way in as every file a scene reads
 * (core/confine.c). Its files resolve against that folder too. What is not there is refused
 * here in one line (the stock message lists every searcher, one line each). */
static int l_safe_searcher(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    const limen__confine *box = limen__lua_box(L);
    bool ok = box && name[0] && name[0] != '.' && strlen(name) < 200;
    for (const char *c = name; ok && *c; c++)
        ok = isalnum((unsigned char)*c) || *c == '_' || *c == '-' ||
             (*c == '.' && c[1] && c[1] != '.');
    if (!ok)
        return luaL_error(L, "module '%s' is not available to a safe scene script", name);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, box->prefix);
    luaL_addchar(&b, '/');
    for (const char *c = name; *c; c++)
        luaL_addchar(&b, *c == '.' ? '/' : *c);
    luaL_addstring(&b, ".lua");
    luaL_pushresult(&b);
    const char *path = lua_tostring(L, -1);
    unsigned char *data;
    size_t len;
    struct stat st;
    char why[160];
    if (limen__confine_read(box, path, limen__lua_mem_left(L), &data, &len, &st, why,
                            sizeof why)) {
        if (strcmp(why, "not found") == 0)
            return luaL_error(L, "module '%s' is not available to a safe scene script", name);
        return luaL_error(L, "module '%s' is not available to a safe scene script: %s: %s",
                          name, path, why);
    }
    limen__lua_note_file(L, path);     /* watched for hot reload, as the script is */
    const char *chunk = lua_pushfstring(L, "@%s", path);
    int rc = limen__lua_load_string(L, (const char *)data, len, chunk, "t");
    free(data);
    if (rc != LUA_OK) {
        limen__lua_caught(L, rc);
        return lua_error(L);
    }
    lua_pushvalue(L, -3);       /* the path: the loader's second argument */
    return 2;
}

/* require(name) for modules already loaded, in package.preload, or files of the script's
 * folder (l_safe_searcher). */
static int l_safe_require(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    lua_settop(L, 1);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    if (lua_getfield(L, 2, name) == LUA_TNIL && lua_getfield(L, 3, name) == LUA_TNIL &&
        !limen__lua_box(L))
        return luaL_error(L, "module '%s' is not available to a safe scene script", name);
    lua_settop(L, 1);
    lua_pushvalue(L, lua_upvalueindex(1));   /* the stock require keeps an upvalue: call it */
    lua_insert(L, 1);
    lua_call(L, 1, LUA_MULTRET);
    return lua_gettop(L);
}

/* What a script run in safe mode lacks, when its error is about one of these being nil:
 * says so, and how to trust the script, instead of leaving "attempt to index a nil value". */
const char *limen__lua_safe_hint(lua_State *L, const char *msg)
{
    static const char *const missing[] = { "io", "debug", "dofile", "loadfile", NULL };
    int safe = lua_getfield(L, LUA_REGISTRYINDEX, LIMEN__LUA_SAFE) == LUA_TBOOLEAN &&
               lua_toboolean(L, -1);
    lua_pop(L, 1);
    if (!safe || !strstr(msg, "a nil value (global '"))
        return NULL;
    for (const char *const *k = missing; *k; k++) {
        char pat[32];
        snprintf(pat, sizeof pat, "(global '%s')", *k);
        if (strstr(msg, pat))
            return lua_pushfstring(L, "%s: not available to a scene script in safe mode "
                                      "(--trusted, or limen_script_desc.trusted = 1, gives "
                                      "it the full standard library)", msg);
    }
    return NULL;
}

/* ------------------------------------------------------------------ table */

static int l_table_insert(lua_State *L)
{
    if (lua_gettop(L) == 3) {
        double n = table_len(L, 1), pos = opt_int(L, 2, 0);
        if (pos >= 1 && pos <= n + 1)
            charge(L, n + 1 - pos);
    }
    return call_stock(L);
}

static int l_table_remove(lua_State *L)
{
    double n = table_len(L, 1), pos = opt_int(L, 2, n);
    if (pos >= 1 && pos <= n + 1)
        charge(L, n + 1 - pos);
    return call_stock(L);
}

static int l_table_move(lua_State *L)
{
    double f = opt_int(L, 2, NAN), e = opt_int(L, 3, NAN);
    charge(L, e - f + 1);
    return call_stock(L);
}

static int l_table_concat(lua_State *L)
{
    double i = opt_int(L, 3, 1), j = opt_int(L, 4, lua_isnoneornil(L, 4) ? table_len(L, 1) : 0);
    charge(L, j - i + 1);
    return call_stock(L);
}

static int l_table_unpack(lua_State *L)
{
    double i = opt_int(L, 2, 1);
    double j = lua_isnoneornil(L, 3) ? (lua_type(L, 1) == LUA_TTABLE ? table_len(L, 1) : NAN)
                                     : opt_int(L, 3, NAN);
    if (j - i + 1 < 1e7)    /* beyond that the stock function refuses at once */
        charge(L, j - i + 1);
    return call_stock(L);
}

/* table.sort charges its comparisons; without a comparison function, comparing two strings
 * takes time that grows with them (one comparison, uncounted by the hook): it charges for
 * comparisons of its longest string too. */
static int l_table_sort(lua_State *L)
{
    double n = table_len(L, 1);
    if (n > 1 && n < 2147483647.0) {
        double compares = n * log2(n);
        charge(L, compares);
        if (lua_isnoneornil(L, 2)) {
            size_t longest = 0;
            for (lua_Integer i = 1; i <= (lua_Integer)n; i++) {
                if (lua_rawgeti(L, 1, i) == LUA_TSTRING && lua_rawlen(L, -1) > longest)
                    longest = lua_rawlen(L, -1);
                lua_pop(L, 1);
            }
            charge(L, compares * (double)longest / SORT_BYTES);
        }
    }
    return call_stock(L);
}

/* ------------------------------------------------------------------ string */

/* string.rep as the stock one (which loops n times to make "" of an empty string), charging
 * its loop once the result has been allocated (the allocator enforces the memory cap). */
static int l_string_rep(lua_State *L)
{
    size_t l, lsep;
    const char *s = luaL_checklstring(L, 1, &l);
    lua_Integer n = luaL_checkinteger(L, 2);
    const char *sep = luaL_optlstring(L, 3, "", &lsep);
    if (n <= 0 || l + lsep == 0) {
        lua_pushliteral(L, "");
        return 1;
    }
    if (l + lsep < l || l + lsep > (size_t)INT_MAX / (lua_Unsigned)n)
        return luaL_error(L, "resulting string too large");
    size_t total = (size_t)n * l + (size_t)(n - 1) * lsep;
    if (total > (1u << 20))
        limen__lua_note_line(L);
    luaL_Buffer b;
    char *p = luaL_buffinitsize(L, &b, total);
    charge(L, (double)n / 2);
    while (n-- > 1) {
        memcpy(p, s, l);
        p += l;
        if (lsep > 0) {
            memcpy(p, sep, lsep);
            p += lsep;
        }
    }
    memcpy(p, s, l);
    luaL_pushresultsize(&b, total);
    return 1;
}

/* string.byte(s, i, j) and utf8.codepoint(s, i, j): up to j - i + 1 results. */
static int l_string_slice(lua_State *L)
{
    size_t l = 0;
    if (lua_type(L, 1) == LUA_TSTRING)
        lua_tolstring(L, 1, &l);
    double i = opt_int(L, 2, 1), j = opt_int(L, 3, i);
    if (j < 0)
        j += (double)l + 1;
    if (i < 0)
        i += (double)l + 1;
    charge(L, fmin(j, (double)l) - fmax(i, 1) + 1);
    return call_stock(L);
}

static int l_string_pack(lua_State *L)
{
    size_t l = 0;
    if (lua_type(L, 1) == LUA_TSTRING)
        lua_tolstring(L, 1, &l);
    charge(L, (double)l);
    return call_stock(L);
}

/* ------------------------------------------------------------------ patterns */

/* Lua's match_class: does byte c belong to class %cl? */
static int match_class(int c, int cl)
{
    int res;
    switch (tolower(cl)) {
    case 'a': res = isalpha(c); break;
    case 'c': res = iscntrl(c); break;
    case 'd': res = isdigit(c); break;
    case 'g': res = isgraph(c); break;
    case 'l': res = islower(c); break;
    case 'p': res = ispunct(c); break;
    case 's': res = isspace(c); break;
    case 'u': res = isupper(c); break;
    case 'w': res = isalnum(c); break;
    case 'x': res = isxdigit(c); break;
    default: return cl == c;
    }
    if (isupper(cl))
        res = !res;
    return res != 0;
}

/* Lua's matchbracketclass: p at '[', ec at the closing ']'. */
static int match_set(int c, const char *p, const char *ec)
{
    int sig = 1;
    if (p[1] == '^') {
        sig = 0;
        p++;
    }
    while (++p < ec) {
        if (*p == '%') {
            p++;
            if (p < ec && match_class(c, (unsigned char)*p))
                return sig;
        } else if (p[1] == '-' && p + 2 < ec) {
            p += 2;
            if ((unsigned char)p[-2] <= c && c <= (unsigned char)*p)
                return sig;
        } else if ((unsigned char)*p == c) {
            return sig;
        }
    }
    return !sig;
}

/* End of the single-character class at p (Lua's classEnd), or NULL if it is malformed. */
static const char *class_end(const char *p, const char *pe)
{
    if (*p == '%')
        return p + 1 < pe ? p + 2 : NULL;
    if (*p != '[')
        return p + 1;
    p++;
    if (p < pe && *p == '^')
        p++;
    do {
        if (p >= pe)
            return NULL;
        if (*p++ == '%' && p < pe)
            p++;
    } while (p >= pe || *p != ']');
    return p + 1;
}

typedef struct subject {
    const unsigned char *s;
    size_t n;
    unsigned char present[256];   /* bytes that occur in s */
    lua_State *L;
    double work;                  /* the estimator's own steps, not yet charged */
} subject;

/* The estimator's own work is charged too, a slice at a time (a long pattern on a long
 * subject makes it long). */
static void estimator_work(subject *sj, double steps)
{
    sj->work += steps;
    if (sj->work >= ESTIMATE_SLICE) {
        charge(sj->L, sj->work / ESTIMATE_STEPS);
        sj->work = 0;
    }
}

/* Longest run of bytes of s in the class [p, ep). */
static double max_run(subject *sj, const char *p, const char *ep)
{
    estimator_work(sj, 256);
    unsigned char in[256];
    int any = 0;
    for (int c = 0; c < 256; c++) {
        in[c] = *p == '.' ? 1 : *p == '%' ? (unsigned char)match_class(c, (unsigned char)p[1]) :
                *p == '[' ? (unsigned char)match_set(c, p, ep - 1) : c == (unsigned char)*p;
        any |= in[c] && sj->present[c];
    }
    if (!any)
        return 0;
    estimator_work(sj, (double)sj->n);
    size_t best = 0, run = 0;
    for (size_t i = 0; i < sj->n; i++) {
        run = in[sj->s[i]] ? run + 1 : 0;
        if (run > best)
            best = run;
    }
    return (double)best;
}

/* An upper bound on the steps Lua's matcher takes for pattern p on subject s, from every
 * start position (gmatch and gsub: all of them together): each item of the pattern with a
 * repetition (* + -) can take as many lengths as the longest run of its class in s, plus one;
 * ? two; %b and back-references scan up to the whole subject. */
static double pattern_cost(lua_State *L, const char *s, size_t n, const char *p, size_t m,
                           int anchorable, double limit)
{
    subject sj = { (const unsigned char *)s, n, { 0 }, L, 0 };
    estimator_work(&sj, (double)n);
    for (size_t i = 0; i < n; i++)
        sj.present[(unsigned char)s[i]] = 1;
    const char *pe = p + m;
    double starts = (double)n + 1, per = 1, items = 1;
    if (anchorable && p < pe && *p == '^') {
        starts = 1;
        p++;
    }
    while (p < pe && starts * per * items <= limit) {
        items++;
        estimator_work(&sj, 1);
        if (*p == '(' || *p == ')' || (*p == '$' && p + 1 == pe)) {
            p++;
            continue;
        }
        if (*p == '%' && p + 1 < pe && p[1] == 'b') {
            per *= (double)n + 1;
            p += 4;
            continue;
        }
        if (*p == '%' && p + 1 < pe && p[1] == 'f') {
            p += 2;
            if (p >= pe || *p != '[' || !(p = class_end(p, pe)))
                return 0;   /* malformed: the stock function says so */
            continue;
        }
        if (*p == '%' && p + 1 < pe && p[1] >= '0' && p[1] <= '9') {
            per *= (double)n + 1;
            p += 2;
            continue;
        }
        const char *ep = class_end(p, pe);
        if (!ep)
            return 0;
        if (ep < pe && (*ep == '*' || *ep == '+' || *ep == '-')) {
            per *= max_run(&sj, p, ep) + 1;
            ep++;
        } else if (ep < pe && *ep == '?') {
            per *= 2;
            ep++;
        }
        p = ep;
    }
    charge(L, sj.work / ESTIMATE_STEPS);
    return starts * per * items;
}

/* Lua's nospecials: find then searches for p as plain text. */
static int no_specials(const char *p, size_t m)
{
    size_t upto = 0;
    do {
        if (strpbrk(p + upto, "^$*+?.([%-"))
            return 0;
        upto += strlen(p + upto) + 1;
    } while (upto <= m);
    return 1;
}

/* find, match, gmatch, gsub: charges the pattern's worst case, or refuses it. */
static int l_string_pattern(lua_State *L)
{
    const char *what = lua_tostring(L, lua_upvalueindex(2));
    size_t n, m;
    const char *s = luaL_checklstring(L, 1, &n);
    const char *p = luaL_checklstring(L, 2, &m);
    int find = strcmp(what, "find") == 0;
    double cost;
    if (find && (lua_toboolean(L, 4) || no_specials(p, m)))
        cost = ((double)n + 1) * ((double)m + 1);   /* plain search (lmemfind) */
    else
        cost = pattern_cost(L, s, n, p, m, strcmp(what, "gmatch") != 0,
                            limen__lua_budget_left(L) * PATTERN_STEPS + 1);
    double steps = cost / PATTERN_STEPS;
    if (steps > limen__lua_budget_left(L)) {
        char msg[160];
        snprintf(msg, sizeof msg, "string.%s: this pattern could take up to %.2g steps on a "
                 "subject of %zu bytes, more than the script's instruction budget allows",
                 what, cost, n);
        return luaL_error(L, "%s", msg);
    }
    charge(L, steps);
    return call_stock(L);
}

/* math.randomseed(): seeded from the clock, not from an address as the stock one (which also
 * returns its seeds), and so is the first state. */
static int l_math_randomseed(lua_State *L)
{
    if (lua_isnone(L, 1)) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        lua_pushinteger(L, (lua_Integer)ts.tv_sec);
        lua_pushinteger(L, (lua_Integer)ts.tv_nsec);
    }
    lua_pushvalue(L, lua_upvalueindex(1));   /* the stock one keeps its state as an upvalue */
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

/* collectgarbage("collect" / "step"): a full collection's work grows with the memory held. */
static int l_collectgarbage(lua_State *L)
{
    const char *opt = luaL_optstring(L, 1, "collect");
    if (strcmp(opt, "collect") == 0 || strcmp(opt, "step") == 0)
        charge(L, (double)limen__lua_memory(L) / GC_BYTES);
    return call_stock(L);
}

/* ------------------------------------------------------------------ opening */

/* Replaces t[name] (a stock C function) by f with the stock function as upvalue 1 and, if
 * tag is not NULL, the string tag as upvalue 2. */
static void wrap(lua_State *L, int t, const char *name, lua_CFunction f, const char *tag)
{
    lua_getfield(L, t, name);
    if (!lua_tocfunction(L, -1)) {
        lua_pop(L, 1);
        return;
    }
    int n = 1;
    if (tag) {
        lua_pushstring(L, tag);
        n = 2;
    }
    lua_pushcclosure(L, f, n);
    lua_setfield(L, t, name);
}

static void remove_fields(lua_State *L, int t, const char *const *names)
{
    for (; *names; names++) {
        lua_pushnil(L);
        lua_setfield(L, t, *names);
    }
}

/* Runs in protected mode: an allocation failure here is an error, not a panic. */
int limen__lua_open_safe(lua_State *L)
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
    wrap(L, g, "setmetatable", l_safe_setmetatable, NULL);
    wrap(L, g, "collectgarbage", l_collectgarbage, NULL);
    limen__lua_open_guards(L, 1, 1);

    lua_getfield(L, g, LUA_TABLIBNAME);
    int t = lua_gettop(L);
    wrap(L, t, "insert", l_table_insert, NULL);
    wrap(L, t, "remove", l_table_remove, NULL);
    wrap(L, t, "move", l_table_move, NULL);
    wrap(L, t, "concat", l_table_concat, NULL);
    wrap(L, t, "unpack", l_table_unpack, NULL);
    wrap(L, t, "sort", l_table_sort, NULL);
    lua_getfield(L, g, LUA_STRLIBNAME);
    int str = lua_gettop(L);
    wrap(L, str, "rep", l_string_rep, NULL);
    wrap(L, str, "byte", l_string_slice, NULL);
    wrap(L, str, "pack", l_string_pack, NULL);
    wrap(L, str, "unpack", l_string_pack, NULL);
    static const char *const patterns[] = { "find", "match", "gmatch", "gsub", NULL };
    for (const char *const *k = patterns; *k; k++)
        wrap(L, str, *k, l_string_pattern, *k);
    lua_getfield(L, g, LUA_MATHLIBNAME);
    wrap(L, lua_gettop(L), "randomseed", l_math_randomseed, NULL);
    lua_getfield(L, -1, "randomseed");     /* the stock seed came from an address */
    lua_call(L, 0, 0);
    lua_getfield(L, g, LUA_UTF8LIBNAME);
    wrap(L, lua_gettop(L), "codepoint", l_string_slice, NULL);
    lua_settop(L, g);

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

    /* package: package.preload (limen) and the script's own folder (l_safe_searcher); no
     * other file or C searchers, no loadlib */
    lua_getfield(L, g, LUA_LOADLIBNAME);
    int pkg = lua_gettop(L);
    lua_getfield(L, pkg, "searchers");
    lua_createtable(L, 2, 0);
    lua_rawgeti(L, -2, 1);      /* the preload searcher */
    lua_rawseti(L, -2, 1);
    lua_pushcfunction(L, l_safe_searcher);
    lua_rawseti(L, -2, 2);
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
