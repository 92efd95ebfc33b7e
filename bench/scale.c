/* scale.c - how cost grows with what a scene holds: plan time of the long hall
 * (tests/hall.h: 50 portal pairs) and trace time of the sphere field, against the number
 * of objects, with the spatial index and without it (the scan of every surface per view,
 * of every portal per shape, of every prim per ray, which the library keeps for its tests).
 * Then the targets, each pair of configurations measured interleaved in one run (so that a
 * shared machine's noise falls on both alike), as ratios:
 *   - one plan of the hall with 10,000 spheres <= 2 ms and <= 10x the hall with 1,000;
 *   - the trace of 20,000 spheres <= 4x the trace of 200;
 *   - churn: at 1,000 and 10,000 spheres, a frame that creates one sphere (and places it)
 *     then plans, and one that destroys a sphere then plans, each against the plan of a frame
 *     where nothing changed, the three interleaved frame by frame on the same hall: at
 *     10,000 the frame with a sphere added <= 1.5x the unchanged one. Medians, and means
 *     (which count the full rebuilds that a quarter of the index's size in changes brings).
 *
 *   scale [--out DIR] [--churn]
 *
 * --churn measures the churn alone and prints it (nothing written).
 * Writes DIR/scale_plan.csv, DIR/scale_trace.csv and DIR/scale_targets.txt; a line per
 * point on stderr. Timings are medians. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "../tests/hall.h"
#include "timing.h"

/* traces on one thread: the shared machine's other work disturbs one thread less */
enum { PAIRS = 50, TRACE_W = 320, TRACE_H = 240 };

static void fail(const char *what, limen_scene *s)
{
    fprintf(stderr, "scale: %s: %s\n", what, s ? limen_scene_error(s) : "out of memory");
    exit(1);
}

/* ------------------------------------------------------------------ plans */

typedef struct hall {
    limen_scene *s;
    limen_plan *p;
    limen_node *balls;
    int n;
} hall;

static hall hall_open(int n, bool brute)
{
    hall h = { .n = n };
    h.s = hall_create(n, PAIRS, 7);
    if (!h.s || limen_plan_create(&h.p))
        fail("hall", h.s);
    h.s->brute_force = brute;
    /* the spheres are the last n nodes created */
    int total = limen_scene_node_count(h.s);
    limen_node *all = malloc(sizeof *all * (size_t)total);
    h.balls = malloc(sizeof *h.balls * (size_t)(n > 0 ? n : 1));
    if (!all || !h.balls)
        fail("hall", NULL);
    limen_scene_nodes(h.s, all, total);
    int k = 0;
    for (int i = 0; i < total; i++)
        if (limen_node_get_kind(h.s, all[i]) == LIMEN_NODE_SPHERE)
            h.balls[k++] = all[i];
    free(all);
    /* the first plan builds the index and the world matrices: not what a frame costs */
    if (limen_plan_build(h.p, h.s, NULL))
        fail("plan", h.s);
    return h;
}

static void hall_close(hall *h)
{
    limen_plan_destroy(h->p);
    limen_scene_destroy(h->s);
    free(h->balls);
}

/* One plan; with `movers`, that many spheres move first (a frame of a game), so the time
 * includes their world matrices and the index's refit. */
static double plan_once(hall *h, int movers, int frame)
{
    for (int i = 0; i < movers && h->n; i++) {
        limen_node b = h->balls[(i * 7919 + frame * 104729) % h->n];
        float pos[3];
        limen_node_get_position(h->s, b, pos);
        pos[1] += (frame % 2 ? 0.01f : -0.01f);
        limen_node_set_position(h->s, b, pos);
    }
    double t0 = now_ms();
    if (limen_plan_build(h->p, h->s, NULL))
        fail("plan", h->s);
    return now_ms() - t0;
}

static double plan_median(hall *h, int reps, int movers)
{
    double *t = malloc(sizeof *t * (size_t)reps);
    for (int i = 0; i < reps; i++)
        t[i] = plan_once(h, movers, i);
    double m = median(t, reps);
    free(t);
    return m;
}

/* ------------------------------------------------------------------ churn */

/* A game's frame at the hall: one sphere created and placed where the hall's are, or one
 * destroyed (at random), or nothing, then a plan; the time of the whole frame. */
static double churn_once(hall *h, int what)
{
    double t0 = now_ms();
    if (what > 0) {
        limen_node b;
        if (limen_node_create(h->s, LIMEN_NODE_SPHERE, NULL, &b))
            fail("create", h->s);
        limen_node_set_position(h->s, b, (float[3]){ (float)(8.1 * hall__uniform() - 4.05),
                                                     (float)(0.1 + 3.8 * hall__uniform()),
                                                     (float)(-4.0 * PAIRS * hall__uniform()) });
        limen_node_set_dims(h->s, b, (float[3]){ 0.08f, 0, 0 });
        h->balls[h->n++] = b;
    } else if (what < 0 && h->n) {
        int k = (int)(hall__uniform() * h->n);
        if (limen_node_destroy(h->s, h->balls[k]))
            fail("destroy", h->s);
        h->balls[k] = h->balls[--h->n];
    }
    if (limen_plan_build(h->p, h->s, NULL))
        fail("plan", h->s);
    return now_ms() - t0;
}

