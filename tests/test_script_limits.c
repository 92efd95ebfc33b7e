/* test_script_limits.c - what keeps a scene script from hurting the program that runs it: the
 * instruction budget, the time limit and the memory cap hold for the script as a whole (every
 * coroutine, every catcher, library functions that loop), no cap makes the program abort, and
 * a safe script neither writes to the host's stdout nor sees an address. */
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "limen.h"
#include "scratch.h"

/* An animated scene (line 3 makes ball "b"). */
static const char *plain = HEAD "local b = s:sphere { name = \"b\" }\n"
                           "s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }\n"
                           "function s.update(t) b.pos = {math.sin(t), 1, 0} end\nreturn s\n";

static limen_node find(limen_scene *s, const char *name)
{
    limen_node n = { 0 };
    CHECK_MSG(limen_node_find(s, name, &n) == LIMEN_OK, "no node '%s'", name);
    return n;
}


/* The buffer loader is internal (src/lua/lua_internal.h, which tests do not include). */
limen_status limen__script_load_buffer(const char *name, const char *buf, size_t len,
                                       const limen_script_desc *desc, limen_script **out);

/* Loads text as dir/name with the given limits. */
static limen_status load_limited(const char *name, const char *text, int64_t budget,
                                 int64_t cap, limen_script **out)
{
    const char *path = script(name, text);
    return limen_script_load(path, &(limen_script_desc){ .instruction_budget = budget,
                                                         .memory_cap = cap }, out);
}

/* Checks that sc's message is "dir/name:line: msg" ("dir/name: msg" for line 0). */
static void expect_message(const limen_script *sc, const char *name, int line, const char *msg)
{
    char want[512];
    if (line)
        snprintf(want, sizeof want, "%s/%s:%d: %s", dir, name, line, msg);
    else
        snprintf(want, sizeof want, "%s/%s: %s", dir, name, msg);
    CHECK_MSG(sc && strcmp(limen_script_error(sc), want) == 0, "%s:\n    got      '%s'\n"
              "    expected '%s'", name, sc ? limen_script_error(sc) : "(no script)", want);
}

/* Checks that text loads as dir/name with the given limits, with no message. */
static void expect_loads(const char *name, const char *text, int64_t budget, int64_t cap)
{
    limen_script *sc = NULL;
    limen_status st = load_limited(name, text, budget, cap, &sc);
    CHECK_MSG(st == LIMEN_OK && strcmp(limen_script_error(sc), "") == 0, "%s: status %d, '%s'",
              name, st, sc ? limen_script_error(sc) : "");
    limen_script_destroy(sc);
}

#define BUDGET_MSG "script exceeded its instruction budget (100000)"

/* An endless loop at load ends with the budget error, however the script tries to catch it:
 * pcall, xpcall with a handler that loops too, a coroutine, a to-be-closed variable. */
static void test_budget_load(void)
{
    static const struct { const char *name, *text; int line; } loops[] = {
        { "loop.lua", HEAD "local i = 0\nwhile true do i = i + 1 end\n", 4 },
        { "loop_pcall.lua", HEAD "while true do\n  pcall(function() while true do end end)\nend\n",
          4 },
        { "loop_xpcall.lua", HEAD "local function h() while true do end end\n"
          "while true do xpcall(function() while true do end end, h) end\n", 4 },
        { "loop_coroutine.lua", HEAD "local co = coroutine.wrap(function()\n"
          "  while true do pcall(function() while true do end end) end\nend)\nco()\n", 4 },
        { "loop_close.lua", HEAD "local t <close> = setmetatable({}, { __close = function()\n"
          "  while true do end end })\nwhile true do end\n", 5 },
        { "loop_recurse.lua", HEAD "local function f(n) return f(n + 1) end\nf(1)\n", 3 },
    };
    for (size_t i = 0; i < sizeof loops / sizeof loops[0]; i++) {
        limen_script *sc = NULL;
        CHECK_MSG(load_limited(loops[i].name, loops[i].text, 100000, 0, &sc) == LIMEN_ERR_SCRIPT,
                  "%s", loops[i].name);
        expect_message(sc, loops[i].name, loops[i].line, BUDGET_MSG);
        CHECK(limen_script_scene(sc) == NULL);
        CHECK(limen_script_update(sc, 0) == LIMEN_ERR_SCRIPT);
        limen_script_destroy(sc);
    }
}

