/* hall.h - the scenes that measure how cost grows with what a scene holds (tests/test_scale.c
 * counts, bench/scale.c times), built with the public API alone.
 *
 * hall_create(n, pairs, seed): a long hall down -z, 8 wide, 4 high, 4 units per portal
 * pair; n small spheres (radius 0.08) scattered through it, `pairs` portal pairs: portal k
 * on the left wall at z = -4k - 2 facing into the hall, its partner on the right wall half
 * the hall further on; a floor, a light, the camera at the entrance looking down the hall.
 *
 * field_create(n, seed): n spheres in a fixed 20 x 12 x 20 block before the camera, their
 * radius falling as n grows so that they cover about the same share of the picture.
 *
 * bunnies_create(n, path, smooth, seed): n statues of one mesh file (the bunny: 10 units
 * wide, scaled to 0.3) on a jittered grid over a fixed 16 x 14 floor, each turned and
 * coloured at random, before a 16 x 6 mirror at its far end; the camera above the near
 * edge looks across the field at the mirror, which shows the field again. */
#ifndef LIMEN_TESTS_HALL_H
#define LIMEN_TESTS_HALL_H

#include <math.h>

#include "limen.h"

static unsigned long long hall__rng;

static double hall__uniform(void)
{
    hall__rng = hall__rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(hall__rng >> 11) * (1.0 / 9007199254740992.0);
}

static limen_node hall__add(limen_scene *s, limen_node_kind kind, float x, float y, float z)
{
    limen_node n = { 0 };
    limen_node_create(s, kind, NULL, &n);
    limen_node_set_position(s, n, (float[3]){ x, y, z });
    return n;
}

static limen_scene *hall__scene(int nodes)
{
    limen_scene *s = NULL;
    if (limen_scene_create(&(limen_scene_desc){ .max_nodes = nodes + 64 }, &s))
        return NULL;
    limen_scene_set_background(s, (float[3]){ 0.1f, 0.12f, 0.15f });
    return s;
}

static limen_node hall__camera(limen_scene *s, float x, float y, float z, float tx, float ty,
                               float tz)
{
    limen_node cam = hall__add(s, LIMEN_NODE_CAMERA, x, y, z);
    limen_node_look_at(s, cam, (float[3]){ x, y, z }, (float[3]){ tx, ty, tz },
                       (float[3]){ 0, 1, 0 });
    limen_scene_set_camera(s, cam);
    return cam;
}

__attribute__((unused)) static limen_scene *hall_create(int n, int pairs, unsigned long long seed)
{
    limen_scene *s = hall__scene(n + 2 * pairs);
    if (!s)
        return NULL;
    hall__rng = seed;
    float len = 4.0f * (float)pairs;
    limen_node floor = hall__add(s, LIMEN_NODE_QUAD, 0, 0, -0.5f * len);
    limen_node_set_rotation(s, floor, (float[3]){ -1.5707963f, 0, 0 });
    limen_node_set_dims(s, floor, (float[3]){ 8, len, 0 });
    limen_node_set_checker(s, floor, (float[3]){ 0.8f, 0.8f, 0.75f },
                           (float[3]){ 0.3f, 0.3f, 0.35f }, 1.0f);
    limen_node light = hall__add(s, LIMEN_NODE_LIGHT, 0, 3.5f, -10);
    limen_node_set_color(s, light, (float[3]){ 0.9f, 0.9f, 0.9f });
    for (int k = 0; k < pairs; k++) {
        limen_node a = hall__add(s, LIMEN_NODE_PORTAL, -4, 1.6f, -4.0f * (float)k - 2);
        limen_node b = hall__add(s, LIMEN_NODE_PORTAL, 4, 1.6f,
                                 -4.0f * (float)((k + pairs / 2) % pairs) - 2);
        limen_node_set_rotation(s, a, (float[3]){ 0, 1.5707963f, 0 });
        limen_node_set_rotation(s, b, (float[3]){ 0, -1.5707963f, 0 });
        limen_node_set_dims(s, a, (float[3]){ 2, 3, 0 });
        limen_node_set_dims(s, b, (float[3]){ 2, 3, 0 });
        limen_portal_link(s, a, b);
    }
    for (int i = 0; i < n; i++) {
        limen_node ball = hall__add(s, LIMEN_NODE_SPHERE, (float)(8.1 * hall__uniform() - 4.05),
                                    (float)(0.1 + 3.8 * hall__uniform()),
                                    (float)(-len * hall__uniform()));
        limen_node_set_dims(s, ball, (float[3]){ 0.08f, 0, 0 });
        limen_node_set_color(s, ball, (float[3]){ (float)(0.3 + 0.7 * hall__uniform()),
                                                  (float)(0.3 + 0.7 * hall__uniform()), 0.4f });
    }
    hall__camera(s, 0, 1.7f, 3, 0, 1.5f, -20);
    return s;
}

