/* trace_cmd.c - `limen trace`: the ray-traced reference image of a scene. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "limen.h"

static const char *usage =
    "usage: limen trace SCENE.lua -o REF.png [--size WxH] [--depth N] [--time T]\n"
    "                   [--threads N] [--stats] [--trusted]\n"
    "                   [--eye X,Y,Z --look X,Y,Z [--up X,Y,Z]]\n";

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "limen: ");
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    return 2;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int limen_cli_trace(int argc, char **argv)
{
    const char *scene = NULL, *out = NULL;
    limen_trace_desc d = { 0 };
    double time = 0;
    int stats = 0, trusted = 0;
    limen_cli_pose pose = { 0 };
    if (argc == 0) {
        fputs(usage, stderr);
        return 2;
    }
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int pose_arg = limen_cli_pose_option(a, v, &pose);
        if (pose_arg < 0)
            return 2;
        if (pose_arg) {
            i++;
            continue;
        }
        bool takes_value = !strcmp(a, "-o") || !strcmp(a, "--output") ||
                           !strcmp(a, "--size") || !strcmp(a, "--depth") ||
                           !strcmp(a, "--time") || !strcmp(a, "--threads");
        if (takes_value && !v)
            return usage_error("option %s needs a value", a);
        if (takes_value)
            i++;
        if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            out = v;
        } else if (!strcmp(a, "--size")) {
            if (limen_cli_parse_size(v, &d.width, &d.height))
                return usage_error("--size: expected WxH with 1 <= W, H <= 16384, got '%s'", v);
        } else if (!strcmp(a, "--depth")) {
            long n;
            if (limen_cli_parse_long(v, 0, 255, &n))
                return usage_error("--depth: expected 0 to 255, got '%s'", v);
            d.limit_depth = 1;
            d.max_depth = (int)n;
        } else if (!strcmp(a, "--threads")) {
            long n;
            if (limen_cli_parse_long(v, 1, 256, &n))
                return usage_error("--threads: expected 1 to 256, got '%s'", v);
            d.threads = (int)n;
        } else if (!strcmp(a, "--time")) {
            if (limen_cli_parse_double(v, &time))
                return usage_error("--time: expected a number, got '%s'", v);
        } else if (!strcmp(a, "--stats")) {
            stats = 1;
        } else if (!strcmp(a, "--trusted")) {
            trusted = 1;
        } else if (a[0] == '-' && a[1]) {
            return usage_error("unknown option '%s'", a);
        } else if (!scene) {
            scene = a;
        } else {
            return usage_error("unexpected argument '%s'", a);
        }
    }
    if (!scene)
        return usage_error("trace: no scene script given%s", "");
    if (!out)
        return usage_error("trace: no output given (-o OUT.png)%s", "");
    if (limen_cli_pose_check(&pose))
        return 2;
    if (!d.width) {
        d.width = 640;
        d.height = 480;
    }

    limen_script *sc = NULL;
    limen_status st = limen_script_load(scene, &(limen_script_desc){ .trusted = trusted }, &sc);
    if (st) {
        fprintf(stderr, "limen: %s\n", sc ? limen_script_error(sc) : limen_status_string(st));
        limen_script_destroy(sc);
        return 1;
    }
    if (limen_script_animated(sc) && limen_script_update(sc, time)) {
        fprintf(stderr, "limen: %s\n", limen_script_error(sc));
        limen_script_destroy(sc);
        return 1;
    }
    limen_scene *s = limen_script_scene(sc);
    if (limen_cli_pose_apply(s, &pose)) {
        limen_script_destroy(sc);
        return 1;
    }
    unsigned char *rgb = malloc((size_t)d.width * (size_t)d.height * 3);
    int rc = 0;
    if (!rgb) {
        fprintf(stderr, "limen: out of memory for a %dx%d image\n", d.width, d.height);
        rc = 1;
    }
    double t0 = now_ms();
    if (!rc && (st = limen_trace_image(s, &d, rgb))) {
        limen_cli_scene_error(scene, limen_last_error(s)[0] ? limen_last_error(s)
                                                            : limen_status_string(st));
        rc = 1;
    }
    double ms = now_ms() - t0;
    if (!rc && limen_write_png(out, d.width, d.height, rgb)) {
        fprintf(stderr, "limen: cannot write '%s'\n", out);
        rc = 1;
    }
    if (!rc && stats)
        printf("{\"ms\": %.3f, \"pixels\": %ld}\n", ms, (long)d.width * d.height);
    free(rgb);
    limen_script_destroy(sc);
    return rc;
}
