/* common.c - what the commands of the limen program share: messages, usage tables, and the
 * options of every command that runs a scene (render, trace). */
#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "cli/cli.h"

int limen_cli_fail(int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("limen: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return status;
}

void limen_cli_usage(FILE *f, const char *synopsis, const char *const *headings,
                     const limen_cli_option *const *tables)
{
    fprintf(f, "usage: %s\n", synopsis);
    for (int t = 0; tables[t]; t++) {
        fprintf(f, "%s:\n", headings[t]);
        for (const limen_cli_option *o = tables[t]; o->name; o++) {
            int w = (int)strlen(o->name);
            fprintf(f, "  %s%*s", o->name, w < 24 ? 24 - w : 1, "");
            for (const char *h = o->help; *h; h++) {
                fputc(*h, f);
                if (*h == '\n')
                    fprintf(f, "%*s", 26, "");
            }
            fputc('\n', f);
        }
    }
}

const limen_cli_option limen_cli_run_options[] = {
    { "-o, --output OUT", "the image to write: .png, or .jpg / .jpeg (JPEG, quality 95)" },
    { "--size WxH", "image size (default 640x480)" },
    { "--depth N", "cap recursion at N levels: a surface recurses to the lesser of N\n"
                   "and its own max_depth (lowers, never raises; default: its own)" },
    { "--depth-override N", "recurse N levels through every surface, in place of its own\n"
                            "max_depth (raises and lowers)" },
    { "--time T", "scene time in seconds passed to update(t) (default 0)" },
    { "--frames N --fps F", "N frames from T at F frames per second (default 1, 30);\n"
                            "files are numbered OUT_0000.png, OUT_0001.png, ..." },
    { "--stats", "print one JSON line per frame (see the command's own list)" },
    { "--eye X,Y,Z --look X,Y,Z", "place the camera there instead of the scene's pose, looking\n"
                                   "at the point (what `limen view` screenshots print)" },
    { "--up X,Y,Z", "with --eye and --look: which way is up (default +Y)" },
    { "--trusted", "run the script with the full Lua standard library (io, os, ...);\n"
                   "without it the script runs in safe mode" },
    { "--memory MB", "the script's memory cap in MiB, meshes and images included (default\n"
                     "64, trusted or not; `none`: no cap); a scene refused for memory\n"
                     "says what --memory would allow it" },
    { "-h, --help", "print this and exit" },
    { NULL, NULL }
};

void limen_cli_run_usage(FILE *f, const char *synopsis, const char *heading,
                         const limen_cli_option *own)
{
    limen_cli_usage(f, synopsis, (const char *const[]){ "options", heading, NULL },
                    (const limen_cli_option *const[]){ limen_cli_run_options, own, NULL });
}

void limen_cli_run_init(limen_cli_run *o)
{
    memset(o, 0, sizeof *o);
    o->frames = 1;
    o->fps = 30;
}

int limen_cli_run_option(int argc, char **argv, int *i, limen_cli_run *o)
{
    const char *a = argv[*i];
    int pose = limen_cli_pose_option(a, *i + 1 < argc ? argv[*i + 1] : NULL, &o->pose);
    if (pose < 0)
        return 2;
    if (pose) {
        ++*i;
        return 1;
    }
    static const char *const valued[] = { "-o", "--output", "--size", "--depth",
                                          "--depth-override", "--time", "--frames", "--fps",
                                          "--memory", NULL };
    int takes = 0;
    for (int k = 0; valued[k]; k++)
        takes |= !strcmp(a, valued[k]);
    const char *v = NULL;
    if (takes) {
        if (*i + 1 >= argc)
            return limen_cli_fail(2, "option %s needs a value", a);
        v = argv[++*i];
    }
    long n;
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
        o->out = v;
    } else if (!strcmp(a, "--size")) {
        if (limen_cli_parse_size(v, &o->width, &o->height))
            return limen_cli_fail(2, "--size: expected WxH with 1 <= W, H <= 16384, got '%s'", v);
    } else if (!strcmp(a, "--depth") || !strcmp(a, "--depth-override")) {
        bool over = a[7] == '-';
        limen_depth_rule rule = over ? LIMEN_DEPTH_RULE_OVERRIDE : LIMEN_DEPTH_RULE_CAP;
        if (limen_cli_parse_long(v, 0, 255, &n))
            return limen_cli_fail(2, "%s: expected 0 to 255, got '%s'", a, v);
        if (o->limits.depth_rule && o->limits.depth_rule != rule)
            return limen_cli_fail(2, "--depth and --depth-override exclude each other");
        o->limits.depth_rule = rule;
        o->limits.depth = (int)n;
    } else if (!strcmp(a, "--time")) {
        if (limen_cli_parse_double(v, &o->time))
            return limen_cli_fail(2, "--time: expected a number, got '%s'", v);
    } else if (!strcmp(a, "--frames")) {
        if (limen_cli_parse_long(v, 1, 1000000, &o->frames))
            return limen_cli_fail(2, "--frames: expected 1 to 1000000, got '%s'", v);
    } else if (!strcmp(a, "--fps")) {
        if (limen_cli_parse_double(v, &o->fps) || !(o->fps > 0))
            return limen_cli_fail(2, "--fps: expected a positive number, got '%s'", v);
    } else if (!strcmp(a, "--stats")) {
        o->stats = 1;
    } else if (!strcmp(a, "--trusted")) {
        o->trusted = 1;
    } else if (!strcmp(a, "--memory")) {
        if (!strcmp(v, "none"))
            o->memory = -1;
        else if (limen_cli_parse_long(v, 1, 1L << 24, &n))
            return limen_cli_fail(2, "--memory: expected MiB from 1 to 16777216, or none, got "
                                     "'%s'", v);
        else
            o->memory = (int64_t)n << 20;
    } else if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
        o->help = 1;
    } else if (a[0] == '-' && a[1]) {
        return 0;
    } else if (!o->scene) {
        o->scene = a;
    } else {
        return limen_cli_fail(2, "unexpected argument '%s'", a);
    }
    return 1;
}

