/* sweep.h - what the stability sweeps (tests/test_sweep_*.c) share: the QUICK / FULL
 * switch, where CSVs and frames go, the ray-traced truth, the error of a frame against it,
 * and the check that a plan holds only finite numbers.
 *
 * Every sweep is a test program: `make test` runs it in QUICK mode (a few steps, asserting
 * the property); with SWEEP_FULL=1 in the environment it runs every step. Either way it
 * writes $LIMEN_BUILD/sweeps/<name>.csv (build/sweeps/ without LIMEN_BUILD) and a few PNG
 * frames of the interesting steps; tests/sweeps/plots.gp turns the CSVs into charts
 * (`make sweeps`).
 *
 * The accuracy bound is the ground-truth tests' (tests/test_truth.c): at most 0.5% of the
 * pixels may differ from the ray tracer by more than 8/255 in some channel.
 */
#ifndef LIMEN_SWEEP_H
#define LIMEN_SWEEP_H

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "../check.h"
#include "core/dmath.h"
#include "limen.h"
#include "../load.h"

#define SWEEP_BOUND 0.005   /* share of pixels over SWEEP_THRESHOLD */
#define SWEEP_THRESHOLD 8   /* 8-bit steps */

#define SWEEP_UNUSED __attribute__((unused))

/* 1 when SWEEP_FULL is set to anything but "" or "0". */
static SWEEP_UNUSED int sweep_full(void)
{
    const char *e = getenv("SWEEP_FULL");
    return e && *e && strcmp(e, "0") != 0;
}

static SWEEP_UNUSED double sweep_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* $LIMEN_BUILD/sweeps (or build/sweeps), created on first use. */
static SWEEP_UNUSED const char *sweep_dir(void)
{
    static char dir[512];
    if (!dir[0]) {
        const char *b = getenv("LIMEN_BUILD");
        snprintf(dir, sizeof dir, "%s", b && *b ? b : "build");
        mkdir(dir, 0777);
        size_t n = strlen(dir);
        snprintf(dir + n, sizeof dir - n, "/sweeps");
        if (mkdir(dir, 0777) != 0 && errno != EEXIST)
            fprintf(stderr, "  cannot create %s\n", dir);
    }
    return dir;
}

/* Path of a file in the sweeps folder: printf-style name. */
static SWEEP_UNUSED const char *sweep_path(char *buf, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static SWEEP_UNUSED const char *sweep_path(char *buf, size_t size, const char *fmt, ...)
{
    int n = snprintf(buf, size, "%s/", sweep_dir());
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + n, size - (size_t)n, fmt, ap);
    va_end(ap);
    return buf;
}

/* Opens <name>.csv for writing and writes its header line (a comment line first, then the
 * column names). */
static SWEEP_UNUSED FILE *sweep_csv(const char *name, const char *comment, const char *columns)
{
    char path[600];
    sweep_path(path, sizeof path, "%s.csv", name);
    FILE *f = fopen(path, "w");
    CHECK_MSG(f != NULL, "cannot write %s", path);
    if (f) {
        fprintf(f, "# %s (%s mode)\n%s\n", comment, sweep_full() ? "full" : "quick", columns);
    }
    return f;
}

/* The ray-traced truth of the scene's camera view (the scene's own depth limits). */
static SWEEP_UNUSED unsigned char *sweep_trace(limen_scene *s, int w, int h)
{
    unsigned char *rgb = malloc((size_t)w * h * 3);
    limen_status st = limen_trace_image(s, &(limen_trace_desc){ .width = w, .height = h }, rgb);
    CHECK_MSG(st == LIMEN_OK, "trace: %s", limen_scene_error(s));
    if (st) {
        free(rgb);
        return NULL;
    }
    return rgb;
}

/* Share of pixels off by more than 8/255; heat (w*h*3, may be NULL) gets the heat map. */
static SWEEP_UNUSED double sweep_diff(const unsigned char *a, const unsigned char *b, int w, int h,
                                      unsigned char *heat)
{
    limen_diff d = { 1.0, 0, 0, 255 };
    if (!a || !b || limen_image_diff(a, b, w, h, SWEEP_THRESHOLD, &d, heat))
        return 1.0;
    return d.bad_share;
}