__attribute__((unused)) static limen_scene *field_create(int n, unsigned long long seed)
{
    limen_scene *s = hall__scene(n);
    if (!s)
        return NULL;
    hall__rng = seed;
    limen_node light = hall__add(s, LIMEN_NODE_LIGHT, 5, 10, 5);
    limen_node_set_color(s, light, (float[3]){ 0.9f, 0.9f, 0.9f });
    /* radius ~ n^(-1/2): n discs of area r^2 cover about the same share at any n */
    float r = (float)(1.2 / sqrt((double)n));
    for (int i = 0; i < n; i++) {
        limen_node ball = hall__add(s, LIMEN_NODE_SPHERE, (float)(20 * hall__uniform() - 10),
                                    (float)(12 * hall__uniform() - 6),
                                    (float)(-20 * hall__uniform() - 5));
        limen_node_set_dims(s, ball, (float[3]){ r, 0, 0 });
        limen_node_set_color(s, ball, (float[3]){ (float)hall__uniform(), 0.6f, 0.5f });
    }
    hall__camera(s, 0, 0, 12, 0, 0, -15);
    return s;
}

__attribute__((unused)) static limen_scene *bunnies_create(int n, const char *path, int smooth,
                                                           unsigned long long seed)
{
    limen_scene *s = hall__scene(n + 8);
    if (!s)
        return NULL;
    hall__rng = seed;
    limen_scene_set_ambient(s, 0.25f);
    limen_node light = hall__add(s, LIMEN_NODE_LIGHT, 3, 6, 0);
    limen_node_set_color(s, light, (float[3]){ 0.9f, 0.88f, 0.8f });
    limen_node floor = hall__add(s, LIMEN_NODE_QUAD, 0, 0, -8);
    limen_node_set_rotation(s, floor, (float[3]){ -1.5707963f, 0, 0 });
    limen_node_set_dims(s, floor, (float[3]){ 16, 16, 0 });
    limen_node_set_color(s, floor, (float[3]){ 0.35f, 0.45f, 0.3f });
    limen_node mirror = hall__add(s, LIMEN_NODE_MIRROR, 0, 3, -16);
    limen_node_set_dims(s, mirror, (float[3]){ 16, 6, 0 });
    int cols = (int)ceil(sqrt((double)n));
    int rows = (n + cols - 1) / cols;
    float dx = 15.0f / (float)cols, dz = 14.0f / (float)rows;
    for (int i = 0; i < n; i++) {
        limen_node b = { 0 };
        if (limen_node_create(s, LIMEN_NODE_MESH, NULL, &b) || limen_mesh_load(s, b, path)) {
            limen_scene_destroy(s);
            return NULL;
        }
        float x = -7.5f + dx * ((float)(i % cols) + 0.2f + 0.6f * (float)hall__uniform());
        float z = -1.0f - dz * ((float)(i / cols) + 0.2f + 0.6f * (float)hall__uniform());
        limen_node_set_position(s, b, (float[3]){ x, 0, z });
        limen_node_set_rotation(s, b, (float[3]){ 0, (float)(6.2831853 * hall__uniform()), 0 });
        limen_node_set_scale(s, b, (float[3]){ 0.03f, 0.03f, 0.03f });
        limen_node_set_color(s, b, (float[3]){ (float)(0.5 + 0.5 * hall__uniform()),
                                               (float)(0.4 + 0.5 * hall__uniform()),
                                               (float)(0.3 + 0.4 * hall__uniform()) });
        limen_mesh_set_smooth(s, b, smooth);
    }
    hall__camera(s, 0, 2.5f, 1.5f, 0, 1.0f, -14);
    return s;
}

#endif