/* Case-insensitive: does path end in ext? */
static int ends_with(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n > k && strcasecmp(path + n - k, ext) == 0;
}

/* A device or a pipe (/dev/stdout, /dev/full, a FIFO): written in place, as PNG. */
static int is_device(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode));
}

limen_status limen_cli_write_image(const char *path, int w, int h, const unsigned char *rgb)
{
    return is_device(path) ? limen_write_png(path, w, h, rgb) : limen_write_image(path, w, h, rgb);
}

int limen_cli_run_check(const limen_cli_run *o, const char *cmd)
{
    if (limen_cli_pose_check(&o->pose))
        return 2;
    if (!o->scene)
        return limen_cli_fail(2, "%s: no scene script given", cmd);
    if (!o->out)
        return limen_cli_fail(2, "%s: no output given (-o OUT.png)", cmd);
    if (!ends_with(o->out, ".png") && !ends_with(o->out, ".jpg") && !ends_with(o->out, ".jpeg") &&
        !(o->frames == 1 && is_device(o->out)))
        return limen_cli_fail(2, "-o: cannot tell an image format from '%s' (expected a name "
                                 "ending in .png, .jpg or .jpeg)", o->out);
    return 0;
}

int limen_cli_frame_path(const char *out, long frame, long frames, char *buf, size_t size)
{
    int n;
    if (frames == 1) {
        n = snprintf(buf, size, "%s", out);
    } else {
        const char *dot = strrchr(out, '.');   /* limen_cli_run_check: there is one, at the end */
        if (dot - out > INT_MAX)
            return -1;
        n = snprintf(buf, size, "%.*s_%04ld%s", (int)(dot - out), out, frame, dot);
    }
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

/* What a scene script prints goes to stderr, marked as the script's: it cannot pass for the
 * program's own output (stdout), nor for one of its messages. */
static void script_print(void *scene, const char *line)
{
    fprintf(stderr, "limen: %s: print: %s\n", (const char *)scene, line);
}

void limen_cli_script_desc(const limen_cli_run *o, limen_script_desc *d)
{
    *d = (limen_script_desc){ .trusted = o->trusted, .memory_cap = o->memory,
                              .print = script_print, .print_user = (void *)o->scene };
}

const char *limen_cli_script_error(const limen_script *sc, limen_status st, char *buf,
                                   size_t size)
{
    const char *msg = sc ? limen_script_error(sc) : limen_status_string(st);
    int64_t need = limen_script_memory_needed(sc);
    if (need <= 0) {
        snprintf(buf, size, "%s", msg);
        return buf;
    }
    /* rounded up to a multiple of 64 MiB, the default: room for a little more */
    const int64_t step = (int64_t)64 << 20;
    int64_t mb = (need + step - 1) / step * 64;
    snprintf(buf, size, "%s (needs %.1f MiB: --memory %lld)", msg, (double)need / 1048576.0,
             (long long)mb);
    return buf;
}

limen_script *limen_cli_load(const limen_cli_run *o)
{
    limen_script *sc = NULL;
    limen_script_desc d;
    limen_cli_script_desc(o, &d);
    limen_status st = limen_script_load(o->scene, &d, &sc);
    if (st) {
        char msg[1400];
        limen_cli_fail(1, "%s", limen_cli_script_error(sc, st, msg, sizeof msg));
        limen_script_destroy(sc);
        return NULL;
    }
    /* what loading its files noticed, each "file: warning: ..." */
    limen_scene *s = limen_script_scene(sc);
    for (int i = 0; i < limen_scene_warning_count(s); i++)
        fprintf(stderr, "%s\n", limen_scene_warning(s, i));
    return sc;
}

int limen_cli_update(limen_script *sc, const limen_cli_run *o, long f, double t, int newline)
{
    if (!limen_script_animated(sc) || !limen_script_update(sc, t))
        return 0;
    if (newline)
        fputc('\n', stderr);
    char msg[1400];
    return limen_cli_fail(1, "%s (in update at frame %ld of %ld, t = %g s)",
                          limen_cli_script_error(sc, LIMEN_ERR_SCRIPT, msg, sizeof msg), f,
                          o->frames, t);
}
