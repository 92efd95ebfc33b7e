/* cli.h - commands of the limen program, one file each where they are long, and what they
 * share (common.c): messages, usage tables, the options of every command that runs a scene. */
#ifndef LIMEN_CLI_H
#define LIMEN_CLI_H

#include <stdio.h>

#include "limen.h"

/* `limen trace ...`: argv holds the arguments after the command name. Returns the exit
 * status. */
int limen_cli_trace(int argc, char **argv);

/* Prints "limen: message" to stderr; returns status (1: the run failed, 2: bad usage). */
int limen_cli_fail(int status, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Prints "limen: SCENE: message" for a message about the scene, unless the message already
 * names a place in it ("SCENE:12: ..."). */
void limen_cli_scene_error(const char *scene, const char *msg);

/* Option values, whole strings only; 0 on success, -1 (out untouched) otherwise. */
int limen_cli_parse_long(const char *s, long lo, long hi, long *out);     /* lo..hi */
int limen_cli_parse_double(const char *s, double *out);                  /* finite */
int limen_cli_parse_size(const char *s, int *w, int *h);   /* "WxH", 1..16384 each */

/* One line of a command's usage: the option with its value, and what it does ('\n' in
 * help continues on the next line, aligned). A table ends with { NULL, NULL }. */
typedef struct limen_cli_option {
    const char *name, *help;
} limen_cli_option;

/* Prints "usage: SYNOPSIS" and then each table under its heading (tables and headings
 * both end with NULL). */
void limen_cli_usage(FILE *f, const char *synopsis, const char *const *headings,
                     const limen_cli_option *const *tables);

/* A camera pose from --eye X,Y,Z --look X,Y,Z [--up X,Y,Z] (pose.c), in world space. */
typedef struct limen_cli_pose {
    int given;                  /* bits: 1 eye, 2 look, 4 up */
    float eye[3], look[3], up[3];
} limen_cli_pose;
/* If a is --eye, --look or --up, reads v into p and returns 1; 0 if a is another option;
 * -1 after a message if v is missing or not three numbers. */
int limen_cli_pose_option(const char *a, const char *v, limen_cli_pose *p);
int limen_cli_pose_check(const limen_cli_pose *p);          /* eye and look together */
/* Places the scene camera at the pose (detached from any parent); 0 if none was given. */
int limen_cli_pose_apply(limen_scene *s, const limen_cli_pose *p);
/* The scene camera's world pose (look = eye + its unit forward); -1 without a camera. */
int limen_cli_pose_get(limen_scene *s, limen_cli_pose *p);
/* "--eye X,Y,Z --look X,Y,Z --up X,Y,Z", each float given exactly. */
void limen_cli_pose_print(FILE *f, const limen_cli_pose *p);

/* What every command that runs a scene takes (render, trace, view). */
typedef struct limen_cli_run {
    const char *scene, *out;
    int width, height;          /* 0: 640 x 480 */
    limen_limits limits;        /* depth_rule and depth from --depth / --depth-override */
    double time, fps;
    long frames;
    int stats, trusted, help;
    limen_cli_pose pose;        /* --eye, --look, --up */
    int64_t memory;             /* --memory: the script's cap in bytes; 0: the default,
                                 * -1: none */
} limen_cli_run;

extern const limen_cli_option limen_cli_run_options[];
/* The usage of a command that runs a scene: its synopsis, limen_cli_run_options, then its
 * own options under heading. */
void limen_cli_run_usage(FILE *f, const char *synopsis, const char *heading,
                         const limen_cli_option *own);

/* Sets the defaults (1 frame, 30 fps). */
void limen_cli_run_init(limen_cli_run *o);
/* Parses argv[*i] if it is one of limen_cli_run_options or the scene path, moving *i past
 * its value: returns 1 if it took it, 0 if it is not one of them, 2 after printing a usage
 * error. */
int limen_cli_run_option(int argc, char **argv, int *i, limen_cli_run *o);
/* After parsing: the scene and an output whose name says its format; 0, or 2 after a
 * message. cmd names the command in messages. */
int limen_cli_run_check(const limen_cli_run *o, const char *cmd);
/* OUT.png -> OUT_0007.png for frame 7 of a sequence (OUT.png itself for a single frame);
 * -1 if the name does not fit in buf (never a truncated name, which would write every
 * frame to one file). */
int limen_cli_frame_path(const char *out, long frame, long frames, char *buf, size_t size);
/* Writes the image in the format its name asks for (limen_write_image); a device or a pipe
 * (/dev/stdout) gets PNG, written in place. */
limen_status limen_cli_write_image(const char *path, int w, int h, const unsigned char *rgb);
/* Loads the scene script; NULL after printing why. */
limen_script *limen_cli_load(const limen_cli_run *o);
/* The script desc the run's options ask for (--trusted, --memory). */
void limen_cli_script_desc(const limen_cli_run *o, limen_script_desc *d);
/* The script's error, followed where the memory cap refused something by the --memory that
 * would allow it ("... (needs 231.8 MiB: --memory 256)"); in buf. */
const char *limen_cli_script_error(const limen_script *sc, limen_status st, char *buf,
                                   size_t size);
/* Runs update(t) for frame f of the run; 0, or 1 after printing the error followed by the
 * frame and time it happened at. newline: end a progress line first. */
int limen_cli_update(limen_script *sc, const limen_cli_run *o, long f, double t, int newline);

/* `limen view ...` (view.c). */
int limen_cli_view(int argc, char **argv);

/* The options of `limen render` (all but -o, --frames, --fps, --plan and --stats, which
 * `view` refuses) into rd, ro and the rest; returns 0, 1 after --help, or 2 after a message. */
int limen_cli_render_options(int argc, char **argv, const char **scene,
                             limen_renderer_desc *rd, limen_render_opts *ro,
                             limen_script_desc *sd, limen_cli_pose *pose);

#endif
