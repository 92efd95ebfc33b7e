/* speed.c - speed per pixel and per view, against two baselines (baseline.h): the floor (a
 * minimal program shading one full-screen wall) and the classic stencil recursion. Each
 * target is a ratio of medians from configurations timed in one run, interleaved frame by
 * frame (every round renders each configuration once), so that the noise of a shared machine
 * falls on all of them alike. Every picture is first checked against the ray tracer.
 *
 *   speed [--quick|--full] [--out DIR] [--scenes DIR] [--gallery DIR]
 *
 * --scenes holds wall.lua and box_room.lua (bench/scenes), --gallery corridor.lua and
 * kaleidoscope.lua (scenes). Writes DIR/speed.csv (every configuration: scene, renderer,
 * depth, median and quartiles, views, bad pixels against the tracer) and DIR/speed.txt (the
 * targets, also printed); the checked pictures go to DIR/speed_pictures/. */
#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "baseline.h"
#include "limen.h"
#include "scene_load.h"
#include "timing.h"

enum { W = 1280, H = 720, MAXF = 64, BAD_THRESHOLD = 8, ROOM_DEPTHS = 17 };
/* A baseline's picture may differ from the tracer's on this share of pixels at most (edges
 * of tessellated spheres, the same rule as the accuracy tests' 0.5%). */
#define BASELINE_BAD 0.005

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "speed: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(1);
}

static double quantile(const double *v, int n, double q)
{
    double s[MAXF];
    memcpy(s, v, sizeof *v * (size_t)n);
    qsort(s, (size_t)n, sizeof *s, cmp_double);
    double pos = q * (n - 1);
    int i = (int)pos;
    return i >= n - 1 ? s[n - 1] : s[i] + (pos - i) * (s[i + 1] - s[i]);
}

/* ------------------------------------------------------------------ scenes */

typedef struct bscene {
    const char *name;
    limen_script *script;
    limen_scene *scene;
    limen_renderer *r;          /* limen's renderer for this scene (stencil method) */
} bscene;

static void load(bscene *b, const char *dir, const char *name)
{
    char msg[600];
    b->name = name;
    /* every surface may go as deep as the depth setting asks */
    b->scene = bench_scene_load(dir, name, 64, &b->script, msg, sizeof msg);
    if (!b->scene)
        die("%s", msg);
    limen_renderer_desc d = { .width = W, .height = H };
    if (limen_renderer_create(&d, &b->r))
        die("renderer: %s", limen_renderer_error(b->r));
}

/* ------------------------------------------------------------------ contenders */

/* LIMEN_QUIET: limen's frames as a game's loop draws them, without stats (NULL: no queries,
 * each frame flushed, not finished), QUIET_BLOCK at a time, the last of them with stats (so
 * finished): time per frame of the block, wall and processor */
enum { QUIET_BLOCK = 4 };
typedef enum kind { LIMEN, FLOOR, CLASSIC, LIMEN_QUIET } kind;
static const char *KIND_NAMES[] = { "limen", "floor", "classic", "limen_loop" };

typedef struct contender {
    kind k;
    bscene *s;
    int depth;
    double ms[MAXF];            /* processor time per frame */
    double wall[MAXF];          /* and wall time */
    double last_wall;
    int n, views;
    double bad;                 /* share of pixels over the threshold against the tracer */
} contender;

static baseline *g_base;

