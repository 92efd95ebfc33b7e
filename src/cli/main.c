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

static const char *usage =
    "usage: limen render SCENE.lua -o OUT.png [options]\n"
    "       limen diff A.png B.png [--threshold N] [--heatmap H.png] [--json]\n"
    "                  [--max-bad SHARE]   exit 1 if more than SHARE (0..1) are over\n"
    "       limen trace SCENE.lua -o REF.png [--size WxH] [--depth N] [--time T]\n"
    "       limen view SCENE.lua [options] [--shots DIR]   a window to walk through\n"
    "options:\n"
    "  --size WxH            image size (default 640x480)\n"
    "  --backend osmesa|egl  OpenGL context (default osmesa)\n"
    "  --msaa N              samples per pixel (default off)\n"
    "  --depth-mode no|zo|zo-reversed   clip-space depth convention (default no)\n"
    "  --time T              scene time in seconds passed to update(t) (default 0)\n"
    "  --frames N --fps F    render N frames from T at F frames per second;\n"
    "                        files are numbered OUT_0000.png, OUT_0001.png, ...\n"
    "  --method stencil|texture|naive   how views nest (default stencil; naive: the\n"
    "                        baseline without culling or scissors, for comparison)\n"
    "  --adaptive T          stop recursion where no pixel could change by more than T\n"
    "                        (8-bit steps; mirror tints decide)\n"
    "  --depth-bits 24|32    depth buffer: 24-bit integer or 32-bit float\n"
    "  --texture-scale S     texture method: resolution of nested views, 0 < S <= 1\n"
    "  --clip oblique|plane|none        how a view cuts what is behind its surface\n"
    "                        (default oblique, with the plane where oblique cannot)\n"
    "  --depth N             recursion limit for every surface (default: their own)\n"
    "  --max-views N         view budget (default 1024)\n"
    "  --fill color|previous where recursion stops: the surface's fill colour\n"
    "                        (default), or its picture from the previous frame\n"
    "  --plan PLAN.json      write the view tree of the (last) frame\n"
    "  --stats               print one JSON line per frame: ms, views, fragments,\n"
    "                        samples, pixels\n"
    "  --trusted             run the script with the full Lua standard library\n"
    "  --eye X,Y,Z --look X,Y,Z [--up X,Y,Z]   place the camera there instead (render,\n"
    "                        trace and view; what view's screenshots print)\n";

void limen_cli_scene_error(const char *scene, const char *msg)
{
    size_t n = strlen(scene);
    if (strncmp(msg, scene, n) == 0 && msg[n] == ':')
        fprintf(stderr, "limen: %s\n", msg);
    else
        fprintf(stderr, "limen: %s: %s\n", scene, msg);
}

/* What a scene script prints goes to stderr, marked as the script's: it cannot pass for the
 * program's own output (stdout), nor for one of its messages. */
static void script_print(void *scene, const char *line)
{
    fprintf(stderr, "limen: %s: print: %s\n", (const char *)scene, line);
}

static int fail(const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "limen: ");
    fprintf(stderr, fmt, a, b);
    fputc('\n', stderr);
    return 1;
}

