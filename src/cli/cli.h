/* cli.h - commands of the limen program, one file each where they are long. */
#ifndef LIMEN_CLI_H
#define LIMEN_CLI_H

#include <stdio.h>

#include "limen.h"

/* `limen trace ...`: argv holds the arguments after the command name. Returns the exit
 * status. */
int limen_cli_trace(int argc, char **argv);

/* Prints "limen: SCENE: message" for a message about the scene, unless the message already
 * names a place in it ("SCENE:12: ..."). */
void limen_cli_scene_error(const char *scene, const char *msg);

/* Option values, whole strings only; 0 on success, -1 (out untouched) otherwise. */
int limen_cli_parse_long(const char *s, long lo, long hi, long *out);     /* lo..hi */
int limen_cli_parse_double(const char *s, double *out);                  /* finite */
int limen_cli_parse_size(const char *s, int *w, int *h);   /* "WxH", 1..16384 each */

/* `limen view ...` (view.c). */
int limen_cli_view(int argc, char **argv);

/* The options of `limen render` (all but -o, --frames, --fps, --plan and --stats, which
 * `view` refuses) into rd, ro and the rest; returns 0, or 2 after a message. */
typedef struct limen_cli_pose limen_cli_pose;
int limen_cli_render_options(int argc, char **argv, const char **scene,
                             limen_renderer_desc *rd, limen_render_opts *ro, int *trusted,
                             limen_cli_pose *pose);

/* A camera pose from --eye X,Y,Z --look X,Y,Z [--up X,Y,Z] (pose.c), in world space. */
struct limen_cli_pose {
    int given;                  /* bits: 1 eye, 2 look, 4 up */
    float eye[3], look[3], up[3];
};
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

#endif