/* One frame; returns its processor time. */
static double run(contender *c)
{
    char err[300] = "";
    double t0 = cpu_ms(), ms;
    if (c->k == LIMEN_QUIET) {
        limen_render_opts o = {
            .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = c->depth,
                        .budget = { INT64_MAX, INT64_MAX } } };
        limen_frame_stats st;
        double w0 = now_ms();
        for (int k = 0; k < QUIET_BLOCK; k++)
            if (limen_render_frame(c->s->r, c->s->scene, &o, k + 1 < QUIET_BLOCK ? NULL : &st))
                die("%s: %s", c->s->name, limen_renderer_error(c->s->r));
        c->last_wall = (now_ms() - w0) / QUIET_BLOCK;
        c->views = st.views;
        return (cpu_ms() - t0) / QUIET_BLOCK;
    }
    if (c->k == LIMEN) {
        limen_render_opts o = {
            .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = c->depth,
                        .budget = { INT64_MAX, INT64_MAX } } };
        limen_frame_stats st;
        if (limen_render_frame(c->s->r, c->s->scene, &o, &st))
            die("%s: %s", c->s->name, limen_renderer_error(c->s->r));
        c->views = st.views;
        c->last_wall = st.ms;
        return cpu_ms() - t0;
    }
    ms = c->k == FLOOR ? baseline_floor_frame(g_base, c->s->scene, err, sizeof err)
                       : baseline_classic_frame(g_base, c->s->scene, c->depth, err, sizeof err);
    if (ms < 0)
        die("%s: %s", c->s->name, err);
    if (c->k == CLASSIC)
        c->views = baseline_views(g_base);
    c->last_wall = ms;
    return cpu_ms() - t0;
}

static double cpu_median(const contender *c)
{
    return quantile(c->ms, c->n, 0.5);
}

static double wall_median(const contender *c)
{
    return quantile(c->wall, c->n, 0.5);
}

/* Renders each contender once and compares its picture with the tracer's at its depth. */
static void check(contender *c, int nc, const char *out, unsigned char *rgb, unsigned char *ref)
{
    for (int i = 0; i < nc; i++) {
        run(&c[i]);
        if (c[i].k == LIMEN || c[i].k == LIMEN_QUIET) {
            if (limen_renderer_read_rgb(c[i].s->r, rgb))
                die("read: %s", limen_renderer_error(c[i].s->r));
        } else {
            baseline_read_rgb(g_base, rgb);
        }
        limen_trace_desc td = { .width = W, .height = H,
                                .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                            .depth = c[i].depth } };
        if (limen_trace_image(c[i].s->scene, &td, ref))
            die("trace %s: %s", c[i].s->name, limen_scene_error(c[i].s->scene));
        limen_diff d;
        if (limen_image_diff(rgb, ref, W, H, BAD_THRESHOLD, &d, NULL))
            die("diff failed");
        c[i].bad = d.bad_share;
        char path[700];
        snprintf(path, sizeof path, "%s/speed_pictures/%s_%s_d%02d.png", out, c[i].s->name,
                 KIND_NAMES[c[i].k], c[i].depth);
        limen_write_png(path, W, H, rgb);
        if ((c[i].k == FLOOR || c[i].k == CLASSIC) && d.bad_share > BASELINE_BAD)
            die("%s %s depth %d: %.3f%% of the pixels differ from the tracer's (%s)",
                KIND_NAMES[c[i].k], c[i].s->name, c[i].depth, 100 * d.bad_share, path);
    }
}

/* Two warm-up rounds, then `rounds` rounds each timing every contender once. */
static void interleave(contender *c, int nc, int rounds)
{
    for (int w = 0; w < 2; w++)
        for (int i = 0; i < nc; i++)
            run(&c[i]);
    for (int i = 0; i < nc; i++)
        c[i].n = 0;
    for (int k = 0; k < rounds && k < MAXF; k++)
        for (int i = 0; i < nc; i++) {
            c[i].ms[c[i].n] = run(&c[i]);
            c[i].wall[c[i].n++] = c[i].last_wall;
        }
}

static void csv_rows(FILE *f, const contender *c, int nc)
{
    for (int i = 0; i < nc; i++)
        fprintf(f, "%s,%s,%d,%d,%.3f,%.3f,%.3f,%d,%.6f,%.3f\n", c[i].s->name,
                KIND_NAMES[c[i].k], c[i].depth, c[i].n, cpu_median(&c[i]),
                quantile(c[i].ms, c[i].n, 0.25), quantile(c[i].ms, c[i].n, 0.75), c[i].views,
                c[i].bad, wall_median(&c[i]));
}

static FILE *g_txt;

static const char *verdict(int ok)
{
    return ok ? "pass" : "FAIL";
}

static void say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    va_start(ap, fmt);
    vfprintf(g_txt, fmt, ap);
    va_end(ap);
}

/* ------------------------------------------------------------------ threads */