typedef struct options {
    const char *scene, *out, *plan;
    limen_renderer_desc rd;
    limen_render_opts ro;
    double time, fps;
    long frames;
    int stats, trusted;
    limen_cli_pose pose;
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

static int parse_render(int argc, char **argv, options *o, int need_out)
{
    memset(o, 0, sizeof *o);
    o->frames = 1;
    o->fps = 30;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int pose = limen_cli_pose_option(a, v, &o->pose);
        if (pose) {
            if (pose < 0)
                return 1;
            i++;
            continue;
        }
#define NEED_VALUE()                                                                     \
    do {                                                                                 \
        if (!v)                                                                          \
            return fail("option %s needs a value%s", a, "");                             \
        i++;                                                                             \
    } while (0)
        if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            NEED_VALUE();
            o->out = v;
        } else if (!strcmp(a, "--size")) {
            NEED_VALUE();
            if (limen_cli_parse_size(v, &o->rd.width, &o->rd.height))
                return fail("--size: expected WxH with 1 <= W, H <= 16384, got '%s'%s", v, "");
        } else if (!strcmp(a, "--backend")) {
            NEED_VALUE();
            if (!strcmp(v, "osmesa"))
                o->rd.backend = LIMEN_BACKEND_OSMESA;
            else if (!strcmp(v, "egl"))
                o->rd.backend = LIMEN_BACKEND_EGL;
            else
                return fail("--backend: expected osmesa or egl, got '%s'%s", v, "");
        } else if (!strcmp(a, "--msaa")) {
            NEED_VALUE();
            long n;
            if (limen_cli_parse_long(v, 0, 64, &n))
                return fail("--msaa: expected 0 to 64, got '%s'%s", v, "");
            o->rd.msaa = (int)n;
        } else if (!strcmp(a, "--depth-mode")) {
            NEED_VALUE();
            if (!strcmp(v, "no"))
                o->rd.depth_range = LIMEN_DEPTH_NO;
            else if (!strcmp(v, "zo"))
                o->rd.depth_range = LIMEN_DEPTH_ZO;
            else if (!strcmp(v, "zo-reversed"))
                o->rd.depth_range = LIMEN_DEPTH_ZO_REVERSED;
            else
                return fail("--depth-mode: expected no, zo or zo-reversed, got '%s'%s", v, "");
        } else if (!strcmp(a, "--time")) {
            NEED_VALUE();
            if (limen_cli_parse_double(v, &o->time))
                return fail("--time: expected a number, got '%s'%s", v, "");
        } else if (!strcmp(a, "--frames")) {
            NEED_VALUE();
            if (limen_cli_parse_long(v, 1, 1000000, &o->frames))
                return fail("--frames: expected 1 to 1000000, got '%s'%s", v, "");
        } else if (!strcmp(a, "--fps")) {
            NEED_VALUE();
            if (limen_cli_parse_double(v, &o->fps) || !(o->fps > 0))
                return fail("--fps: expected a positive number, got '%s'%s", v, "");
        } else if (!strcmp(a, "--method")) {
            NEED_VALUE();
            if (!strcmp(v, "stencil"))
                o->ro.method = LIMEN_METHOD_STENCIL;
            else if (!strcmp(v, "texture"))
                o->ro.method = LIMEN_METHOD_TEXTURE;
            else if (!strcmp(v, "naive"))
                o->ro.method = LIMEN_METHOD_NAIVE;
            else
                return fail("--method: expected stencil, texture or naive, got '%s'%s", v, "");
        } else if (!strcmp(a, "--adaptive")) {
            NEED_VALUE();
            double t;
            if (limen_cli_parse_double(v, &t) || !(t >= 0 && t <= 255))
                return fail("--adaptive: expected a threshold in 8-bit steps (0 to 255), got "
                            "'%s'%s", v, "");
            o->ro.adaptive = (float)(t / 255.0);
        } else if (!strcmp(a, "--depth-bits")) {
            NEED_VALUE();
            long n;
            if (limen_cli_parse_long(v, 24, 32, &n) || (n != 24 && n != 32))
                return fail("--depth-bits: expected 24 or 32, got '%s'%s", v, "");
            o->rd.depth_bits = (int)n;
        } else if (!strcmp(a, "--fill")) {
            NEED_VALUE();
            if (!strcmp(v, "color"))
                o->ro.fill = LIMEN_FILL_COLOR;
            else if (!strcmp(v, "previous"))
                o->ro.fill = LIMEN_FILL_PREVIOUS;
            else
                return fail("--fill: expected color or previous, got '%s'%s", v, "");
        } else if (!strcmp(a, "--texture-scale")) {
            NEED_VALUE();
            double sc;
            if (limen_cli_parse_double(v, &sc) || !(sc > 0 && sc <= 1))
                return fail("--texture-scale: expected 0 < S <= 1, got '%s'%s", v, "");
            o->ro.texture_scale = (float)sc;
        } else if (!strcmp(a, "--clip")) {
            NEED_VALUE();
            if (!strcmp(v, "oblique"))
                o->ro.clip = LIMEN_CLIP_OBLIQUE;
            else if (!strcmp(v, "plane"))
                o->ro.clip = LIMEN_CLIP_PLANE;
            else if (!strcmp(v, "none"))
                o->ro.clip = LIMEN_CLIP_NONE;
            else
                return fail("--clip: expected oblique, plane or none, got '%s'%s", v, "");
        } else if (!strcmp(a, "--depth")) {
            NEED_VALUE();
            long n;
            if (limen_cli_parse_long(v, 0, 255, &n))
                return fail("--depth: expected 0 to 255, got '%s'%s", v, "");
            o->ro.limit_depth = 1;
            o->ro.max_depth = (int)n;
        } else if (!strcmp(a, "--max-views")) {
            NEED_VALUE();
            long n;
            if (limen_cli_parse_long(v, 1, 1000000, &n))
                return fail("--max-views: expected 1 to 1000000, got '%s'%s", v, "");
            o->ro.max_views = (int)n;
        } else if (!strcmp(a, "--plan")) {
            NEED_VALUE();
            o->plan = v;
        } else if (!strcmp(a, "--stats")) {
            o->stats = 1;
        } else if (!strcmp(a, "--trusted")) {
            o->trusted = 1;
        } else if (a[0] == '-' && a[1]) {
            return fail("unknown option '%s'%s", a, "");
        } else if (!o->scene) {
            o->scene = a;
        } else {
            return fail("unexpected argument '%s'%s", a, "");
        }
#undef NEED_VALUE
    }
    if (!o->scene)
        return fail("render: no scene script given%s%s", "", "");
    if (!o->out && need_out)
        return fail("render: no output given (-o OUT.png)%s%s", "", "");
    return limen_cli_pose_check(&o->pose) ? 1 : 0;
}