static double mean(const double *v, int n)
{
    double sum = 0;
    for (int i = 0; i < n; i++)
        sum += v[i];
    return n ? sum / n : 0;
}

/* Frames unchanged, with a sphere added, with one removed, interleaved; medians and means
 * into med[3] and avg[3]. */
static void churn_measure(int n, int frames, double med[3], double avg[3])
{
    hall h = hall_open(n, false);
    limen_node *grown = realloc(h.balls, sizeof *grown * (size_t)(n + frames + 1));
    if (!grown)
        fail("churn", NULL);
    h.balls = grown;
    double *t[3];
    for (int c = 0; c < 3; c++)
        if (!(t[c] = malloc(sizeof *t[c] * (size_t)frames)))
            fail("churn", NULL);
    for (int i = 0; i < frames; i++)
        for (int c = 0; c < 3; c++)
            t[c][i] = churn_once(&h, c == 0 ? 0 : c == 1 ? 1 : -1);
    for (int c = 0; c < 3; c++) {
        avg[c] = mean(t[c], frames);
        med[c] = median(t[c], frames);
        free(t[c]);
    }
    hall_close(&h);
}

/* ------------------------------------------------------------------ traces */

static double trace_once(limen_scene *s, unsigned char *rgb)
{
    double t0 = now_ms();
    limen_trace_desc d = { .width = TRACE_W, .height = TRACE_H, .threads = 1 };
    if (limen_trace_image(s, &d, rgb))
        fail("trace", s);
    return now_ms() - t0;
}

/* ------------------------------------------------------------------ main */