/* Processor time of each of llvmpipe's rasterizer threads in this process (Linux:
 * /proc/self/task/TID/schedstat, nanoseconds on a processor), to tell a frame that keeps
 * every thread busy from one that leaves all the work to one: shares of the work do not
 * depend on what else the machine runs, unlike wall time. */
enum { MAXT = 64 };
typedef struct tsnap {
    int n;
    long tid[MAXT];
    double ms[MAXT];
} tsnap;

static void tsnap_take(tsnap *t)
{
    t->n = 0;
    DIR *d = opendir("/proc/self/task");
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) && t->n < MAXT) {
        char path[300], buf[128];
        snprintf(path, sizeof path, "/proc/self/task/%s/comm", e->d_name);
        FILE *f = fopen(path, "r");
        size_t k = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
        if (f)
            fclose(f);
        buf[k] = '\0';
        if (!strstr(buf, "llvmpipe"))
            continue;
        snprintf(path, sizeof path, "/proc/self/task/%s/schedstat", e->d_name);
        unsigned long long ns = 0;
        if (!(f = fopen(path, "r")))
            continue;
        if (fscanf(f, "%llu", &ns) == 1) {
            t->tid[t->n] = atol(e->d_name);
            t->ms[t->n++] = (double)ns * 1e-6;
        }
        fclose(f);
    }
    closedir(d);
}

/* Runs `frames` frames of c alone and says how its rasterizing spread over llvmpipe's
 * threads: per thread, milliseconds of processor time a frame, and the busiest one's share. */
static void thread_shares(contender *c, int frames, double *busiest_share)
{
    tsnap a, b;
    tsnap_take(&a);
    for (int i = 0; i < frames; i++)
        run(c);
    tsnap_take(&b);
    double total = 0, most = 0;
    say("    %s: llvmpipe threads, processor ms a frame:", KIND_NAMES[c->k]);
    for (int j = 0; j < b.n; j++) {
        double d = b.ms[j];
        for (int i = 0; i < a.n; i++)
            if (a.tid[i] == b.tid[j])
                d -= a.ms[i];
        if (d / frames < 0.05)
            continue;   /* another context's threads */
        say(" %.2f", d / frames);
        total += d;
        most = fmax(most, d);
    }
    *busiest_share = total > 0 ? most / total : 1;
    say(" (the busiest %.0f%% of it)\n", 100 * *busiest_share);
}

