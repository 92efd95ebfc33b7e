/* main.c - the limen program: parse arguments, run a scene script, render, write files. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "limen.h"

static const char *const render_synopsis =
    "limen render SCENE.lua -o OUT.png [options]";

static const limen_cli_option render_options[] = {
    { "--backend osmesa|egl", "OpenGL context (default osmesa)" },
    { "--method M", "how views nest: stencil (default), texture, or naive (the baseline\n"
                    "of common engines, without culling or scissors, for comparison)" },
    { "--clip oblique|plane|none", "how a view cuts what is behind its surface (default\n"
                                   "oblique, with the plane where oblique cannot)" },
    { "--max-views N", "view budget (default 1024)" },
    { "--lod PIXELS", "draw each mesh at the coarsest level of detail whose error covers at\n"
                      "most PIXELS pixels in a view (default 0.125); full: always the full mesh" },
    { "--adaptive T", "stop recursion where no pixel could change by more than T\n"
                      "(8-bit steps; mirror tints decide)" },
    { "--fill color|previous", "where recursion stops: the surface's fill colour\n"
                               "(default), or its picture from the previous frame" },
    { "--texture-scale S", "texture method: resolution of nested views, 0 < S <= 1" },
    { "--msaa N", "samples per pixel (default off)" },
    { "--depth-bits 24|32", "depth buffer: 24-bit integer or 32-bit float" },
    { "--depth-mode MODE", "clip-space depth convention: no (default), zo, zo-reversed" },
    { "--plan PLAN.json", "write the view tree of the (last) frame: views, the surfaces\n"
                          "each sees, and the shapes cloned through portals" },
    { "--stats", "one JSON line per frame: frame, time, ms, views, truncated (views\n"
                 "the limits and the frame budget left out), fragments,\n"
                 "samples, pixels, draw_calls, triangles (meshes at their levels\n"
                 "of detail), and warm_up: true for the run's first frame, whose\n"
                 "ms includes one-time work (shader compilation, buffers); take ms\n"
                 "from later frames (--frames) for a steady figure" },
    { NULL, NULL }
};

static const char *const diff_synopsis =
    "limen diff A.png B.png [--threshold N] [--heatmap H.png] [--json] [--max-bad SHARE]";

static const limen_cli_option diff_options[] = {
    { "--threshold N", "a pixel differs where its largest channel differs by more\n"
                       "than N (0 to 255, default 8)" },
    { "--heatmap H.png", "draw where: A in dim grey, pixels over the threshold red to yellow" },
    { "--json", "one JSON line instead of a sentence" },
    { "--max-bad SHARE", "exit 1 if more than SHARE (0 to 1) of the pixels differ" },
    { "-h, --help", "print this and exit" },
    { NULL, NULL }
};

static void render_usage(FILE *f)
{
    limen_cli_run_usage(f, render_synopsis, "render options", render_options);
}

static void diff_usage(FILE *f)
{
    limen_cli_usage(f, diff_synopsis, (const char *const[]){ "options", NULL },
                    (const limen_cli_option *const[]){ diff_options, NULL });
}

static const char *const usage =
    "usage: limen render SCENE.lua -o OUT.png [options]   draw a scene with OpenGL\n"
    "       limen trace SCENE.lua -o REF.png [options]    ray trace its reference image\n"
    "       limen diff A.png B.png [options]              compare two images\n"
    "       limen view SCENE.lua [options] [--shots DIR]  a window to walk through\n"
    "       limen --version\n"
    "`limen COMMAND --help` lists a command's options.\n";

void limen_cli_scene_error(const char *scene, const char *msg)
{
    size_t n = strlen(scene);
    if (strncmp(msg, scene, n) == 0 && msg[n] == ':')
        fprintf(stderr, "limen: %s\n", msg);
    else
        fprintf(stderr, "limen: %s: %s\n", scene, msg);
}

typedef struct options {
    limen_cli_run run;
    const char *plan;
    limen_renderer_desc rd;
    limen_render_opts ro;
} options;

int limen_cli_parse_long(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int limen_cli_parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || v != v || v - v != 0)
        return -1;
    *out = v;
    return 0;
}

int limen_cli_parse_size(const char *s, int *w, int *h)
{
    /* strtol with range checks, not sscanf's %d, whose overflow is undefined (glibc wraps
     * 4294967297 to 1) */
    char *x_end, *end;
    errno = 0;
    long x = strtol(s, &x_end, 10);
    if (errno || x_end == s || *x_end != 'x' || x_end[1] == '-' || x_end[1] == '+')
        return -1;
    long y = strtol(x_end + 1, &end, 10);
    if (errno || end == x_end + 1 || *end || x < 1 || y < 1 || x > 16384 || y > 16384)
        return -1;
    *w = (int)x, *h = (int)y;
    return 0;
}

