/* collide.c - what a sweep costs against what the scene holds: sphere sweeps (radius 0.3,
 * 2 units long, random places and directions) in the hall of tests/hall.h with 100, 1,000
 * and 10,000 spheres. Two halls: one that grows with its spheres (n / 100 portal pairs, so
 * 4 units of hall per 100 spheres: a sweep meets as much at any n), and the fixed hall of
 * bench/scale (50 pairs, 200 units: the spheres crowd in as n grows, and a sweep meets more).
 * The two sizes of each pair are measured interleaved, batch by batch, in one run, so that a
 * shared machine's noise falls on both alike; medians of the batches' processor time, wall
 * time beside it.
 *   - target: a sweep in the growing hall of 10,000 spheres <= 3x one in the hall of 100.
 *
 *   collide [--out DIR]
 *
 * Writes DIR/collide.csv and DIR/collide.txt (the target line); progress on stderr. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../tests/hall.h"
#include "core/internal.h"
#include "limen.h"
#include "timing.h"

enum { BATCH = 2000, REPS = 9, SIZES = 3 };

static const int N[SIZES] = { 100, 1000, 10000 };

static void fail(const char *what, limen_scene *s)
{
    fprintf(stderr, "collide: %s: %s\n", what, s ? limen_scene_error(s) : "out of memory");
    exit(1);
}

typedef struct sweeps {
    float from[BATCH][3], to[BATCH][3];
} sweeps;

/* BATCH random sweeps inside a hall `len` long (8 wide, 4 high, down -z from 0). */
static void make_sweeps(sweeps *w, float len, unsigned long long seed)
{
    hall__rng = seed;
    for (int i = 0; i < BATCH; i++) {
        float p[3] = { (float)(7 * hall__uniform() - 3.5), (float)(0.5 + 3 * hall__uniform()),
                       (float)(-len * hall__uniform()) };
        double d[3] = { hall__uniform() - 0.5, hall__uniform() - 0.5, hall__uniform() - 0.5 };
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++) {
            w->from[i][k] = p[k];
            w->to[i][k] = (float)(p[k] + 2 * d[k] / l);
        }
    }
}

/* Runs the batch; processor and wall milliseconds per sweep; counts the hits. */
static void run_batch(limen_scene *s, const sweeps *w, double *cpu, double *wall, int *hits)
{
    double c0 = cpu_ms(), w0 = now_ms();
    int h = 0;
    for (int i = 0; i < BATCH; i++) {
        limen_sweep_result r;
        if (limen_sweep_sphere(s, w->from[i], w->to[i], 0.3f, NULL, &r))
            fail("sweep", s);
        h += r.hit;
    }
    *cpu = (cpu_ms() - c0) / BATCH;
    *wall = (now_ms() - w0) / BATCH;
    *hits = h;
}

typedef struct point {
    double cpu, wall;
    int hits;
} point;

/* The halls of N[a] and N[b] spheres, interleaved. */
static void measure_pair(int na, int nb, bool grow, point *pa, point *pb)
{
    int pairs_a = grow ? (na / 100 > 0 ? na / 100 : 1) : 50;
    int pairs_b = grow ? (nb / 100 > 0 ? nb / 100 : 1) : 50;
    limen_scene *a = hall_create(na, pairs_a, 7), *b = hall_create(nb, pairs_b, 7);
    if (!a || !b)
        fail("hall", NULL);
    static sweeps wa, wb;
    make_sweeps(&wa, 4.0f * (float)pairs_a, 11);
    make_sweeps(&wb, 4.0f * (float)pairs_b, 11);
    double ca[REPS], cb[REPS], xa[REPS], xb[REPS];
    point dummy;
    run_batch(a, &wa, &dummy.cpu, &dummy.wall, &dummy.hits);     /* warm: the index */
    run_batch(b, &wb, &dummy.cpu, &dummy.wall, &dummy.hits);
    for (int r = 0; r < REPS; r++) {
        run_batch(a, &wa, &ca[r], &xa[r], &pa->hits);
        run_batch(b, &wb, &cb[r], &xb[r], &pb->hits);
    }
    pa->cpu = median(ca, REPS);
    pa->wall = median(xa, REPS);
    pb->cpu = median(cb, REPS);
    pb->wall = median(xb, REPS);
    limen_scene_destroy(a);
    limen_scene_destroy(b);
}

int main(int argc, char **argv)
{
    const char *out = "build/bench";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out = argv[++i];
        } else {
            fprintf(stderr, "usage: collide [--out DIR]\n");
            return 2;
        }
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/collide.csv", out);
    /* written whole or not at all (core/file.c), like everything limen writes */
    limen__out ocsv, otxt;
    if (limen__out_open(&ocsv, path)) {
        fprintf(stderr, "collide: cannot write %s\n", path);
        return 1;
    }
    FILE *csv = ocsv.f;
    fprintf(csv, "hall,spheres,us_cpu_per_sweep,us_wall_per_sweep,hits_per_%d\n", BATCH);
    point grow[SIZES], fixed[SIZES];
    for (int g = 0; g < 2; g++) {
        point *pts = g ? fixed : grow;
        /* 100 against 10,000 (the target), then 1,000 against 10,000 for the curve */
        measure_pair(N[0], N[2], g == 0, &pts[0], &pts[2]);
        point again;
        measure_pair(N[1], N[2], g == 0, &pts[1], &again);
        for (int i = 0; i < SIZES; i++) {
            fprintf(csv, "%s,%d,%.3f,%.3f,%d\n", g ? "fixed" : "growing", N[i],
                    1e3 * pts[i].cpu, 1e3 * pts[i].wall, pts[i].hits);
            fprintf(stderr, "collide: %s hall, %5d spheres: %.2f us a sweep (wall %.2f us), "
                    "%d of %d hit\n", g ? "fixed" : "growing", N[i], 1e3 * pts[i].cpu,
                    1e3 * pts[i].wall, pts[i].hits, BATCH);
        }
    }
    if (limen__out_close(&ocsv)) {
        fprintf(stderr, "collide: cannot write %s\n", path);
        return 1;
    }
    snprintf(path, sizeof path, "%s/collide.txt", out);
    if (limen__out_open(&otxt, path)) {
        fprintf(stderr, "collide: cannot write %s\n", path);
        return 1;
    }
    FILE *fo = otxt.f;
    double ratio = grow[2].cpu / grow[0].cpu, fratio = fixed[2].cpu / fixed[0].cpu;
    fprintf(fo, "collide: a sweep in the hall of 10,000 spheres %.2f us against 100 %.2f us "
            "(processor time; wall %.2f / %.2f us): %.2fx (target <= 3x): %s\n",
            1e3 * grow[2].cpu, 1e3 * grow[0].cpu, 1e3 * grow[2].wall, 1e3 * grow[0].wall, ratio,
            ratio <= 3.0 ? "met" : "NOT met");
    fprintf(fo, "collide: in the fixed hall of bench/scale (10,000 spheres crowded into the "
            "room of 100): %.2f us against %.2f us, %.2fx (%d against %d sweeps of %d hit)\n",
            1e3 * fixed[2].cpu, 1e3 * fixed[0].cpu, fratio, fixed[2].hits, fixed[0].hits,
            BATCH);
    if (limen__out_close(&otxt)) {
        fprintf(stderr, "collide: cannot write %s\n", path);
        return 1;
    }
    return 0;
}