int main(int argc, char **argv)
{
    int full = 0;
    const char *out = "build/bench", *scenes = "bench/scenes", *gallery = "scenes", *only = "";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--full"))
            full = 1;
        else if (!strcmp(argv[i], "--quick"))
            full = 0;
        else if (!strcmp(argv[i], "--out") && i + 1 < argc)
            out = argv[++i];
        else if (!strcmp(argv[i], "--scenes") && i + 1 < argc)
            scenes = argv[++i];
        else if (!strcmp(argv[i], "--gallery") && i + 1 < argc)
            gallery = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else
            die("usage: speed [--quick|--full] [--out DIR] [--scenes DIR] [--gallery DIR] "
                "[--only wall|room|gallery]");
    }
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* rounds: the room; the gallery's classic frames are long (hundreds of
     * full-screen views in the kaleidoscope at depth 8, the depth of turn 1's target), so
     * they get fewer */
    const int rounds = full ? 21 : 9, gallery_rounds = full ? 9 : 5, kaleido_depth = 8;
    const int wall_rounds = full ? MAXF : 41;   /* short frames: many rounds are cheap */
    char path[700];
    snprintf(path, sizeof path, "%s/speed_pictures", out);
    char cmd[800];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", path);
    if (system(cmd))
        die("cannot make %s", path);
    snprintf(path, sizeof path, "%s/speed.txt", out);
    g_txt = fopen(path, "w");
    snprintf(path, sizeof path, "%s/speed.csv", out);
    FILE *csv = fopen(path, "w");
    if (!g_txt || !csv)
        die("cannot write into %s", out);
    fprintf(csv, "scene,renderer,depth,frames,ms_median,ms_p25,ms_p75,views,bad_share,"
                 "wall_ms_median\n");

    char err[300];
    g_base = baseline_create(W, H, err, sizeof err);
    if (!g_base)
        die("%s", err);
    bscene wall, room, corridor, kaleido;
    load(&wall, scenes, "wall");
    load(&room, scenes, "box_room");
    load(&corridor, gallery, "corridor");
    load(&kaleido, gallery, "kaleidoscope");
    unsigned char *rgb = malloc((size_t)W * H * 3), *ref = malloc((size_t)W * H * 3);
    if (!rgb || !ref)
        die("out of memory");

    say("\nspeed targets (%s run, %dx%d, stencil method; each ratio from medians of the "
        "processor time per frame of configurations timed in interleaved rounds):\n",
        full ? "full" : "quick", W, H);

    int every = !*only;
    double bad_wall = NAN, bad_floor = NAN, bad_room = NAN, bad_classic = NAN;
    if (every || !strcmp(only, "wall")) {
        /* the wall against the floor, and limen's frame without stats (no queries) */
        contender cw[3] = { { .k = LIMEN, .s = &wall }, { .k = FLOOR, .s = &wall },
                            { .k = LIMEN_QUIET, .s = &wall } };
        check(cw, 3, out, rgb, ref);
        interleave(cw, 3, wall_rounds);
        csv_rows(csv, cw, 3);
        /* a game feels wall time; processor time beside it shows whether the frame used
         * llvmpipe's threads (LP_NUM_THREADS, named here as the run set it) */
        double wr = cpu_median(&cw[0]) / cpu_median(&cw[1]);
        double ww = wall_median(&cw[0]) / wall_median(&cw[1]);
        double qw = wall_median(&cw[2]) / wall_median(&cw[1]);
        double qr = cpu_median(&cw[2]) / cpu_median(&cw[1]);
        const char *lp = getenv("LP_NUM_THREADS");
        say("wall depth 0 <= 1.3x the floor in wall time (LP_NUM_THREADS %s): %.2fx (limen "
            "%.2f ms, floor %.2f ms wall; processor time %.2fx: %.2f against %.2f ms; %d "
            "rounds): %s\n", lp ? lp : "unset", ww, wall_median(&cw[0]), wall_median(&cw[1]),
            wr, cpu_median(&cw[0]), cpu_median(&cw[1]), wall_rounds, verdict(ww <= 1.3));
        say("    as a game's loop (without stats: no queries, each frame flushed, not finished; "
            "%d a block, the last with stats): %.2fx the floor in wall time (%.2f ms a frame), "
            "%.2fx in processor time (%.2f ms)\n", QUIET_BLOCK, qw, wall_median(&cw[2]), qr,
            cpu_median(&cw[2]));
        /* one line for bench/run.sh, which repeats this run with each thread count and
         * takes the medians: threads, wall ratio, processor ratio, the same as a game loop */
        snprintf(path, sizeof path, "%s/wall_ratios.csv", out);
        FILE *wf = fopen(path, "a");
        if (wf) {
            fprintf(wf, "%s,%.4f,%.4f,%.4f,%.4f\n", lp ? lp : "unset", ww, wr, qw, qr);
            fclose(wf);
        }
        double share[2];
        thread_shares(&cw[0], wall_rounds, &share[0]);
        thread_shares(&cw[1], wall_rounds, &share[1]);
        bad_wall = cw[0].bad, bad_floor = cw[1].bad;
    }
    if (every || !strcmp(only, "room")) {
        /* the box room: limen and the classic recursion at every depth 0..16 */
        contender cr[2 * ROOM_DEPTHS];
        for (int d = 0; d < ROOM_DEPTHS; d++) {
            cr[d] = (contender){ .k = LIMEN, .s = &room, .depth = d };
            cr[ROOM_DEPTHS + d] = (contender){ .k = CLASSIC, .s = &room, .depth = d };
        }
        fprintf(stderr, "speed: checking the box room against the tracer at 17 depths\n");
        check(cr, 2 * ROOM_DEPTHS, out, rgb, ref);
        fprintf(stderr, "speed: timing the box room\n");
        interleave(cr, 2 * ROOM_DEPTHS, rounds);
        csv_rows(csv, cr, 2 * ROOM_DEPTHS);
        double r16 = cpu_median(&cr[16]) / cpu_median(&cr[0]), r11 = cpu_median(&cr[11]) / cpu_median(&cr[10]);
        say("box room depth 16 <= 1.25x depth 0: %.2fx (%.1f ms, %d views, against %.1f ms; "
            "wall time %.2fx): %s\n", r16, cpu_median(&cr[16]), cr[16].views, cpu_median(&cr[0]),
            wall_median(&cr[16]) / wall_median(&cr[0]), verdict(r16 <= 1.25));
        say("box room depth 11 <= 1.15x depth 10: %.2fx (%.1f ms against %.1f ms; wall time "
            "%.2fx): %s\n", r11, cpu_median(&cr[11]), cpu_median(&cr[10]),
            wall_median(&cr[11]) / wall_median(&cr[10]), verdict(r11 <= 1.15));
        double worst = INFINITY;
        int worst_d = 0;
        for (int d = 0; d < ROOM_DEPTHS; d++) {
            double x = cpu_median(&cr[ROOM_DEPTHS + d]) / cpu_median(&cr[d]);
            if (x < worst)
                worst = x, worst_d = d;
        }
        say("box room >= 2x faster than the classic recursion at every depth 0-16: %.2fx at worst "
            "(depth %d: %.1f ms against %.1f ms): %s\n    per depth:", worst, worst_d,
            cpu_median(&cr[worst_d]), cpu_median(&cr[ROOM_DEPTHS + worst_d]), verdict(worst >= 2));
        for (int d = 0; d < ROOM_DEPTHS; d++)
            say(" %d:%.1f/%.1f", d, cpu_median(&cr[d]), cpu_median(&cr[ROOM_DEPTHS + d]));
        say(" (limen/classic ms)\n    wall time per depth:");
        for (int d = 0; d < ROOM_DEPTHS; d++)
            say(" %d:%.1f/%.1f", d, wall_median(&cr[d]), wall_median(&cr[ROOM_DEPTHS + d]));
        say(" (limen/classic ms)\n");
        bad_room = cr[16].bad, bad_classic = cr[2 * ROOM_DEPTHS - 1].bad;
    }
    if (every || !strcmp(only, "gallery")) {
        /* the gallery's corridor and kaleidoscope */
        struct { bscene *s; int depth; } gal[2] = { { &corridor, 12 }, { &kaleido, kaleido_depth } };
        for (int g = 0; g < 2; g++) {
            contender cg[2] = { { .k = LIMEN, .s = gal[g].s, .depth = gal[g].depth },
                                { .k = CLASSIC, .s = gal[g].s, .depth = gal[g].depth } };
            fprintf(stderr, "speed: %s depth %d\n", gal[g].s->name, gal[g].depth);
            check(cg, 2, out, rgb, ref);
            interleave(cg, 2, gallery_rounds);
            csv_rows(csv, cg, 2);
            double x = cpu_median(&cg[1]) / cpu_median(&cg[0]);
            say("%s depth %d >= 2x faster than the classic recursion: %.2fx (limen %.1f ms, %d "
                "views; classic %.1f ms, %d views; %d rounds; wall time %.2fx): %s\n",
                gal[g].s->name, gal[g].depth, x, cpu_median(&cg[0]), cg[0].views, cpu_median(&cg[1]),
                cg[1].views, gallery_rounds, wall_median(&cg[1]) / wall_median(&cg[0]),
                verdict(x >= 2));
        }
    }
    say("pictures against the tracer (share of pixels off by more than %d/255): limen wall "
        "%.3f%%, room depth 16 %.3f%%; classic room depth 16 %.3f%%; floor %.3f%%\n",
        BAD_THRESHOLD, 100 * bad_wall, 100 * bad_room, 100 * bad_classic, 100 * bad_floor);

    fclose(csv);
    fclose(g_txt);
    bscene *all[4] = { &wall, &room, &corridor, &kaleido };
    for (int i = 0; i < 4; i++) {
        limen_renderer_destroy(all[i]->r);
        limen_script_destroy(all[i]->script);
    }
    baseline_destroy(g_base);
    free(rgb);
    free(ref);
    return 0;
}