/* Options whose value is one of a few names, in the order of their enum's values. */
enum { C_BACKEND, C_DEPTH_MODE, C_METHOD, C_FILL, C_CLIP, C_COUNT };
static const struct {
    const char *option;
    const char *const names[4];
} choices[C_COUNT] = {
    [C_BACKEND] = { "--backend", { "osmesa", "egl" } },
    [C_DEPTH_MODE] = { "--depth-mode", { "no", "zo", "zo-reversed" } },
    [C_METHOD] = { "--method", { "stencil", "texture", "naive" } },
    [C_FILL] = { "--fill", { "color", "previous" } },
    [C_CLIP] = { "--clip", { "oblique", "plane", "none" } },
};

/* Sets the choice option c to value v; 2 after a usage error ("expected a, b or c"). */
static int set_choice(int c, const char *v, options *o)
{
    const char *const *names = choices[c].names;
    int k = 0;
    while (k < 4 && names[k] && strcmp(v, names[k]))
        k++;
    if (k == 4 || !names[k]) {
        char list[96] = "";
        for (int i = 0; i < 4 && names[i]; i++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                     i == 0 ? "" : i + 1 < 4 && names[i + 1] ? ", " : " or ", names[i]);
        return limen_cli_fail(2, "%s: expected %s, got '%s'", choices[c].option, list, v);
    }
    switch (c) {
    case C_BACKEND: o->rd.backend = (limen_backend)k; break;
    case C_DEPTH_MODE: o->rd.depth_range = (limen_depth_range)k; break;
    case C_METHOD: o->ro.method = (limen_method)k; break;
    case C_FILL: o->ro.fill = (limen_fill)k; break;
    default: o->ro.limits.clip = (limen_clip_method)k; break;
    }
    return 1;
}

/* Parses one render-only option a with value v (NULL if none follows); returns 1 if it
 * took v, 2 after a usage error. */
static int render_option(const char *a, const char *v, options *o)
{
    static const char *const numeric[] = { "--plan", "--msaa", "--adaptive", "--depth-bits",
                                           "--texture-scale", "--max-views", "--lod", NULL };
    int known = 0;
    for (int i = 0; numeric[i]; i++)
        known |= !strcmp(a, numeric[i]);
    for (int c = 0; c < C_COUNT; c++)
        known |= !strcmp(a, choices[c].option);
    if (!known)
        return limen_cli_fail(2, "unknown option '%s'", a);
    if (!v)
        return limen_cli_fail(2, "option %s needs a value", a);
    for (int c = 0; c < C_COUNT; c++)
        if (!strcmp(a, choices[c].option))
            return set_choice(c, v, o);
    long n;
    double x;
    if (!strcmp(a, "--plan")) {
        o->plan = v;
    } else if (!strcmp(a, "--msaa")) {
        if (limen_cli_parse_long(v, 0, 64, &n))
            return limen_cli_fail(2, "--msaa: expected 0 to 64, got '%s'", v);
        o->rd.msaa = (int)n;
    } else if (!strcmp(a, "--adaptive")) {
        if (limen_cli_parse_double(v, &x) || !(x >= 0 && x <= 255))
            return limen_cli_fail(2, "--adaptive: expected a threshold in 8-bit steps (0 to "
                                     "255), got '%s'", v);
        o->ro.limits.adaptive = (float)(x / 255.0);
    } else if (!strcmp(a, "--depth-bits")) {
        if (limen_cli_parse_long(v, 24, 32, &n) || (n != 24 && n != 32))
            return limen_cli_fail(2, "--depth-bits: expected 24 or 32, got '%s'", v);
        o->rd.depth_bits = (int)n;
    } else if (!strcmp(a, "--texture-scale")) {
        if (limen_cli_parse_double(v, &x) || !(x > 0 && x <= 1))
            return limen_cli_fail(2, "--texture-scale: expected 0 < S <= 1, got '%s'", v);
        o->ro.texture_scale = (float)x;
    } else if (!strcmp(a, "--max-views")) {
        if (limen_cli_parse_long(v, 1, 1000000, &n))
            return limen_cli_fail(2, "--max-views: expected 1 to 1000000, got '%s'", v);
        o->ro.limits.max_views = (int)n;
    } else if (!strcmp(a, "--lod")) {
        if (!strcmp(v, "full"))
            o->ro.limits.lod_pixels = LIMEN_LOD_FULL;
        else if (limen_cli_parse_double(v, &x) || !(x >= 0))
            return limen_cli_fail(2, "--lod: expected a number of pixels >= 0 or 'full', got "
                                     "'%s'", v);
        else
            o->ro.limits.lod_pixels = (float)x;
    }
    return 1;
}