/* An endless loop in update stops the script; its scene stays readable; later updates fail at
 * once with the same message. */
static void test_budget_update(void)
{
    limen_script *sc = NULL;
    CHECK_OK(load_limited("upd_loop.lua", HEAD "local b = s:sphere { name = \"b\" }\n"
                          "function s.update(t)\n  b.pos = {t, 0, 0}\n"
                          "  if t > 1 then while true do end end\nend\nreturn s\n",
                          100000, 0, &sc));
    CHECK_OK(limen_script_update(sc, 0.5));
    CHECK(limen_script_update(sc, 2) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "upd_loop.lua", 6, BUDGET_MSG);
    CHECK(limen_script_update(sc, 0.5) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "upd_loop.lua", 6, BUDGET_MSG);
    limen_scene *s = limen_script_scene(sc);
    CHECK(s != NULL && limen_scene_node_count(s) == 1);
    float p[3] = { 0 };
    if (s)
        CHECK_OK(limen_node_get_position(s, find(s, "b"), p));
    CHECK(p[0] == 2);   /* what update did before the loop */
    CHECK(limen_script_animated(sc) == 1);
    limen_script_destroy(sc);
}

/* 0 means the default budget (50 million); a negative budget means none. */
static void test_budget_default(void)
{
    const char *text = HEAD "for i = 1, 6e7 do end\nreturn s\n";   /* 6e7 instructions */
    limen_script *sc = NULL;
    CHECK(load_limited("long.lua", text, 0, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "long.lua", 3, "script exceeded its instruction budget (50000000)");
    limen_script_destroy(sc);
    CHECK_OK(load_limited("long.lua", text, -1, 0, &sc));
    limen_script_destroy(sc);
    /* a trusted script keeps its budget */
    const char *path = script("trusted_loop.lua", HEAD "while true do end\n");
    CHECK(limen_script_load(path, &(limen_script_desc){ .trusted = 1, .instruction_budget = 1000 },
                            &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "trusted_loop.lua", 3, "script exceeded its instruction budget (1000)");
    limen_script_destroy(sc);
}

/* A memory bomb ends with "not enough memory" naming the cap and the line. */
static void test_memory_load(void)
{
    limen_script *sc = NULL;
    CHECK(load_limited("bomb.lua", HEAD "local t = {}\nfor i = 1, 1e8 do\n  t[i] = { i }\nend\n"
                       "return s\n", 0, 1 << 20, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "bomb.lua", 5, "not enough memory (script memory cap 1 MiB)");
    limen_script_destroy(sc);
    CHECK(load_limited("bomb_rep.lua", HEAD "local x = string.rep(\"x\", 4 << 20)\nreturn s\n", 0,
                       1 << 20, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "bomb_rep.lua", 3, "not enough memory (script memory cap 1 MiB)");
    limen_script_destroy(sc);
    CHECK(load_limited("bomb_concat.lua", HEAD "local x = \"x\"\nwhile true do x = x .. x end\n", 0,
                       1 << 20, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "bomb_concat.lua", 4, "not enough memory (script memory cap 1 MiB)");
    limen_script_destroy(sc);
    /* the script's own pcall cannot catch the cap: the error reaches the caller */
    CHECK(load_limited("bomb_caught.lua", HEAD "local ok = pcall(function()\n"
                       "  local t = {}\n  while true do t[#t + 1] = {} end\nend)\n"
                       "assert(not ok)\nreturn s\n", 0, 1 << 20, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "bomb_caught.lua", 5, "not enough memory (script memory cap 1 MiB)");
    limen_script_destroy(sc);
    /* no cap */
    CHECK_OK(load_limited("big.lua", HEAD "local x = string.rep(\"x\", 4 << 20)\nreturn s\n", 0,
                          -1, &sc));
    limen_script_destroy(sc);
    /* a cap too small for the standard library */
    CHECK(load_limited("tiny.lua", HEAD "return s\n", 0, 1000, &sc) != LIMEN_OK);
    CHECK_MSG(sc && strstr(limen_script_error(sc), "not enough memory") != NULL, "%s",
              limen_script_error(sc));
    limen_script_destroy(sc);
}

/* The scenes' C-side nodes count against the cap too: their slots stay after the nodes go, so
 * filling and emptying scene after scene would otherwise grow the program without bound. */
static void test_memory_scenes(void)
{
    limen_script *sc = NULL;
    CHECK(load_limited("scenes_bomb.lua", HEAD "local keep = {}\nfor k = 1, 100 do\n"
                       "  local o = limen.scene {}\n  local nodes = {}\n"
                       "  for i = 1, 4096 do nodes[i] = o:group {} end\n"
                       "  for i = 1, 4096 do nodes[i]:destroy() end\n  keep[k] = o\nend\n",
                       0, 4 << 20, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "scenes_bomb.lua", 7, "not enough memory (script memory cap 4 MiB)");
    limen_script_destroy(sc);
    /* the memory comes back with the scenes */
    expect_loads("scenes_churn.lua", HEAD "for k = 1, 8 do\n"
                 "  local o = limen.scene {}\n  for i = 1, 1500 do o:group {} end\n"
                 "  o = nil\n  collectgarbage()\nend\nreturn s\n", 0, 4 << 20);
}

/* A memory bomb in update stops the script cleanly; the next update fails the same way. */
static void test_memory_update(void)
{
    limen_script *sc = NULL;
    CHECK_OK(load_limited("upd_bomb.lua", HEAD "local hold = {}\nfunction s.update(t)\n"
                          "  while true do hold[#hold + 1] = { t } end\nend\nreturn s\n",
                          0, 1 << 20, &sc));
    CHECK(limen_script_update(sc, 1) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "upd_bomb.lua", 5, "not enough memory (script memory cap 1 MiB)");
    CHECK(limen_script_update(sc, 2) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "upd_bomb.lua", 5, "not enough memory (script memory cap 1 MiB)");
    CHECK(limen_script_scene(sc) != NULL);
    limen_script_destroy(sc);
}

/* Library functions that loop over their arguments pay for it, or are refused. */
static void test_metered(void)
{
    limen_script *sc = NULL;
    CHECK_OK(load_limited("rep_empty.lua", HEAD "assert(string.rep(\"\", 1e15) == \"\")\n"
                          "assert((\"ab\"):rep(3, \",\") == \"ab,ab,ab\")\nreturn s\n", 0, 0, &sc));
    limen_script_destroy(sc);
    CHECK(load_limited("insert_len.lua", HEAD "local t = setmetatable({}, { __len = function()\n"
                       "  return 1e15 end })\ntable.insert(t, 1, 0)\n", 0, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "insert_len.lua", 5, "script exceeded its instruction budget (50000000)");
    limen_script_destroy(sc);
    CHECK(load_limited("move.lua", HEAD "table.move({}, 1, 1e15, 2)\n", 0, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "move.lua", 3, "script exceeded its instruction budget (50000000)");
    limen_script_destroy(sc);
    CHECK(load_limited("pattern.lua", HEAD "local x = string.rep(\"a\", 30000)\n"
                       "return x:find(\"a*a*a*b\")\n", 0, 0, &sc) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(sc && strstr(limen_script_error(sc), "pattern.lua:4: string.find: this pattern could "
                           "take up to ") && strstr(limen_script_error(sc), " steps on a subject "
                           "of 30000 bytes, more than the script's instruction budget allows"),
              "%s", limen_script_error(sc));
    limen_script_destroy(sc);
    /* ordinary patterns on long subjects are fine */
    expect_loads("pattern_ok.lua", HEAD "local words = string.rep(\"ab cd \", 20000)\n"
                 "local n = 0\nfor w in words:gmatch(\"%S+\") do n = n + 1 end\n"
                 "assert(n == 40000)\n"
                 "assert(select(2, words:gsub(\"(%w+) (%w+)\", \"%2 %1\")) == 20000)\n"
                 "assert(words:find(\"cd ab\", 1, true) == 4)\n"
                 "assert((\"k=v\"):match(\"^(%w+)=(%w+)$\") == \"k\")\nreturn s\n",
                 0, 0);
    /* one instruction comparing two long strings: the time limit (1 s here) ends it */
    CHECK(load_limited("compare.lua", HEAD "local a, b = (\"x\"):rep(4096):rep(4096), (\"x\"):rep(4096):rep(4096)\n"
                       "while a == b do end\n", 5000000, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "compare.lua", 4, "script exceeded its time limit (1 s, set by its "
                   "instruction budget)");
    limen_script_destroy(sc);
}

/* Limits belong to each script: one that runs out leaves another alone. */
static void test_limits_per_script(void)
{
    limen_script *good = NULL, *bad_one = NULL;
    CHECK_OK(limen_script_load(script("plain.lua", plain), NULL, &good));
    CHECK(load_limited("loop.lua", HEAD "while true do end\n", 100000, 0, &bad_one) ==
          LIMEN_ERR_SCRIPT);
    CHECK_OK(limen_script_update(good, 1));
    CHECK(limen_script_update(bad_one, 1) == LIMEN_ERR_SCRIPT);
    CHECK_OK(limen_script_update(good, 2));
    CHECK(strcmp(limen_script_error(good), "") == 0);
    limen_script_destroy(bad_one);
    CHECK_OK(limen_script_update(good, 3));
    limen_script_destroy(good);
}

/* The fuzzer's entry: a script from memory reads like one from a file of that name. */
static void test_buffer_load(void)
{
    limen_script *sc = NULL;
    CHECK_OK(limen__script_load_buffer("mem.lua", plain, strlen(plain), NULL, &sc));
    CHECK(limen_script_animated(sc) == 1);
    CHECK_OK(limen_script_update(sc, 0));
    limen_script_destroy(sc);
    const char *bad_text = HEAD "s:sphere { radius = 0 }\n";
    CHECK(limen__script_load_buffer("mem.lua", bad_text, strlen(bad_text), NULL, &sc) ==
          LIMEN_ERR_SCRIPT);
    CHECK_MSG(sc && strcmp(limen_script_error(sc), "mem.lua:3: sphere: field 'radius' must be a "
                           "positive number (got 0)") == 0, "%s", limen_script_error(sc));
    limen_script_destroy(sc);
    CHECK(limen__script_load_buffer("mem.lua", NULL, 0, NULL, &sc) == LIMEN_ERR_ARG);
    limen_script_destroy(sc);
}


/* Checks that sc failed with a message ending in `tail` (the line may vary with the case). */
static void expect_tail(const limen_script *sc, const char *name, const char *tail)
{
    const char *msg = sc ? limen_script_error(sc) : "(no script)";
    size_t n = strlen(msg), t = strlen(tail);
    CHECK_MSG(n >= t && strcmp(msg + n - t, tail) == 0 && strstr(msg, name),
              "%s:\n    got      '%s'\n    expected '...%s'", name, msg, tail);
}

/* Processor time of this thread, in seconds. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------------------------ one budget for all threads */

#define WORK "local function work() local x = 0 for i = 1, 150 do x = x + i end end\n"

/* Work spread over many coroutines, each shorter than a hook interval, is counted: before, a
 * coroutine that never reached its first hook ran free (10,000 of them here run 6 million
 * instructions against a budget of 2 million). */
static void test_budget_coroutines(void)
{
    static const struct { const char *name, *text; } spread[] = {
        { "co_wrap.lua", HEAD WORK "for k = 1, 10000 do coroutine.wrap(work)() end\nreturn s\n" },
        { "co_resume.lua", HEAD WORK "for k = 1, 10000 do\n"
          "  assert(coroutine.resume(coroutine.create(work)))\nend\nreturn s\n" },
        { "co_nested.lua", HEAD WORK "local function f(d)\n  if d == 0 then return work() end\n"
          "  for i = 1, 10 do coroutine.wrap(f)(d - 1) end\nend\nf(4)\nreturn s\n" },
        { "co_pcall.lua", HEAD WORK "for k = 1, 10000 do\n"
          "  pcall(coroutine.wrap(function() work() error(\"x\") end))\nend\nreturn s\n" },
        { "co_close.lua", HEAD WORK "for k = 1, 10000 do\n"
          "  local co = coroutine.create(function()\n"
          "    local t <close> = setmetatable({}, { __close = work })\n"
          "    coroutine.yield()\n  end)\n  coroutine.resume(co)\n  coroutine.close(co)\nend\n"
          "return s\n" },
    };
    for (size_t i = 0; i < sizeof spread / sizeof spread[0]; i++) {
        limen_script *sc = NULL;
        CHECK_MSG(load_limited(spread[i].name, spread[i].text, 2000000, 0, &sc) ==
                  LIMEN_ERR_SCRIPT, "%s loaded", spread[i].name);
        expect_tail(sc, spread[i].name, "script exceeded its instruction budget (2000000)");
        limen_script_destroy(sc);
        /* what arming a coroutine costs leaves the default budget ample for them */
        CHECK_OK(load_limited(spread[i].name, spread[i].text, 0, 0, &sc));
        limen_script_destroy(sc);
    }
    /* a coroutine stopped by the budget stops the script that resumes it, whatever catches */
    limen_script *sc = NULL;
    CHECK(load_limited("co_catch.lua", HEAD "local co = coroutine.create(function()\n"
                       "  while true do end\nend)\nlocal ok = coroutine.resume(co)\n"
                       "assert(not ok)\nreturn s\n", 100000, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_tail(sc, "co_catch.lua", "script exceeded its instruction budget (100000)");
    limen_script_destroy(sc);
}

/* Compiling is work: load charges a byte of source in four, and so does the script's own text
 * (here 6.4 MB of comments, which allocate nothing, against a budget of 1 million). */
static void test_budget_load_metered(void)
{
    limen_script *sc = NULL;
    CHECK(load_limited("load_big.lua", HEAD "local src = (\"--\" .. (\"x\"):rep(62) .. "
                       "\"\\n\"):rep(100000)\nassert(load(src))\nreturn s\n", 1000000, 0, &sc)
          == LIMEN_ERR_SCRIPT);
    expect_message(sc, "load_big.lua", 4, "script exceeded its instruction budget (1000000)");
    limen_script_destroy(sc);
    CHECK(load_limited("load_reader.lua", HEAD "local piece = (\"--\" .. (\"x\"):rep(62) .. "
                       "\"\\n\"):rep(1000)\nlocal n = 0\nassert(load(function()\n"
                       "  n = n + 1\n  return n <= 100 and piece or nil\nend))\nreturn s\n",
                       1000000, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_tail(sc, "load_reader.lua", "script exceeded its instruction budget (1000000)");
    limen_script_destroy(sc);
    size_t len = 64 * 100000;
    char *text = malloc(len + 64);
    if (!text)
        return;
    strcpy(text, HEAD);
    size_t at = strlen(text);
    while (at + 64 < len) {
        memcpy(text + at, "--", 2);
        memset(text + at + 2, 'x', 61);
        text[at + 63] = '\n';
        at += 64;
    }
    strcpy(text + at, "return s\n");
    limen_script_desc desc = { .instruction_budget = 1000000 };
    CHECK(limen__script_load_buffer("mem.lua", text, strlen(text), &desc, &sc) ==
          LIMEN_ERR_SCRIPT);
    expect_tail(sc, "mem.lua", "script exceeded its instruction budget (1000000)");
    limen_script_destroy(sc);
    desc.instruction_budget = 0;
    CHECK_OK(limen__script_load_buffer("mem.lua", text, strlen(text), &desc, &sc));
    limen_script_destroy(sc);
    /* the same text from a file */
    CHECK(load_limited("comments.lua", text, 1000000, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_tail(sc, "comments.lua", "script exceeded its instruction budget (1000000)");
    limen_script_destroy(sc);
    CHECK_OK(load_limited("comments.lua", text, 0, 0, &sc));
    limen_script_destroy(sc);
    free(text);
    /* a file read in slices keeps what luaL_loadfilex does: a BOM and a '#' first line are
     * skipped, the line numbers stay */
    CHECK(load_limited("shebang.lua", "\xEF\xBB\xBF#!/usr/bin/env lua\n" HEAD "error(\"x\")\n",
                       0, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "shebang.lua", 4, "x");
    limen_script_destroy(sc);
}

/* s:nodes() pays for its sort: 100 calls on 4,000 nodes charge 4.8 million. */
static void test_budget_nodes(void)
{
    limen_script *sc = NULL;
    const char *text = HEAD "for i = 1, 4000 do s:group {} end\n"
                       "for k = 1, 100 do assert(#s:nodes() == 4000) end\nreturn s\n";
    CHECK(load_limited("nodes.lua", text, 3000000, 0, &sc) == LIMEN_ERR_SCRIPT);
    expect_message(sc, "nodes.lua", 4, "script exceeded its instruction budget (3000000)");
    limen_script_destroy(sc);
    CHECK_OK(load_limited("nodes.lua", text, 0, 0, &sc));
    limen_script_destroy(sc);
}

/* ------------------------------------------------------------------ the time limit */

/* Instructions and library calls whose time grows with their operands end within a small
 * factor of the time limit (1 s here, processor time): comparing two 16 MiB strings is one
 * instruction of some 30 ms, which the hook used to let run a thousand times before it looked
 * at the clock (half a minute), and more in coroutines too short to reach their first hook. */
static void test_time_limit_holds(void)
{
    static const struct { const char *name, *text, *tail; } slow[] = {
        { "cmp.lua", HEAD "local a, b = (\"\\0\"):rep(4096):rep(4096), (\"\\0\"):rep(4096):rep(4096)\n"
          "while true do local _ = a < b end\n",
          "script exceeded its time limit (1 s, set by its instruction budget)" },
        { "cmp_co.lua", HEAD "local a, b = (\"\\0\"):rep(4096):rep(4096), (\"\\0\"):rep(4096):rep(4096)\n"
          "while true do\n  coroutine.wrap(function() for i = 1, 50 do local _ = a < b end end)()\n"
          "end\n", "script exceeded its time limit (1 s, set by its instruction budget)" },
        { "cmp_sort.lua", HEAD "local a, t = (\"\\0\"):rep(1 << 20), {}\n"
          "for i = 1, 2000 do t[i] = a end\ntable.sort(t)\n",
          "script exceeded its instruction budget (10000000)" },
        { "estimator.lua", HEAD "local p = \"^\" .. (\"z*\"):rep(8 << 20)\n"
          "return (\"a\"):rep(1000):find(p)\n",
          "script exceeded its instruction budget (10000000)" },
    };
    for (size_t i = 0; i < sizeof slow / sizeof slow[0]; i++) {
        limen_script *sc = NULL;
        double t0 = cpu_now();
        CHECK_MSG(load_limited(slow[i].name, slow[i].text, 10000000, 0, &sc) ==
                  LIMEN_ERR_SCRIPT, "%s loaded", slow[i].name);
        double spent = cpu_now() - t0;
        expect_tail(sc, slow[i].name, slow[i].tail);
        CHECK_MSG(spent < 3.0, "%s: %.2f s of processor time for a limit of 1 s", slow[i].name,
                  spent);
        limen_script_destroy(sc);
    }
}

/* The time limit counts the script's processor time, not the wall clock's: on a busy machine
 * (here four threads spinning on the script's processor) endless recursion still ends at the
 * memory cap, its intended limit, rather than at the time limit (1 s here) as it did at times
 * (tests/malformed/stack_overflow.lua). */
static atomic_int spinning;

static void *spin(void *arg)
{
    cpu_set_t *one = arg;
    pthread_setaffinity_np(pthread_self(), sizeof *one, one);
    while (atomic_load(&spinning))
        ;
    return NULL;
}

static void test_busy_machine(void)
{
    cpu_set_t old, one;
    CPU_ZERO(&one);
    if (sched_getaffinity(0, sizeof old, &old) != 0)
        return;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &old)) {
            CPU_SET(c, &one);
            break;
        }
    pthread_setaffinity_np(pthread_self(), sizeof one, &one);
    pthread_t busy[4];
    atomic_store(&spinning, 1);
    int started = 0;
    for (; started < 4; started++)
        if (pthread_create(&busy[started], NULL, spin, &one) != 0)
            break;
    limen_script *sc = NULL;
    struct timespec w0, w1;
    clock_gettime(CLOCK_MONOTONIC, &w0);
    CHECK(load_limited("recurse.lua", HEAD "local function f() return 1 + f() end\nf()\n",
                       10000000, 16 << 20, &sc) == LIMEN_ERR_SCRIPT);
    clock_gettime(CLOCK_MONOTONIC, &w1);
    atomic_store(&spinning, 0);
    for (int i = 0; i < started; i++)
        pthread_join(busy[i], NULL);
    pthread_setaffinity_np(pthread_self(), sizeof old, &old);
    expect_message(sc, "recurse.lua", 3, "not enough memory (script memory cap 16 MiB)");
    printf("     recursion to the cap: %.2f s on a shared processor\n",
           (double)(w1.tv_sec - w0.tv_sec) + 1e-9 * (double)(w1.tv_nsec - w0.tv_nsec));
    limen_script_destroy(sc);
}

/* ------------------------------------------------------------------ the memory cap */

#define BOMB "local function bomb() local t = {} while true do t[#t + 1] = {} end end\n"

/* No catcher stops the memory cap: pcall, xpcall and its handler, coroutine.resume, wrap and
 * close, load; each script goes on as if nothing happened if it can catch it. */
static void test_memory_uncatchable(void)
{
    static const struct { const char *name, *text; int line; } caught[] = {
        { "mem_pcall.lua", HEAD BOMB "pcall(bomb)\nreturn s\n", 3 },
        { "mem_xpcall.lua", HEAD BOMB "xpcall(bomb, function(e) return e end)\nreturn s\n", 3 },
        { "mem_handler.lua", HEAD BOMB "xpcall(error, function(e) bomb() end)\nreturn s\n", 3 },
        { "mem_resume.lua", HEAD BOMB "coroutine.resume(coroutine.create(bomb))\nreturn s\n", 3 },
        { "mem_wrap.lua", HEAD BOMB "pcall(coroutine.wrap(bomb))\nreturn s\n", 3 },
        { "mem_close.lua", HEAD BOMB "local co = coroutine.create(function()\n"
          "  local t <close> = setmetatable({}, { __close = bomb })\n  coroutine.yield()\nend)\n"
          "coroutine.resume(co)\ncoroutine.close(co)\nreturn s\n", 3 },
        { "mem_load.lua", HEAD "local f = load(function() return (\"x\"):rep(2 << 20) end)\n"
          "assert(not f)\nreturn s\n", 3 },
        { "mem_buffer.lua", HEAD "local keep = (\"y\"):rep(400000)\n"
          "pcall(string.rep, \"x\", 700000)\nreturn s\n", 4 },
        { "mem_concat.lua", HEAD "local keep = (\"y\"):rep(400000)\n"
          "pcall(function() return keep .. keep end)\nreturn s\n", 4 },
        { "mem_nested.lua", HEAD BOMB "for i = 1, 10 do pcall(pcall, pcall, bomb) end\nreturn s\n",
          3 },
    };
    for (size_t i = 0; i < sizeof caught / sizeof caught[0]; i++) {
        limen_script *sc = NULL;
        CHECK_MSG(load_limited(caught[i].name, caught[i].text, 0, 1 << 20, &sc) ==
                  LIMEN_ERR_SCRIPT, "%s loaded", caught[i].name);
        expect_message(sc, caught[i].name, caught[i].line,
                       "not enough memory (script memory cap 1 MiB)");
        limen_script_destroy(sc);
    }
    /* garbage is not a hit: an emergency collection that makes room lets the script go on */
    expect_loads("mem_garbage.lua", HEAD "collectgarbage(\"stop\")\n"
                 "for i = 1, 100 do\n  local x = {}\n  for j = 1, 1000 do x[j] = j end\n"
                 "end\nreturn s\n", 0, 1 << 20);
}

/* No cap aborts the program: every cap from 0 to 64 KiB, 16 bytes apart, loads (or fails with
 * a message) and updates. A message made outside a protected call used to abort at ~5 KB. */
static void test_small_caps(void)
{
    const char *path = script("caps.lua", HEAD "local b = s:sphere {}\n"
                              "function s.update(t)\n  local x = {}\n"
                              "  for i = 1, 100 do x[i] = { i } end\n  b.pos = {t, 0, 0}\nend\n"
                              "return s\n");
    int loaded = 0;
    for (int64_t cap = 0; cap <= 64 << 10; cap += 16) {
        limen_script *sc = NULL;
        limen_status st = limen_script_load(path, &(limen_script_desc){ .memory_cap = cap }, &sc);
        CHECK_MSG(st == LIMEN_OK || (sc && strstr(limen_script_error(sc), "not enough memory")),
                  "cap %lld: status %d, '%s'", (long long)cap, st, sc ? limen_script_error(sc) : "");
        if (st == LIMEN_OK) {
            loaded++;
            st = limen_script_update(sc, 1);
            CHECK_MSG(st == LIMEN_OK || strstr(limen_script_error(sc), "not enough memory"),
                      "cap %lld: update: '%s'", (long long)cap, limen_script_error(sc));
        }
        limen_script_destroy(sc);
    }
    CHECK(loaded > 0);   /* 0 means no cap: it loads */
}

/* ------------------------------------------------------------------ what a safe script shows */

static char printed[8][1024];
static int nprinted;

static void take_line(void *user, const char *line)
{
    (*(int *)user)++;
    if (nprinted < 8)
        snprintf(printed[nprinted++], sizeof printed[0], "%s", line);
}

/* print goes to the host's callback, one escaped line a call; without one, nowhere: never to
 * the host's stdout, where a script could forge the program's own output. */
static void test_print(void)
{
    const char *path = script("print.lua", HEAD "print(\"a\\nb\", 1, nil, true)\n"
                              "print(\"{\\\"frame\\\": 0}\")\nprint(\"\\255\")\nreturn s\n");
    int calls = 0;
    nprinted = 0;
    limen_script *sc = NULL;
    CHECK_OK(limen_script_load(path, &(limen_script_desc){ .print = take_line,
                                                           .print_user = &calls }, &sc));
    limen_script_destroy(sc);
    CHECK(calls == 3);
    CHECK_MSG(strcmp(printed[0], "a\\nb\\t1\\tnil\\ttrue") == 0, "'%s'", printed[0]);
    CHECK_MSG(strcmp(printed[1], "{\"frame\": 0}") == 0, "'%s'", printed[1]);
    CHECK_MSG(strcmp(printed[2], "\\xFF") == 0, "'%s'", printed[2]);
    /* no callback: stdout stays empty */
    char out[] = "/tmp/limen-stdout.XXXXXX";
    int fd = mkstemp(out);
    if (fd < 0)
        return;
    fflush(stdout);
    int saved = dup(1);
    dup2(fd, 1);
    CHECK_OK(limen_script_load(path, NULL, &sc));
    limen_script_destroy(sc);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    CHECK_MSG(lseek(fd, 0, SEEK_END) == 0, "a safe script wrote %lld bytes to stdout",
              (long long)lseek(fd, 0, SEEK_END));
    close(fd);
    unlink(out);
}

/* No address reaches a safe script: tostring, print and string.format show a number in its
 * place (the same for the same value), and math.randomseed() returns no address (the stock
 * one returned the state's). */
static void test_no_addresses(void)
{
    expect_loads("addresses.lua", HEAD
                 "local t, u = {}, {}\n"
                 "assert(tostring(t):match(\"^table: #%d+$\"), tostring(t))\n"
                 "assert(tostring(t) == tostring(t) and tostring(t) ~= tostring(u))\n"
                 "assert(tostring(print):match(\"^function: #%d+$\"))\n"
                 "assert(tostring(coroutine.running()):match(\"^thread: #%d+$\"))\n"
                 "local p = string.format(\"%p|%8p|%p|%p\", t, u, 1, \"str\")\n"
                 "assert(p:match(\"^#%d+| +#%d+|%(null%)|#%d+$\"), p)\n"
                 "assert(string.format(\"%s\", t) == tostring(t))\n"
                 "assert(string.format(\"%p\", t) == tostring(t):match(\"#%d+\"))\n"
                 "assert(string.format(\"%5.1f %%p %s\", 1, \"x\") == \"  1.0 %p x\")\n"
                 "local named = setmetatable({}, { __name = \"thing\" })\n"
                 "assert(tostring(named):match(\"^thing: #%d+$\"), tostring(named))\n"
                 "assert(tostring(setmetatable({}, { __tostring = function() "
                 "return \"mine\" end })) == \"mine\")\n"
                 "local a, b = math.randomseed()\n"
                 "assert(b >= 0 and b < 1000000000, b)\n"
                 "assert(math.random(1, 6) >= 1)\n"
                 "assert(not tostring(s):find(\"0x\"))\nreturn s\n", 0, 0);
}

static const check_case cases[] = {
    { "budget_load", test_budget_load },
    { "budget_update", test_budget_update },
    { "budget_default", test_budget_default },
    { "budget_coroutines", test_budget_coroutines },
    { "budget_load_metered", test_budget_load_metered },
    { "budget_nodes", test_budget_nodes },
    { "memory_load", test_memory_load },
    { "memory_scenes", test_memory_scenes },
    { "memory_update", test_memory_update },
    { "memory_uncatchable", test_memory_uncatchable },
    { "small_caps", test_small_caps },
    { "metered", test_metered },
    { "time_limit_holds", test_time_limit_holds },
    { "busy_machine", test_busy_machine },
    { "limits_per_script", test_limits_per_script },
    { "buffer_load", test_buffer_load },
    { "print", test_print },
    { "no_addresses", test_no_addresses },
    { 0 }
};

int main(int argc, char **argv)
{
    return scratch_main(argc, argv, cases);
}