int main(int argc, char **argv)
{
    const char *out = "build/bench";
    bool churn_only = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc)
            out = argv[++i];
        else if (!strcmp(argv[i], "--churn"))
            churn_only = true;
        else {
            fprintf(stderr, "usage: scale [--out DIR] [--churn]\n");
            return 2;
        }
    }
    /* enough frames that a quarter of 10,000 in changes (two a frame) rebuilds once, and that
     * of 1,000 some ten times: the means count those builds */
    enum { CHURN_FRAMES = 1401 };
    static const int CHURN_N[2] = { 1000, 10000 };
    double cmed[2][3], cavg[2][3];
    for (int k = 0; k < 2 && churn_only; k++) {
        churn_measure(CHURN_N[k], CHURN_FRAMES, cmed[k], cavg[k]);
        printf("churn %6d spheres: unchanged %.3f ms; one added %.3f ms (%.2fx), one removed "
               "%.3f ms (%.2fx) (medians; means %.3f, %.3f, %.3f)\n", CHURN_N[k], cmed[k][0],
               cmed[k][1], cmed[k][1] / cmed[k][0], cmed[k][2], cmed[k][2] / cmed[k][0],
               cavg[k][0], cavg[k][1], cavg[k][2]);
    }
    if (churn_only)
        return 0;
    char path[1024];
    snprintf(path, sizeof path, "%s/scale_plan.csv", out);
    FILE *fp = fopen(path, "w");
    snprintf(path, sizeof path, "%s/scale_trace.csv", out);
    FILE *ft = fopen(path, "w");
    if (!fp || !ft) {
        fprintf(stderr, "scale: cannot write into %s\n", out);
        return 1;
    }

    /* plan time against sphere count */
    static const int PLAN_N[] = { 100, 300, 1000, 3000, 10000, 20000, 50000 };
    fprintf(fp, "spheres,views,plan_ms,moving_ms,brute_ms\n");
    for (size_t k = 0; k < sizeof PLAN_N / sizeof PLAN_N[0]; k++) {
        int n = PLAN_N[k];
        hall h = hall_open(n, false);
        double t = plan_median(&h, 31, 0), moving = plan_median(&h, 31, n / 100);
        int views = limen_plan_count(h.p);
        hall_close(&h);
        double brute = NAN;
        if (n <= 10000) {
            hall b = hall_open(n, true);
            brute = plan_median(&b, n <= 1000 ? 11 : 3, 0);
            hall_close(&b);
        }
        fprintf(fp, "%d,%d,%.4f,%.4f,%.4f\n", n, views, t, moving, brute);
        fprintf(stderr, "plan  %6d spheres: %4d views, %8.3f ms (1%% moving %8.3f ms), without "
                "the index %9.3f ms\n", n, views, t, moving, brute);
    }

    /* trace time against sphere count */
    static const int TRACE_N[] = { 200, 600, 2000, 6000, 20000 };
    unsigned char *rgb = malloc((size_t)TRACE_W * TRACE_H * 3);
    fprintf(ft, "spheres,trace_ms,brute_ms\n");
    for (size_t k = 0; k < sizeof TRACE_N / sizeof TRACE_N[0]; k++) {
        int n = TRACE_N[k];
        limen_scene *s = field_create(n, 11);
        if (!s)
            fail("field", NULL);
        double t[5];
        for (int i = 0; i < 5; i++)
            t[i] = trace_once(s, rgb);
        double indexed = median(t, 5);
        double brute = NAN;
        if (n <= 6000) {
            s->brute_force = true;
            for (int i = 0; i < 3; i++)
                t[i] = trace_once(s, rgb);
            brute = median(t, 3);
        }
        limen_scene_destroy(s);
        fprintf(ft, "%d,%.3f,%.3f\n", n, indexed, brute);
        fprintf(stderr, "trace %6d spheres: %8.2f ms, without the index %9.2f ms (%dx%d)\n", n,
                indexed, brute, TRACE_W, TRACE_H);
    }
    fclose(fp);
    fclose(ft);

    /* the targets, interleaved */
    enum { PLAN_REPS = 41, TRACE_REPS = 7 };
    hall small = hall_open(1000, false), big = hall_open(10000, false);
    double ts[PLAN_REPS], tb[PLAN_REPS];
    for (int i = 0; i < PLAN_REPS; i++) {
        ts[i] = plan_once(&small, 0, i);
        tb[i] = plan_once(&big, 0, i);
    }
    double plan_small = median(ts, PLAN_REPS), plan_big = median(tb, PLAN_REPS);
    hall_close(&small);
    hall_close(&big);
    limen_scene *f200 = field_create(200, 11), *f20k = field_create(20000, 11);
    if (!f200 || !f20k)
        fail("field", NULL);
    double a[TRACE_REPS], b[TRACE_REPS];
    for (int i = 0; i < TRACE_REPS; i++) {
        a[i] = trace_once(f200, rgb);
        b[i] = trace_once(f20k, rgb);
    }
    double tr_small = median(a, TRACE_REPS), tr_big = median(b, TRACE_REPS);
    limen_scene_destroy(f200);
    limen_scene_destroy(f20k);
    free(rgb);

    for (int k = 0; k < 2; k++) {
        churn_measure(CHURN_N[k], CHURN_FRAMES, cmed[k], cavg[k]);
        fprintf(stderr, "churn %6d spheres: unchanged %.3f ms, one added %.3f ms, one removed "
                "%.3f ms (medians; means %.3f, %.3f, %.3f)\n", CHURN_N[k], cmed[k][0],
                cmed[k][1], cmed[k][2], cavg[k][0], cavg[k][1], cavg[k][2]);
    }

    snprintf(path, sizeof path, "%s/scale_targets.txt", out);
    FILE *fo = fopen(path, "w");
    if (!fo) {
        fprintf(stderr, "scale: cannot write %s\n", path);
        return 1;
    }
    double plan_ratio = plan_big / plan_small, trace_ratio = tr_big / tr_small;
    fprintf(fo, "scale: hall of 10,000 spheres, %d portal pairs: one plan %.3f ms (target <= 2 "
            "ms): %s\n", PAIRS, plan_big, plan_big <= 2.0 ? "met" : "NOT met");
    fprintf(fo, "scale: that plan against the hall of 1,000 (%.3f ms): %.2fx (target <= 10x): "
            "%s\n", plan_small, plan_ratio, plan_ratio <= 10.0 ? "met" : "NOT met");
    fprintf(fo, "scale: trace of 20,000 spheres %.1f ms against 200 %.1f ms (%dx%d): %.2fx "
            "(target <= 4x): %s\n", tr_big, tr_small, TRACE_W, TRACE_H, trace_ratio,
            trace_ratio <= 4.0 ? "met" : "NOT met");
    for (int k = 0; k < 2; k++) {
        double add = cmed[k][1] / cmed[k][0], del = cmed[k][2] / cmed[k][0];
        fprintf(fo, "scale: churn at %d spheres: a frame with one sphere added %.2fx, one "
                "removed %.2fx the unchanged frame (%.3f ms; means with the rebuilds %.2fx, "
                "%.2fx)", CHURN_N[k], add, del, cmed[k][0], cavg[k][1] / cavg[k][0],
                cavg[k][2] / cavg[k][0]);
        if (CHURN_N[k] == 10000)
            fprintf(fo, " (target: added <= 1.5x): %s", add <= 1.5 ? "met" : "NOT met");
        fputc('\n', fo);
    }
    fclose(fo);
    return 0;
}
