/* trace_cmd.c - `limen trace`: the ray-traced reference image of a scene. */
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"

static const char *const synopsis = "limen trace SCENE.lua -o REF.png [options]";

static const limen_cli_option trace_options[] = {
    { "--threads N", "worker threads (default: one per online CPU)" },
    { "--samples N", "rays per pixel, averaged (a box filter): 1 (default) the centre, 4 the\n"
                     "standard 4x MSAA positions (compare with render --msaa 4), 9, 16,\n"
                     "25, ... a grid" },
    { "--lod PIXELS", "trace each mesh at the level of detail `render --lod PIXELS` draws it\n"
                      "at in the camera's view (PIXELS > 0); full (default): the full mesh" },
    { "--lod-level K", "trace every mesh at its level of detail K (its coarsest where it\n"
                       "has fewer; 0: as --lod says)" },
    { "--stats", "one JSON line per frame: frame, time, ms, pixels" },
    { NULL, NULL }
};

static void usage(FILE *f)
{
    limen_cli_run_usage(f, synopsis, "trace options", trace_options);
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* --lod PIXELS|full and --lod-level K at argv[*i]; 0 or the exit status. */
static int parse_lod(int argc, char **argv, int *i, limen_trace_desc *d)
{
    const char *a = argv[*i];
    if (*i + 1 >= argc)
        return limen_cli_fail(2, "option %s needs a value", a);
    const char *v = argv[++*i];
    double x;
    long n;
    if (!strcmp(a, "--lod-level")) {
        if (limen_cli_parse_long(v, 0, 255, &n))
            return limen_cli_fail(2, "--lod-level: expected 0 to 255, got '%s'", v);
        d->lod_level = (int)n;
    } else if (!strcmp(v, "full")) {
        d->lod_pixels = 0;
    } else if (limen_cli_parse_double(v, &x) || !(x > 0)) {
        return limen_cli_fail(2, "--lod: expected a number of pixels > 0 or 'full', got '%s'", v);
    } else {
        d->lod_pixels = (float)x;
    }
    return 0;
}

static int parse(int argc, char **argv, limen_cli_run *o, limen_trace_desc *d)
{
    limen_cli_run_init(o);
    for (int i = 0; i < argc; i++) {
        int r = limen_cli_run_option(argc, argv, &i, o);
        if (r == 2)
            return 2;
        if (r == 1)
            continue;
        long n;
        if (!strcmp(argv[i], "--lod") || !strcmp(argv[i], "--lod-level")) {
            if ((r = parse_lod(argc, argv, &i, d)))
                return r;
            continue;
        }
        bool threads = !strcmp(argv[i], "--threads");
        if (!threads && strcmp(argv[i], "--samples"))
            return limen_cli_fail(2, "unknown option '%s'", argv[i]);
        if (i + 1 >= argc)
            return limen_cli_fail(2, "option %s needs a value", argv[i]);
        const char *a = argv[i++];
        bool bad = limen_cli_parse_long(argv[i], 1, 256, &n) != 0;
        long k = bad ? 0 : lround(sqrt((double)n));
        if (bad || (!threads && n != 4 && k * k != n))
            return limen_cli_fail(2, "%s: expected %s, got '%s'", a,
                                  threads ? "1 to 256" : "1, 4, 9, 16, ... (a square) up to 256",
                                  argv[i]);
        if (threads)
            d->threads = (int)n;
        else
            d->samples = (int)n;
    }
    return 0;
}

int limen_cli_trace(int argc, char **argv)
{
    limen_cli_run o;
    limen_trace_desc d = { 0 };
    if (argc == 0) {
        usage(stderr);
        return 2;
    }
    int rc = parse(argc, argv, &o, &d);
    if (rc)
        return rc;
    if (o.help) {
        usage(stdout);
        return 0;
    }
    if ((rc = limen_cli_run_check(&o, "trace")))
        return rc;
    d.width = o.width;
    d.height = o.height;
    d.limits = o.limits;
    d = limen_trace_desc_defaults(&d);      /* the image size, for the buffer below */

    limen_script *sc = limen_cli_load(&o);
    if (!sc)
        return 1;
    limen_scene *s = limen_script_scene(sc);
    unsigned char *rgb = malloc((size_t)d.width * (size_t)d.height * 3);
    if (!rgb)
        rc = limen_cli_fail(1, "out of memory for a %dx%d image", d.width, d.height);
    char path[PATH_MAX];
    for (long f = 0; f < o.frames && !rc; f++) {
        double t = o.time + (double)f / o.fps;
        if ((rc = limen_cli_update(sc, &o, f, t, 0)))
            break;
        if (limen_cli_pose_apply(s, &o.pose)) {
            rc = 1;
            break;
        }
        double t0 = now_ms();
        limen_status st = limen_trace_image(s, &d, rgb);
        if (st) {
            limen_cli_scene_error(o.scene, limen_scene_error(s)[0] ? limen_scene_error(s)
                                                                   : limen_status_string(st));
            rc = 1;
            break;
        }
        double ms = now_ms() - t0;
        if (limen_cli_frame_path(o.out, f, o.frames, path, sizeof path)) {
            rc = limen_cli_fail(1, "-o: the path is too long");
            break;
        }
        if (limen_cli_write_image(path, d.width, d.height, rgb))
            rc = limen_cli_fail(1, "cannot write '%s'", path);
        else if (o.stats)
            printf("{\"frame\": %ld, \"time\": %.6g, \"ms\": %.3f, \"pixels\": %ld}\n", f, t, ms,
                   (long)d.width * d.height);
    }
    free(rgb);
    limen_script_destroy(sc);
    return rc;
}