int limen_cli_render_options(int argc, char **argv, const char **scene,
                             limen_renderer_desc *rd, limen_render_opts *ro, int *trusted,
                             limen_cli_pose *pose)
{
    options o;
    if (parse_render(argc, argv, &o, 0))
        return 2;
    if (o.out || o.plan || o.stats || o.frames != 1)
        return fail("view: -o, --frames, --plan and --stats are render's options%s%s", "", ""),
               2;
    *scene = o.scene;
    *rd = o.rd;
    *ro = o.ro;
    *trusted = o.trusted;
    *pose = o.pose;
    return 0;
}

/* OUT.png -> OUT_0007.png for frame 7 of a sequence. */
/* The file of frame `frame`; -1 if its name does not fit in buf (never a truncated name,
 * which would write every frame to one file). */
static int frame_path(const char *out, long frame, long frames, char *buf, size_t size)
{
    int n;
    if (frames == 1) {
        n = snprintf(buf, size, "%s", out);
    } else {
        const char *dot = strrchr(out, '.');
        const char *slash = strrchr(out, '/');
        size_t len = strlen(out);
        size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - out) : len;
        if (stem > (size_t)INT_MAX)
            return -1;
        n = snprintf(buf, size, "%.*s_%04ld%s", (int)stem, out, frame,
                     dot && stem < len ? dot : ".png");
    }
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

