/* pose.c - `--eye X,Y,Z --look X,Y,Z [--up X,Y,Z]`: a camera pose given on the command line
 * in place of the scene camera's own, and the same pose printed back (by `limen view`), with
 * digits enough that the printed numbers give the same floats again. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

static int parse_vec3(const char *s, float out[3])
{
    char buf[3][64];
    const char *p = s;
    for (int k = 0; k < 3; k++) {
        const char *end = k < 2 ? strchr(p, ',') : p + strlen(p);
        if (!end || end == p || end - p >= (long)sizeof buf[k])
            return -1;
        memcpy(buf[k], p, (size_t)(end - p));
        buf[k][end - p] = '\0';
        double v;
        if (limen_cli_parse_double(buf[k], &v) || fabs(v) > 1e30)
            return -1;
        out[k] = (float)v;
        p = end + 1;
    }
    return 0;
}

int limen_cli_pose_option(const char *a, const char *v, limen_cli_pose *p)
{
    float *dst = !strcmp(a, "--eye") ? p->eye : !strcmp(a, "--look") ? p->look
               : !strcmp(a, "--up") ? p->up : NULL;
    if (!dst)
        return 0;
    if (!v) {
        fprintf(stderr, "limen: option %s needs a value\n", a);
        return -1;
    }
    if (parse_vec3(v, dst)) {
        fprintf(stderr, "limen: %s: expected X,Y,Z (three numbers), got '%s'\n", a, v);
        return -1;
    }
    p->given |= dst == p->eye ? 1 : dst == p->look ? 2 : 4;
    return 1;
}

int limen_cli_pose_check(const limen_cli_pose *p)
{
    if (p->given && (p->given & 3) != 3) {
        fprintf(stderr, "limen: --eye and --look go together (--up is optional)\n");
        return -1;
    }
    return 0;
}

int limen_cli_pose_apply(limen_scene *s, const limen_cli_pose *p)
{
    if (!p->given)
        return 0;
    limen_node cam = limen_scene_get_camera(s);
    const float y_up[3] = { 0, 1, 0 };
    if (!cam.id) {
        fprintf(stderr, "limen: the scene has no camera to place\n");
        return -1;
    }
    /* the pose is in world space: the camera leaves any parent */
    if (limen_node_set_parent(s, cam, (limen_node){ 0 }) ||
        limen_node_look_at(s, cam, p->eye, p->look, (p->given & 4) ? p->up : y_up)) {
        fprintf(stderr, "limen: cannot place the camera: %s\n", limen_scene_error(s));
        return -1;
    }
    return 0;
}

int limen_cli_pose_get(limen_scene *s, limen_cli_pose *p)
{
    float m[16];
    limen_node cam = limen_scene_get_camera(s);
    if (!cam.id || limen_node_world_matrix(s, cam, m))
        return -1;
    float fl = sqrtf(m[8] * m[8] + m[9] * m[9] + m[10] * m[10]);
    float ul = sqrtf(m[4] * m[4] + m[5] * m[5] + m[6] * m[6]);
    if (!(fl > 0) || !(ul > 0))
        return -1;
    for (int k = 0; k < 3; k++) {
        p->eye[k] = m[12 + k];
        p->look[k] = m[12 + k] - m[8 + k] / fl;
        p->up[k] = m[4 + k] / ul;
    }
    p->given = 7;
    return 0;
}

void limen_cli_pose_print(FILE *f, const limen_cli_pose *p)
{
    fprintf(f, "--eye %.9g,%.9g,%.9g --look %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g",
            (double)p->eye[0], (double)p->eye[1], (double)p->eye[2], (double)p->look[0],
            (double)p->look[1], (double)p->look[2], (double)p->up[0], (double)p->up[1],
            (double)p->up[2]);
}