/* Returns 0 to go on, or the exit status (0 after --help). need_out: render's -o. */
static int parse_render(int argc, char **argv, options *o, int *done, int need_out)
{
    memset(o, 0, sizeof *o);
    limen_cli_run_init(&o->run);
    for (int i = 0; i < argc; i++) {
        int r = limen_cli_run_option(argc, argv, &i, &o->run);
        if (r == 0) {
            r = render_option(argv[i], i + 1 < argc ? argv[i + 1] : NULL, o);
            i += r == 1;
        }
        if (r == 2)
            return 2;
    }
    if (o->run.help) {
        render_usage(stdout);
        *done = 1;
        return 0;
    }
    o->rd.width = o->run.width;
    o->rd.height = o->run.height;
    o->ro.limits.depth_rule = o->run.limits.depth_rule;
    o->ro.limits.depth = o->run.limits.depth;
    if (!need_out) {
        if (limen_cli_pose_check(&o->run.pose))
            return 2;
        return o->run.scene ? 0 : limen_cli_fail(2, "view: no scene script given");
    }
    return limen_cli_run_check(&o->run, "render");
}

int limen_cli_render_options(int argc, char **argv, const char **scene,
                             limen_renderer_desc *rd, limen_render_opts *ro,
                             limen_script_desc *sd, limen_cli_pose *pose)
{
    options o;
    int done = 0, rc = parse_render(argc, argv, &o, &done, 0);
    if (rc || done)
        return done ? 1 : rc;
    if (o.run.out || o.plan || o.run.stats || o.run.frames != 1)
        return limen_cli_fail(2, "view: -o, --frames, --plan and --stats are render's options");
    *scene = o.run.scene;
    *rd = o.rd;
    *ro = o.ro;
    limen_cli_script_desc(&o.run, sd);
    *pose = o.run.pose;
    return 0;
}

static int cmd_render(int argc, char **argv)
{
    options o;
    int done = 0, rc = parse_render(argc, argv, &o, &done, 1);
    if (rc || done)
        return rc;
    limen_script *sc = limen_cli_load(&o.run);
    if (!sc)
        return 1;
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(&o.rd, &r);
    if (st) {
        limen_cli_fail(1, "%s", r ? limen_renderer_error(r) : limen_status_string(st));
        limen_renderer_destroy(r);
        limen_script_destroy(sc);
        return 1;
    }
    int w, h;
    limen_renderer_get_size(r, &w, &h);
    unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
    if (!rgb)
        rc = limen_cli_fail(1, "out of memory for a %dx%d image", w, h);
    int tty = isatty(2);
    long frames = o.run.frames;
    char path[PATH_MAX];
    for (long f = 0; f < frames && !rc; f++) {
        double t = o.run.time + (double)f / o.run.fps;
        limen_frame_stats stats;
        if ((rc = limen_cli_update(sc, &o.run, f, t, tty && f)))
            break;
        if (limen_cli_pose_apply(limen_script_scene(sc), &o.run.pose)) {
            rc = 1;
            break;
        }
        st = limen_render_frame(r, limen_script_scene(sc), &o.ro, &stats);
        if (st) {
            if (tty && f)
                fputc('\n', stderr);
            limen_cli_scene_error(o.run.scene, limen_renderer_error(r));
            rc = 1;
            break;
        }
        if (limen_cli_frame_path(o.run.out, f, frames, path, sizeof path)) {
            rc = limen_cli_fail(1, "%s-o: the path is too long", tty && f ? "\n" : "");
            break;
        }
        /* a failed read of the pixels is the renderer's, not the file's */
        if ((st = limen_renderer_read_rgb(r, rgb))) {
            rc = limen_cli_fail(1, "%scannot read the frame back: %s", tty && f ? "\n" : "",
                                limen_renderer_error(r)[0] ? limen_renderer_error(r)
                                                           : limen_status_string(st));
            break;
        }
        if (limen_cli_write_image(path, w, h, rgb)) {
            rc = limen_cli_fail(1, "%scannot write '%s'", tty && f ? "\n" : "", path);
            break;
        }
        if (o.run.stats)
            printf("{\"frame\": %ld, \"time\": %.6g, \"ms\": %.3f, \"warm_up\": %s, "
                   "\"views\": %d, \"truncated\": %d, \"fragments\": %llu, \"samples\": %llu, "
                   "\"pixels\": %llu, \"draw_calls\": %d, \"triangles\": %llu}\n",
                   f, t, stats.ms, f ? "false" : "true", stats.views, stats.truncated,
                   (unsigned long long)stats.fragments, (unsigned long long)stats.samples,
                   (unsigned long long)stats.pixels, stats.draw_calls,
                   (unsigned long long)stats.triangles);
        if (frames > 1 && tty)
            fprintf(stderr, "\rlimen: frame %ld/%ld", f + 1, frames);
    }
    if (frames > 1 && tty)
        fputc('\n', stderr);
    if (!rc && o.plan &&
        limen_plan_write_json(limen_renderer_plan(r), limen_script_scene(sc), o.plan))
        rc = limen_cli_fail(1, "cannot write '%s'", o.plan);
    if (!rc && frames > 1 && !limen_cli_frame_path(o.run.out, 0, frames, path, sizeof path)) {
        fprintf(stderr, "limen: wrote %ld frames to %s\n", frames, path);
    }
    free(rgb);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
    return rc;
}