static int cmd_render(int argc, char **argv)
{
    options o;
    if (parse_render(argc, argv, &o, 1))
        return 2;
    limen_script *sc = NULL;
    limen_status st = limen_script_load(o.scene, &(limen_script_desc){
        .trusted = o.trusted, .print = script_print, .print_user = (void *)o.scene }, &sc);
    if (st) {
        fprintf(stderr, "limen: %s\n", sc ? limen_script_error(sc) : limen_status_string(st));
        limen_script_destroy(sc);
        return 1;
    }
    limen_renderer *r = NULL;
    st = limen_renderer_create(&o.rd, &r);
    if (st) {
        fprintf(stderr, "limen: %s\n", r ? limen_renderer_error(r) : limen_status_string(st));
        limen_renderer_destroy(r);
        limen_script_destroy(sc);
        return 1;
    }
    int tty = isatty(2);
    int rc = 0;
    char path[PATH_MAX];
    for (long f = 0; f < o.frames && !rc; f++) {
        double t = o.time + (double)f / o.fps;
        limen_frame_stats stats;
        if (limen_script_animated(sc) && limen_script_update(sc, t)) {
            fprintf(stderr, "%slimen: %s\n", tty && f ? "\n" : "", limen_script_error(sc));
            rc = 1;
            break;
        }
        if (limen_cli_pose_apply(limen_script_scene(sc), &o.pose)) {
            rc = 1;
            break;
        }
        st = limen_render_frame(r, limen_script_scene(sc), &o.ro, &stats);
        if (st) {
            if (tty && f)
                fputc('\n', stderr);
            limen_cli_scene_error(o.scene, limen_renderer_error(r));
            rc = 1;
            break;
        }
        if (frame_path(o.out, f, o.frames, path, sizeof path)) {
            fprintf(stderr, "%slimen: -o: the path is too long\n", tty && f ? "\n" : "");
            rc = 1;
            break;
        }
        st = limen_renderer_write_png(r, path);
        if (st) {
            fprintf(stderr, "%slimen: %s\n", tty && f ? "\n" : "", limen_renderer_error(r));
            rc = 1;
            break;
        }
        if (o.stats)
            printf("{\"frame\": %ld, \"time\": %.6g, \"ms\": %.3f, \"views\": %d, "
                   "\"truncated\": %d, \"fragments\": %llu, \"samples\": %llu, "
                   "\"pixels\": %llu}\n",
                   f, t, stats.ms, stats.views, stats.truncated,
                   (unsigned long long)stats.fragments, (unsigned long long)stats.samples,
                   (unsigned long long)stats.pixels);
        if (o.frames > 1 && tty)
            fprintf(stderr, "\rlimen: frame %ld/%ld", f + 1, o.frames);
    }
    if (o.frames > 1 && tty)
        fputc('\n', stderr);
    if (!rc && o.plan &&
        limen_plan_write_json(limen_renderer_plan(r), limen_script_scene(sc), o.plan)) {
        fprintf(stderr, "limen: cannot write '%s'\n", o.plan);
        rc = 1;
    }
    if (!rc && o.frames > 1)
        fprintf(stderr, "limen: wrote %ld frames to %s\n", o.frames,
                (frame_path(o.out, 0, o.frames, path, sizeof path), path));
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
        if (!strcmp(argv[i], "--heatmap") && v) {
            heat = v;
            i++;
        } else if (!strcmp(argv[i], "--threshold") && v) {
            if (limen_cli_parse_long(v, 0, 255, &threshold))
                return fail("--threshold: expected 0 to 255, got '%s'%s", v, ""), 2;
            i++;
        } else if (!strcmp(argv[i], "--max-bad") && v) {
            if (limen_cli_parse_double(v, &max_bad) || max_bad < 0 || max_bad > 1)
                return fail("--max-bad: expected 0 to 1, got '%s'%s", v, ""), 2;
            i++;
        } else if (!strcmp(argv[i], "--json")) {
            json = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return fail("diff: unknown option or missing value '%s'%s", argv[i], ""), 2;
        } else if (!a) {
            a = argv[i];
        } else if (!b) {
            b = argv[i];
        } else {
            return fail("diff: unexpected argument '%s'%s", argv[i], ""), 2;
        }
    }
    if (!a || !b)
        return fail("diff: needs two images%s%s", "", ""), 2;
    int wa, ha, wb, hb;
    unsigned char *pa = NULL, *pb = NULL, *ph = NULL;
    static const char too_big[] = ": more pixels than limen reads (LIMEN_IMAGE_MAX_PIXELS)";
    limen_status ra = limen_read_png(a, &wa, &ha, &pa);
    if (ra)
        return fail("cannot read '%s'%s", a, ra == LIMEN_ERR_ARG ? too_big : "");
    limen_status rb = limen_read_png(b, &wb, &hb, &pb);
    if (rb) {
        limen_free(pa);
        return fail("cannot read '%s'%s", b, rb == LIMEN_ERR_ARG ? too_big : "");
    }
    int rc = 0;
    limen_diff d;
    if (wa != wb || ha != hb) {
        char sa[32], sb[32];
        snprintf(sa, sizeof sa, "%dx%d", wa, ha);
        snprintf(sb, sizeof sb, "%dx%d", wb, hb);
        rc = fail("diff: sizes differ (%s against %s)", sa, sb);
    } else {
        if (heat && !(ph = malloc((size_t)wa * (size_t)ha * 3)))
            rc = fail("out of memory%s%s", "", "");
        if (!rc)
            limen_image_diff(pa, pb, wa, ha, (int)threshold, &d, ph);
        if (!rc && heat && limen_write_png(heat, wa, ha, ph))
            rc = fail("cannot write '%s'%s", heat, "");
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
    if (!strcmp(argv[1], "render"))
        return cmd_render(argc - 2, argv + 2);
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