/* Renders a frame with limen's renderer into rgb (w*h*3); 0 on success. */
static SWEEP_UNUSED int sweep_render(limen_renderer *r, limen_scene *s, limen_render_opts o,
                                     unsigned char *rgb)
{
    limen_status st = limen_render_frame(r, s, &o, NULL);
    CHECK_MSG(st == LIMEN_OK, "render: %s", limen_renderer_error(r));
    if (st)
        return -1;
    st = limen_renderer_read_rgb(r, rgb);
    CHECK_MSG(st == LIMEN_OK, "read: %s", limen_renderer_error(r));
    return st ? -1 : 0;
}

/* Writes panels side by side (each w x h) as one PNG named by fmt. */
static SWEEP_UNUSED void sweep_png(int w, int h, int npanels, const unsigned char *const *panels,
                                   const char *fmt, ...) __attribute__((format(printf, 5, 6)));
static SWEEP_UNUSED void sweep_png(int w, int h, int npanels, const unsigned char *const *panels,
                                   const char *fmt, ...)
{
    char name[256], path[800];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    sweep_path(path, sizeof path, "%s.png", name);
    const int gap = 4, W = npanels * w + (npanels - 1) * gap;
    unsigned char *img = malloc((size_t)W * h * 3);
    memset(img, 255, (size_t)W * h * 3);
    for (int p = 0; p < npanels; p++)
        for (int y = 0; y < h && panels[p]; y++)
            memcpy(img + 3 * ((size_t)y * W + (size_t)p * (w + gap)), panels[p] + 3 * (size_t)y * w,
                   3 * (size_t)w);
    CHECK_MSG(limen_write_png(path, W, h, img) == LIMEN_OK, "cannot write %s", path);
    free(img);
}

static SWEEP_UNUSED int sweep_finite(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

/* Views of the plan with a NaN or an infinity in view, proj, eye, clip plane or tint. */
static SWEEP_UNUSED int sweep_plan_nonfinite(const limen_plan *p)
{
    int bad = 0;
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i);
        bad += !(sweep_finite(v->view, 16) && sweep_finite(v->proj, 16) &&
                 sweep_finite(v->eye, 3) && sweep_finite(v->clip_plane, 4) &&
                 sweep_finite(v->tint, 3));
    }
    return bad;
}

/* A sweep's main: runs its cases and says, on stderr, the mode and how long it took. */
static SWEEP_UNUSED int sweep_main(int argc, char **argv, const check_case *cases)
{
    double t0 = sweep_now_ms();
    int rc = check_run(argc, argv, cases);
    fprintf(stderr, "     (%s mode, %.1f s)\n", sweep_full() ? "full" : "quick",
            (sweep_now_ms() - t0) / 1e3);
    return rc;
}

/* dest = inverse of m (double, column-major, cofactors); 0 if singular. */
static SWEEP_UNUSED int sweep_inv4(const double m[16], double dest[16])
{
    double t[16];
    double det = limen__d_adjugate(m, t);
    if (!isfinite(det) || det == 0)
        return 0;
    for (int i = 0; i < 16; i++)
        dest[i] = t[i] / det;
    return 1;
}

/* The world-space plane c_world in the eye space of view matrix `view` (float), in double:
 * (view^-1)^T c, normalised so |n| = 1. 0 if the view is singular. */
static SWEEP_UNUSED int sweep_plane_to_view(const float view[16], const float c_world[4],
                                            double out[4])
{
    double v[16], inv[16];
    for (int i = 0; i < 16; i++)
        v[i] = view[i];
    if (!sweep_inv4(v, inv))
        return 0;
    for (int j = 0; j < 4; j++)
        out[j] = inv[j * 4] * c_world[0] + inv[j * 4 + 1] * c_world[1] +
                 inv[j * 4 + 2] * c_world[2] + inv[j * 4 + 3] * c_world[3];
    double len = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    if (!(len > 0))
        return 0;
    for (int j = 0; j < 4; j++)
        out[j] /= len;
    return 1;
}

static SWEEP_UNUSED limen_renderer *sweep_renderer(int w, int h, limen_depth_range range, int bits)
{
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(
        &(limen_renderer_desc){ .width = w, .height = h, .depth_range = range, .depth_bits = bits },
        &r);
    CHECK_MSG(st == LIMEN_OK, "renderer: %s", limen_renderer_error(r));
    if (st) {
        limen_renderer_destroy(r);
        return NULL;
    }
    return r;
}

#endif