static int cmd_diff(int argc, char **argv)
{
    const char *a = NULL, *b = NULL, *heat = NULL;
    long threshold = 8;
    int json = 0;
    double max_bad = -1;
    for (int i = 0; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            diff_usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--heatmap") && v) {
            heat = v;
            i++;
        } else if (!strcmp(argv[i], "--threshold") && v) {
            if (limen_cli_parse_long(v, 0, 255, &threshold))
                return limen_cli_fail(2, "--threshold: expected 0 to 255, got '%s'", v);
            i++;
        } else if (!strcmp(argv[i], "--max-bad") && v) {
            if (limen_cli_parse_double(v, &max_bad) || max_bad < 0 || max_bad > 1)
                return limen_cli_fail(2, "--max-bad: expected 0 to 1, got '%s'", v);
            i++;
        } else if (!strcmp(argv[i], "--json")) {
            json = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return limen_cli_fail(2, "diff: unknown option or missing value '%s'", argv[i]);
        } else if (!a) {
            a = argv[i];
        } else if (!b) {
            b = argv[i];
        } else {
            return limen_cli_fail(2, "diff: unexpected argument '%s'", argv[i]);
        }
    }
    if (!a || !b)
        return limen_cli_fail(2, "diff: needs two images");
    int wa, ha, wb, hb;
    unsigned char *pa = NULL, *pb = NULL, *ph = NULL;
    static const char too_big[] = ": more pixels than limen reads (LIMEN_IMAGE_MAX_PIXELS)";
    limen_status ra = limen_read_png(a, &wa, &ha, &pa);
    if (ra)
        return limen_cli_fail(1, "cannot read '%s'%s", a, ra == LIMEN_ERR_ARG ? too_big : "");
    limen_status rb = limen_read_png(b, &wb, &hb, &pb);
    if (rb) {
        limen_free(pa);
        return limen_cli_fail(1, "cannot read '%s'%s", b, rb == LIMEN_ERR_ARG ? too_big : "");
    }
    int rc = 0;
    limen_diff d;
    if (wa != wb || ha != hb) {
        rc = limen_cli_fail(1, "diff: sizes differ (%dx%d against %dx%d)", wa, ha, wb, hb);
    } else {
        if (heat && !(ph = malloc((size_t)wa * (size_t)ha * 3)))
            rc = limen_cli_fail(1, "out of memory");
        if (!rc)
            limen_image_diff(pa, pb, wa, ha, (int)threshold, &d, ph);
        if (!rc && heat && limen_write_png(heat, wa, ha, ph))
            rc = limen_cli_fail(1, "cannot write '%s'", heat);
        if (!rc) {
            if (json)
                printf("{\"bad_share\": %.6f, \"bad_pixels\": %ld, \"pixels\": %ld, "
                       "\"psnr\": %.3f, \"max_delta\": %d, \"threshold\": %ld}\n",
                       d.bad_share, d.bad_pixels, (long)wa * ha,
                       isinf(d.psnr) ? 999.0 : d.psnr, d.max_delta, threshold);
            else
                printf("%.4f%% of pixels differ by more than %ld (%ld of %ld), PSNR %.2f dB, "
                       "largest difference %d\n",
                       100.0 * d.bad_share, threshold, d.bad_pixels, (long)wa * ha,
                       isinf(d.psnr) ? 999.0 : d.psnr, d.max_delta);
            if (max_bad >= 0 && d.bad_share > max_bad)
                rc = 1;
        }
    }
    free(ph);
    limen_free(pa);
    limen_free(pb);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
        fputs(usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    if (!strcmp(argv[1], "render")) {
        if (argc == 2) {
            render_usage(stderr);
            return 2;
        }
        return cmd_render(argc - 2, argv + 2);
    }
    if (!strcmp(argv[1], "diff"))
        return cmd_diff(argc - 2, argv + 2);
    if (!strcmp(argv[1], "trace"))
        return limen_cli_trace(argc - 2, argv + 2);
    if (!strcmp(argv[1], "view"))
        return limen_cli_view(argc - 2, argv + 2);
    if (!strcmp(argv[1], "--version")) {
        printf("limen %s\n", LIMEN_VERSION);
        return 0;
    }
    fprintf(stderr, "limen: unknown command '%s'\n%s", argv[1], usage);
    return 2;
}
