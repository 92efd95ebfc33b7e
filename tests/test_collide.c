/* test_collide.c - bodies that collide (limen_sweep_sphere, limen_sweep_capsule,
 * limen_node_slide; Lua s:sweep and node:slide): contacts against known answers, the holes
 * behind portals and the partner's side, and a brute-force oracle on random scenes (every
 * piece of every node on both sides of every portal, contact times solved in closed form,
 * without the spatial index), fast moves that must not tunnel, and a ball bounced through a
 * loop of portals that must never leave its room. */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "limen.h"
#include "scratch.h"

/* ------------------------------------------------------------------ building scenes */

static limen_node make(limen_scene *s, limen_node_kind kind, const char *name, float x, float y,
                       float z, float dx, float dy, float dz)
{
    limen_node n;
    CHECK_OK(limen_node_create(s, kind, name, &n));
    CHECK_OK(limen_node_set_position(s, n, (float[3]){ x, y, z }));
    if (dx > 0)
        CHECK_OK(limen_node_set_dims(s, n, (float[3]){ dx, dy, dz }));
    return n;
}

static void face(limen_scene *s, limen_node n, float x, float y, float z)
{
    CHECK_OK(limen_node_set_facing(s, n, (float[3]){ x, y, z }, NULL));
}

static double frac(const limen_sweep_result *r)
{
    return r->fraction;
}

/* A floor quad at y = 0 and a ball: known contact fractions. */
static void test_known(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node floor = make(s, LIMEN_NODE_QUAD, "floor", 0, 0, 0, 10, 10, 0);
    face(s, floor, 0, 1, 0);
    limen_node ball = make(s, LIMEN_NODE_SPHERE, "ball", 3, 1, 0, 0.5f, 0, 0);
    limen_node box = make(s, LIMEN_NODE_BOX, "box", -3, 1, 0, 1, 2, 1);
    limen_node cyl = make(s, LIMEN_NODE_CYLINDER, "cyl", 0, 0, 3, 0.5f, 2, 0);
    limen_sweep_result r;
    /* falling from 3 to -1 with radius 0.5 touches at y = 0.5: fraction 2.5 / 4 */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 3, 0 }, (float[3]){ 0, -1, 0 }, 0.5f, NULL, &r));
    CHECK(r.hit && r.node.id == floor.id);
    CHECK_NEAR(frac(&r), 2.5 / 4, 1e-6);
    CHECK_NEAR(r.centre[1], 0.5, 1e-5);
    CHECK_NEAR(r.normal[1], 1, 1e-6);
    CHECK_NEAR(r.point[1], 0, 1e-6);
    /* along x into the ball at (3, 1, 0): centres 1 apart at x = 2 */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, 0 }, (float[3]){ 4, 1, 0 }, 0.5f, NULL, &r));
    CHECK(r.hit && r.node.id == ball.id);
    CHECK_NEAR(frac(&r), 0.5, 1e-6);
    CHECK_NEAR(r.point[0], 2.5, 1e-5);
    /* into the box's face at x = -2.5 */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, 0 }, (float[3]){ -4, 1, 0 }, 0.5f, NULL, &r));
    CHECK(r.hit && r.node.id == box.id);
    CHECK_NEAR(frac(&r), 2.0 / 4, 1e-6);
    CHECK_NEAR(r.normal[0], 1, 1e-6);
    /* onto the box's top edge (y = 2, x = -2.5) from above at x = -2.3: touches when the
     * centre is 0.5 from the edge, at height 2 + sqrt(0.25 - 0.04) */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ -2.3f, 4, 0 }, (float[3]){ -2.3f, 2, 0 }, 0.5f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == box.id);
    CHECK_NEAR(r.centre[1], 2 + sqrt(0.21), 1e-5);
    /* into the cylinder's side (radius 0.5 at z = 3) along z, and onto its cap */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, 0 }, (float[3]){ 0, 1, 6 }, 0.25f, NULL, &r));
    CHECK(r.hit && r.node.id == cyl.id);
    CHECK_NEAR(r.centre[2], 3 - 0.75, 1e-5);
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0.3f, 5, 3 }, (float[3]){ 0.3f, 1, 3 }, 0.25f, NULL,
                                &r));
    CHECK(r.hit && r.node.id == cyl.id);
    CHECK_NEAR(r.centre[1], 2.25, 1e-5);
    /* a miss, and the ignored node */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, -2 }, (float[3]){ 4, 1, -2 }, 0.5f, NULL, &r));
    CHECK(!r.hit && r.fraction == 1 && r.node.id == 0);
    CHECK_NEAR(r.centre[0], 4, 1e-6);
    limen_sweep_opts o = { .ignore = ball };
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, 0 }, (float[3]){ 4, 1, 0 }, 0.5f, &o, &r));
    CHECK(!r.hit);
    /* a capsule (vertical, 1 long) falling: its low end touches at y = 0.5 */
    CHECK_OK(limen_sweep_capsule(s, (float[3]){ 0, 2, -2 }, (float[3]){ 0, 3, -2 }, 0.5f,
                                 (float[3]){ 0, -4, 0 }, NULL, &r));
    CHECK(r.hit && r.node.id == floor.id);
    CHECK_NEAR(frac(&r), 1.5 / 4, 1e-6);
    CHECK_NEAR(r.centre[1], 1.0, 1e-5);
    CHECK_NEAR(r.segment[1], 1, 1e-6);
    /* a lying capsule sideways into the ball: its segment passes 0.2 below the centre */
    CHECK_OK(limen_sweep_capsule(s, (float[3]){ 0, 0.8f, -1 }, (float[3]){ 0, 0.8f, 1 }, 0.3f,
                                 (float[3]){ 4, 0, 0 }, NULL, &r));
    CHECK(r.hit && r.node.id == ball.id);
    CHECK_NEAR(r.centre[0], 3 - sqrt(0.64 - 0.04), 1e-5);
    limen_scene_destroy(s);
}

/* NaN, Inf, huge numbers, bad radii and stale handles are refused with a message. */
static void test_refuse(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node b = make(s, LIMEN_NODE_BOX, "b", 0, 0, 0, 1, 1, 1);
    limen_sweep_result r;
    limen_slide_result sr;
    float ok[3] = { 0, 0, 0 }, to[3] = { 1, 0, 0 };
    float bad[4][3] = { { NAN, 0, 0 }, { 0, INFINITY, 0 }, { 0, 0, -INFINITY }, { 2e9f, 0, 0 } };
    for (int i = 0; i < 4; i++) {
        CHECK(limen_sweep_sphere(s, bad[i], to, 1, NULL, &r) == LIMEN_ERR_ARG);
        CHECK(strstr(limen_scene_error(s), "sweep_sphere") != NULL);
        CHECK(limen_sweep_sphere(s, ok, bad[i], 1, NULL, &r) == LIMEN_ERR_ARG);
        CHECK(limen_sweep_capsule(s, ok, bad[i], 1, to, NULL, &r) == LIMEN_ERR_ARG);
        CHECK(limen_sweep_capsule(s, ok, to, 1, bad[i], NULL, &r) == LIMEN_ERR_ARG);
        CHECK(limen_node_slide(s, b, bad[i], 1, &sr) == LIMEN_ERR_ARG);
        CHECK(strstr(limen_scene_error(s), "slide: displacement") != NULL);
    }
    float radii[4] = { 0, -1, NAN, INFINITY };
    for (int i = 0; i < 4; i++) {
        CHECK(limen_sweep_sphere(s, ok, to, radii[i], NULL, &r) == LIMEN_ERR_ARG);
        CHECK(strstr(limen_scene_error(s), "radius") != NULL);
        CHECK(limen_node_slide(s, b, to, radii[i], &sr) == LIMEN_ERR_ARG);
    }
    CHECK(limen_sweep_sphere(s, NULL, to, 1, NULL, &r) == LIMEN_ERR_ARG);
    CHECK(limen_sweep_sphere(s, ok, to, 1, NULL, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_node_slide(s, (limen_node){ 0 }, to, 1, &sr) == LIMEN_ERR_HANDLE);
    limen_sweep_opts o = { .ignore = { 12345 } };
    CHECK(limen_sweep_sphere(s, ok, to, 1, &o, &r) == LIMEN_ERR_HANDLE);
    CHECK(limen_sweep_sphere(NULL, ok, to, 1, NULL, &r) == LIMEN_ERR_ARG);
    /* the node did not move */
    float p[3];
    CHECK_OK(limen_node_get_position(s, b, p));
    CHECK(p[0] == 0 && p[1] == 0 && p[2] == 0);
    limen_scene_destroy(s);
}

/* A wall (a box) with portal "in" a millimetre in front of it, "out" in an open field. */
static limen_scene *wall_scene(limen_node *wall, limen_node *in, limen_node *out, float out_w)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    *wall = make(s, LIMEN_NODE_BOX, "wall", 0, 1.5f, -0.1f, 8, 3, 0.2f);
    *in = make(s, LIMEN_NODE_PORTAL, "in", 0, 1.2f, 0.001f, 1.2f, 2.2f, 0);
    *out = make(s, LIMEN_NODE_PORTAL, "out", 20, 1.2f * out_w / 1.2f, 0, out_w,
                out_w * 2.2f / 1.2f, 0);
    face(s, *out, -1, 0, 0);
    CHECK_OK(limen_portal_link(s, *in, *out));
    return s;
}

/* The hole: a body that fits passes through the wall behind the portal; one too wide, or
 * beside the opening, or through an unpaired portal, is stopped. */
static void test_hole(void)
{
    limen_node wall, in, out;
    limen_scene *s = wall_scene(&wall, &in, &out, 1.2f);
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 2 }, (float[3]){ 0, 1.2f, -2 }, 0.3f,
                                NULL, &r));
    CHECK(!r.hit);
    CHECK(r.portals == 1 && r.portal.id == in.id);
    /* 2 in front of "in", so the rest (2 units) goes on from "out" towards -x */
    CHECK_NEAR(r.centre[0], 20 - 2.001, 1e-4);
    CHECK_NEAR(r.centre[1], 1.2, 1e-4);
    CHECK_NEAR(r.centre[2], 0, 1e-4);
    /* too wide for the 1.2 x 2.2 opening: the frame (the wall) stops it */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 2 }, (float[3]){ 0, 1.2f, -2 }, 0.7f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == wall.id && r.portals == 0);
    CHECK(r.centre[2] > 0.001f);
    /* beside the opening the wall is whole */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 2, 1.2f, 2 }, (float[3]){ 2, 1.2f, -2 }, 0.3f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == wall.id);
    CHECK_NEAR(r.centre[2], 0.3, 1e-5);
    /* off-centre within the opening, so that the sphere reaches past its edge: the frame */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0.45f, 1.2f, 2 }, (float[3]){ 0.45f, 1.2f, -2 },
                                0.3f, NULL, &r));
    CHECK(r.hit && r.node.id == wall.id);
    /* unpair: the portal is a wall of its own, one millimetre in front of the box */
    limen_node lone;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "lone", &lone));
    CHECK_OK(limen_node_set_dims(s, lone, (float[3]){ 1.2f, 2.2f, 0 }));
    CHECK_OK(limen_portal_link(s, out, lone));
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 2 }, (float[3]){ 0, 1.2f, -2 }, 0.3f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == in.id);
    CHECK_NEAR(r.centre[2], 0.301, 1e-5);
    limen_scene_destroy(s);
}

/* A body halfway through collides on both sides: a box just in front of "out" stops a
 * sphere whose centre has not reached "in" yet, and a box in front of "in" stops one whose
 * centre has come out of "out". Depth 0 makes the portal a wall. */
static void test_both_sides(void)
{
    limen_node wall, in, out;
    limen_scene *s = wall_scene(&wall, &in, &out, 1.2f);
    /* a thin box 0.2 in front of "out" (x = 19.8 face), over the opening */
    limen_node beyond = make(s, LIMEN_NODE_BOX, "beyond", 19.7f, 1.2f, 0, 0.2f, 0.4f, 0.4f);
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 2 }, (float[3]){ 0, 1.2f, -2 }, 0.4f,
                                NULL, &r));
    /* the sphere's front reaches 0.2 past "in" (z = 0.001) when its centre is 0.2 in front */
    CHECK(r.hit && r.node.id == beyond.id && r.portals == 0);
    CHECK_NEAR(r.centre[2], 0.201, 1e-4);
    CHECK_NEAR(r.point[2], -0.199, 1e-4);     /* the contact, seen from the entry side */
    CHECK_NEAR(r.normal[2], 1, 1e-4);
    /* the other way round: coming out of "out" backwards, past a box in front of "in" */
    CHECK_OK(limen_node_destroy(s, beyond));
    limen_node before = make(s, LIMEN_NODE_BOX, "before", 0, 1.2f, 0.301f, 0.4f, 0.4f, 0.2f);
    /* from in front of "out" through it (entering "out" leads back out of "in") */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 18, 1.2f, 0 }, (float[3]){ 21, 1.2f, 0 }, 0.1f,
                                NULL, &r));
    CHECK(r.portals == 1 && r.portal.id == out.id);
    CHECK(r.hit && r.node.id == before.id);
    /* out of "in" at z = 0.001 going +z, the box's face at z = 0.201: centre at 0.101 */
    CHECK_NEAR(r.centre[2], 0.101, 1e-4);
    /* a depth limit of 0 closes the portal: the sphere stops at it */
    limen_sweep_opts o = { .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 0 } };
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 18, 1.2f, 0 }, (float[3]){ 21, 1.2f, 0 }, 0.1f,
                                &o, &r));
    CHECK(r.hit && r.node.id == out.id && r.portals == 0);
    CHECK_NEAR(r.centre[0], 19.9, 1e-4);
    limen_scene_destroy(s);
}

/* A corridor that loops: "a" at z = -4 facing +z leads out of "b" at z = 0 facing -z. A
 * step as long as two laps passes "a" twice, one of half a lap once, and each time the
 * body comes out where it should. */
static void test_twice(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node a = make(s, LIMEN_NODE_PORTAL, "a", 0, 1, -4, 2, 2, 0);
    limen_node b = make(s, LIMEN_NODE_PORTAL, "b", 0, 1, 0, 2, 2, 0);
    face(s, b, 0, 0, -1);
    CHECK_OK(limen_portal_link(s, a, b));
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, -1 }, (float[3]){ 0, 1, -11 }, 0.3f, NULL,
                                &r));
    CHECK(!r.hit && r.portals == 2 && r.portal.id == a.id);
    CHECK_NEAR(r.centre[2], -3, 1e-4);
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, -1 }, (float[3]){ 0, 1, -3 }, 0.3f, NULL,
                                &r));
    CHECK(!r.hit && r.portals == 0);
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1, -1 }, (float[3]){ 0, 1, -5 }, 0.3f, NULL,
                                &r));
    CHECK(!r.hit && r.portals == 1);
    CHECK_NEAR(r.centre[2], -1, 1e-4);
    limen_node body = make(s, LIMEN_NODE_SPHERE, "body", 0, 1, -1, 0.3f, 0, 0);
    limen_slide_result sr;
    CHECK_OK(limen_node_slide(s, body, (float[3]){ 0, 0, -10 }, 0.3f, &sr));
    CHECK(sr.crossed == 2 && sr.contacts == 0);
    float p[3];
    CHECK_OK(limen_node_get_position(s, body, p));
    CHECK_NEAR(p[2], -3, 1e-4);
    limen_scene_destroy(s);
}

/* A floor with 18 portals on it (in pairs): a sweep low over a row of them, in front of all,
 * cuts the floor's face by each hole it meets (in parts that grow with the holes, not as
 * their power) and touches the floor beyond the last. */
static void test_many_holes(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node floor = make(s, LIMEN_NODE_BOX, "floor", 0, -0.1f, 0, 20, 0.2f, 20);
    limen_node prev = { 0 };
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 6; i++) {
            limen_node p = make(s, LIMEN_NODE_PORTAL, NULL, (float)(2 * i - 5), 0.001f,
                                (float)(1.2 * j - 1.2), 1, 1, 0);
            face(s, p, 0, 1, 0);
            if (prev.id) {
                CHECK_OK(limen_portal_link(s, prev, p));
                prev = (limen_node){ 0 };
            } else {
                prev = p;
            }
        }
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ -8, 0.9f, 0 }, (float[3]){ 8, 0.45f, 0 }, 0.5f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == floor.id && r.portals == 0);
    CHECK_NEAR(r.fraction, 0.4 / 0.45, 1e-5);
    limen_scene_destroy(s);
}

/* Unequal portals scale the body: out of a portal twice as wide, the radius doubles. */
static void test_unequal(void)
{
    limen_node wall, in, out;
    limen_scene *s = wall_scene(&wall, &in, &out, 2.4f);
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 1 }, (float[3]){ 0, 1.2f, -1 }, 0.2f,
                                NULL, &r));
    CHECK(!r.hit && r.portals == 1);
    CHECK_NEAR(r.radius, 0.4, 1e-5);
    /* 0.999 to the portal, so 1.001 left, doubled: out at x = 20 - 2.002 */
    CHECK_NEAR(r.centre[0], 20 - 2 * 1.001, 1e-4);
    CHECK_NEAR(r.centre[1], 2.4, 1e-4);
    CHECK_NEAR(r.matrix[0] * r.matrix[0] + r.matrix[1] * r.matrix[1] + r.matrix[2] * r.matrix[2],
               4, 1e-4);
    /* a box 1 in front of "out" stops the doubled sphere 0.4 before it */
    limen_node box = make(s, LIMEN_NODE_BOX, "box", 18.5f, 2.4f, 0, 1, 1, 1);
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 1.2f, 1 }, (float[3]){ 0, 1.2f, -1 }, 0.2f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == box.id && r.portals == 1);
    CHECK_NEAR(r.centre[0], 19 + 0.4, 1e-4);
    limen_scene_destroy(s);
}

/* Meshes collide by their triangles (here a square of two, turned to face +z). */
static void test_mesh(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "m", &m));
    const float pos[] = { -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0 };
    const uint32_t idx[] = { 0, 1, 2, 0, 2, 3 };
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){ .positions = pos,
                                      .vertex_count = 4, .indices = idx, .triangle_count = 2 }));
    CHECK_OK(limen_node_set_position(s, m, (float[3]){ 0, 0, -3 }));
    CHECK_OK(limen_node_set_scale(s, m, (float[3]){ 2, 2, 2 }));
    limen_sweep_result r;
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 1.5f, 1.5f, 0 }, (float[3]){ 1.5f, 1.5f, -6 }, 0.5f,
                                NULL, &r));
    CHECK(r.hit && r.node.id == m.id);
    CHECK_NEAR(r.centre[2], -2.5, 1e-5);
    /* past its corner (2, 2) it misses */
    CHECK_OK(limen_sweep_sphere(s, (float[3]){ 2.6f, 2.6f, 0 }, (float[3]){ 2.6f, 2.6f, -6 }, 0.5f,
                                NULL, &r));
    CHECK(!r.hit);
    limen_scene_destroy(s);
}

/* A grid of 101 x 101 vertices over [-50, 50]^2, flat but for a bump at (40, 1, 40); with
 * `whole` 0, only the cells around the bump. */
static limen_node grid_mesh(limen_scene *s, int whole)
{
    static float pos[101 * 101 * 3];
    static uint32_t idx[100 * 100 * 6];
    for (int j = 0; j <= 100; j++)
        for (int i = 0; i <= 100; i++) {
            float *p = &pos[3 * (j * 101 + i)];
            p[0] = (float)(i - 50);
            p[1] = i == 90 && j == 90 ? 1.0f : 0.0f;
            p[2] = (float)(j - 50);
        }
    int t = 0;
    for (int j = 0; j < 100; j++)
        for (int i = 0; i < 100; i++) {
            if (!whole && (i < 88 || i > 91 || j < 88 || j > 91))
                continue;
            uint32_t a = (uint32_t)(j * 101 + i), b = a + 1, c = a + 101, d = a + 102;
            uint32_t tri[6] = { a, c, b, b, c, d };
            memcpy(&idx[3 * t], tri, sizeof tri);
            t += 2;
        }
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "grid", &m));
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){ .positions = pos,
                                      .vertex_count = 101 * 101, .indices = idx,
                                      .triangle_count = t }));
    return m;
}

/* A sweep across a mesh of 20,000 triangles, whose box holds all of them (tested a few
 * thousand at a time), meets the bump where a mesh of its 32 neighbours alone does. */
static void test_big_mesh(void)
{
    double f[2];
    for (int whole = 0; whole < 2; whole++) {
        limen_scene *s;
        CHECK_OK(limen_scene_create(NULL, &s));
        limen_node m = grid_mesh(s, whole);
        limen_sweep_result r;
        CHECK_OK(limen_sweep_sphere(s, (float[3]){ -45, 0.6f, -45 }, (float[3]){ 45, 0.6f, 45 },
                                    0.5f, NULL, &r));
        CHECK(r.hit && r.node.id == m.id);
        CHECK(r.centre[0] > 38 && r.centre[0] < 40);
        f[whole] = r.fraction;
        limen_scene_destroy(s);
    }
    CHECK_NEAR(f[0], f[1], 1e-6);
}

/* Collide and slide: into a wall at 45 degrees, the node ends against it having slid along;
 * through a portal it comes out turned; it ignores itself and its children. */
static void test_slide(void)
{
    limen_node wall, in, out;
    limen_scene *s = wall_scene(&wall, &in, &out, 1.2f);
    limen_node body = make(s, LIMEN_NODE_SPHERE, "body", 2, 1.2f, 1, 0.3f, 0, 0);
    limen_node hat = make(s, LIMEN_NODE_BOX, "hat", 0, 0.5f, 0, 0.2f, 0.2f, 0.2f);
    CHECK_OK(limen_node_set_parent(s, hat, body));
    limen_slide_result r;
    CHECK_OK(limen_node_slide(s, body, (float[3]){ 1, 0, -2 }, 0.3f, &r));
    float p[3];
    CHECK_OK(limen_node_get_position(s, body, p));
    CHECK(r.contacts >= 1 && r.crossed == 0);
    CHECK_NEAR(p[2], 0.3, 1e-3);            /* against the wall's face at z = 0 */
    CHECK(p[2] >= 0.3f - 1e-5f);
    CHECK_NEAR(p[0], 3, 1e-3);              /* slid the whole way along x */
    CHECK_NEAR(r.normal[2], 1, 1e-4);
    CHECK_NEAR(r.moved[0], 1, 1e-3);
    CHECK_NEAR(r.moved[2], -0.7, 1e-3);
    /* straight into the opening: it comes out of "out", turned to -x */
    CHECK_OK(limen_node_set_position(s, body, (float[3]){ 0, 1.2f, 1 }));
    CHECK_OK(limen_node_slide(s, body, (float[3]){ 0, 0, -2 }, 0.3f, &r));
    CHECK(r.crossed == 1 && r.portal.id == in.id && r.contacts == 0);
    float w[16];
    CHECK_OK(limen_node_world_matrix(s, body, w));
    CHECK_NEAR(w[12], 19, 1e-3);
    CHECK_NEAR(w[14], 0, 1e-3);
    CHECK_NEAR(w[8], 1, 1e-4);              /* its local +z (back) now points along +x */
    /* a very fast move into the wall beside the opening does not tunnel */
    CHECK_OK(limen_node_set_position(s, body, (float[3]){ 3, 1.2f, 1 }));
    CHECK_OK(limen_node_slide(s, body, (float[3]){ 0, 0, -1e6f }, 0.3f, &r));
    CHECK_OK(limen_node_get_position(s, body, p));
    CHECK(r.contacts >= 1 && p[2] >= 0.3f - 1e-5f && p[2] < 0.31f);
    /* a person (a capsule from the eyes 0.8 down) stops at a low box that a ball at the
     * eyes passes over; the capsule passes the opening (its bottom, 0.15, above the
     * portal's, 0.1) and comes out turned */
    limen_node low = make(s, LIMEN_NODE_BOX, "low", 0, 0.25f, 3, 1, 0.5f, 1);
    limen_node eye = make(s, LIMEN_NODE_CAMERA, "eye", 0, 1.2f, 5, 0, 0, 0);
    CHECK_OK(limen_node_slide(s, eye, (float[3]){ 0, 0, -3 }, 0.25f, &r));
    CHECK(r.contacts == 0);
    CHECK_OK(limen_node_set_position(s, eye, (float[3]){ 0, 1.2f, 5 }));
    CHECK_OK(limen_node_slide_capsule(s, eye, (float[3]){ 0, 0, -3 }, 0.25f,
                                      (float[3]){ 0, -0.8f, 0 }, &r));
    CHECK_OK(limen_node_get_position(s, eye, p));
    CHECK(r.contacts >= 1);
    CHECK_NEAR(p[2], 3.5 + 0.25, 1e-3);
    CHECK_OK(limen_node_destroy(s, low));
    CHECK_OK(limen_node_slide_capsule(s, eye, (float[3]){ 0, 0, -5 }, 0.25f,
                                      (float[3]){ 0, -0.8f, 0 }, &r));
    CHECK(r.crossed == 1 && r.contacts == 0);
    CHECK_NEAR(r.segment[1], -0.8, 1e-4);
    CHECK_OK(limen_node_world_matrix(s, eye, w));
    CHECK_NEAR(w[12], 20 - 1.251, 1e-3);
    CHECK(limen_node_slide_capsule(s, eye, (float[3]){ 0, 0, -1 }, 0.25f,
                                   (float[3]){ 0, NAN, 0 }, &r) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

/* The Lua names: s:sweep{from, to, radius} and node:slide{by, radius}; NaN refused. */
static void test_lua(void)
{
    const char *path = script("collide.lua", HEAD
        "s:plane { pos = {0, 0, 0}, normal = {0, 1, 0}, size = {10, 10} }\n"
        "local ball = s:sphere { name = 'ball', pos = {3, 1, 0}, radius = 0.5 }\n"
        "local r = s:sweep { from = {0, 3, 0}, to = {0, -1, 0}, radius = 0.5 }\n"
        "assert(r.hit == true and math.abs(r.fraction - 0.625) < 1e-6, 'fraction')\n"
        "assert(math.abs(r.centre[2] - 0.5) < 1e-5 and r.point[2] == 0, 'centre, point')\n"
        "assert(r.normal[2] == 1 and r.portals == 0 and r.node ~= nil, 'normal')\n"
        "r = s:sweep { from = {0, 1, 0}, to = {4, 1, 0}, radius = 0.5 }\n"
        "assert(r.node == ball and math.abs(r.fraction - 0.5) < 1e-6, 'ball')\n"
        "r = s:sweep { from = {0, 1, 0}, to = {4, 1, 0}, radius = 0.5, segment = {0, 0.5, 0} }\n"
        "assert(r.node == ball, 'capsule')\n"
        "r = s:sweep { from = {0, 1, -3}, to = {4, 1, -3}, radius = 0.5 }\n"
        "assert(r.hit == false and r.fraction == 1 and r.node == nil, 'miss')\n"
        "local a, b = s:portal_pair({ pos = {0, 1, -5}, normal = {0, 0, 1}, size = {1, 2} },\n"
        "                           { pos = {-4, 1, -5}, normal = {1, 0, 0}, size = {1, 2} })\n"
        "r = s:sweep { from = {0, 1, -4}, to = {0, 1, -6}, radius = 0.2 }\n"
        "assert(r.portals == 1 and r.portal == a and math.abs(r.centre[1] + 3) < 1e-4, 'portal')\n"
        "local body = s:sphere { pos = {0, 1, -4}, radius = 0.2 }\n"
        "local m = body:slide { by = {0, 0, -2}, radius = 0.2 }\n"
        "assert(m.portals == 1 and m.portal == a and m.contacts == 0, 'slide portal')\n"
        "assert(math.abs(body.pos[1] + 3) < 1e-4, 'slide pos')\n"
        "local tall = s:sphere { pos = {3, 2, 3}, radius = 0.1 }\n"
        "m = tall:slide { by = {0, -5, 0}, radius = 0.2, segment = {0, -1, 0} }\n"
        "assert(m.contacts >= 1 and math.abs(tall.pos[2] - 1.2) < 1e-3, 'capsule slide')\n"
        "m = body:slide { by = {0, -5, 0}, radius = 0.2 }\n"
        "assert(m.contacts >= 1 and math.abs(body.pos[2] - 0.2) < 1e-3, 'slide floor')\n"
        "assert(math.abs(m.moved[2] + 0.8) < 1e-3 and m.normal[2] == 1, 'moved')\n"
        "local ok, e = pcall(s.sweep, s, { from = {0/0, 0, 0}, to = {1, 0, 0}, radius = 1 })\n"
        "assert(not ok and e:find('sweep: field .from.%[1%] must be a finite number'), e)\n"
        "ok, e = pcall(s.sweep, s, { from = {0, 0, 0}, to = {1/0, 0, 0}, radius = 1 })\n"
        "assert(not ok and e:find('finite'), e)\n"
        "ok, e = pcall(s.sweep, s, { from = {0, 0, 0}, to = {1, 0, 0}, radius = -1 })\n"
        "assert(not ok and e:find('radius'), e)\n"
        "ok, e = pcall(s.sweep, s, { from = {0, 0, 0}, to = {1, 0, 0}, radius = 1, speed = 2 })\n"
        "assert(not ok and e:find('speed'), e)\n"
        "ok, e = pcall(body.slide, body, { by = {0, 0/0, 0}, radius = 1 })\n"
        "assert(not ok and e:find('by'), e)\n"
        "return s\n");
    limen_script *sc = NULL;
    limen_status st = limen_script_load(path, NULL, &sc);
    CHECK_MSG(st == LIMEN_OK, "%s", limen_script_error(sc));
    limen_script_destroy(sc);
}

/* ------------------------------------------------------------------ the oracle */

/* Pieces as the oracle sees them: every polygon (box faces, quads, mirrors, closed portals,
 * mesh triangles) and ball of the scene, read through limen_drawables. */
typedef struct opiece {
    int ball, nv;
    limen_node node;
    double v[40][3], c[3], r;
} opiece;

typedef struct ogate {
    limen_node node;
    double plane[4], side[5][4], pside[5][4], x[16], k;
} ogate;

static uint64_t rng_state;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}
static double rnd_in(double a, double b)
{
    return a + (b - a) * rnd();
}

static double odot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void opoint(const float *m, const double p[3], double o[3])
{
    for (int i = 0; i < 3; i++)
        o[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
}

static void dpoint(const double *m, const double p[3], double o[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
    memcpy(o, r, sizeof r);
}

static void dvec(const double *m, const double p[3], double o[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2];
    memcpy(o, r, sizeof r);
}

static double pdist(const double pl[4], const double p[3])
{
    return odot(pl, p) + pl[3];
}

/* Plane through p with unit normal along n. */
static void mkplane(const double n[3], const double p[3], double pl[4])
{
    double l = sqrt(odot(n, n));
    for (int k = 0; k < 3; k++)
        pl[k] = n[k] / l;
    pl[3] = -odot(pl, p);
}

/* Clips with the public limen_clip_polygon; false when less than a triangle is left. */
static bool oclip(const double (*in)[3], int n, const double pl[4], double (*out)[3], int *m)
{
    double h[48][4], o[49][4];
    for (int i = 0; i < n; i++) {
        memcpy(h[i], in[i], sizeof(double) * 3);
        h[i][3] = 1;
    }
    int k = limen_clip_polygon(&h[0][0], n, pl, &o[0][0], 40);
    for (int i = 0; i < k; i++)
        for (int c = 0; c < 3; c++)
            out[i][c] = o[i][c] / o[i][3];
    *m = k;
    return k >= 3;
}

typedef struct oscene {
    opiece *p;
    int n, cap;
} oscene;

static void opush(oscene *o, const opiece *pc)
{
    if (o->n == o->cap) {
        o->cap = o->cap ? 2 * o->cap : 256;
        o->p = realloc(o->p, sizeof *o->p * (size_t)o->cap);
    }
    o->p[o->n++] = *pc;
}

/* The polygon less the prisms behind the gates (recursively, one gate at a time). */
static void ocarve(oscene *o, limen_node node, const double (*v)[3], int n, ogate *const *g,
                   int ng)
{
    if (ng == 0) {
        opiece pc = { .nv = n, .node = node };
        memcpy(pc.v, v, sizeof(double) * 3 * (size_t)n);
        opush(o, &pc);
        return;
    }
    const double *outs[6] = { g[0]->plane, g[0]->side[0], g[0]->side[1], g[0]->side[2],
                              g[0]->side[3], g[0]->side[4] };
    double a[40][3], b[40][3];      /* whole unless it meets the prism */
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    int m = n;
    bool meets = true;
    for (int i = 0; i < 6 && meets; i++) {
        double in[4] = { -outs[i][0], -outs[i][1], -outs[i][2], -outs[i][3] };
        meets = oclip((const double(*)[3])a, m, in, b, &m);
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
    if (!meets) {
        ocarve(o, node, v, n, g + 1, ng - 1);
        return;
    }
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);     /* disjoint parts, as the library */
    m = n;
    for (int i = 0; i < 6; i++) {
        double out[40][3];
        int k;
        if (oclip((const double(*)[3])a, m, outs[i], out, &k))
            ocarve(o, node, (const double(*)[3])out, k, g + 1, ng - 1);
        double in[4] = { -outs[i][0], -outs[i][1], -outs[i][2], -outs[i][3] };
        if (!oclip((const double(*)[3])a, m, in, b, &m))
            return;
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
}

static void ocut(oscene *o, limen_node node, const double (*v)[3], int n, const ogate *ghost,
                 ogate *const *holes, int nholes)
{
    if (!ghost) {
        ocarve(o, node, v, n, holes, nholes);
        return;
    }
    double a[40][3], b[40][3];
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    int m = n;
    for (int i = 0; i < 5; i++) {
        if (!oclip((const double(*)[3])a, m, ghost->pside[i], b, &m))
            return;
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
    ocarve(o, node, (const double(*)[3])a, m, NULL, 0);
}

static void dmul(const double *a, const double *b, double *o);
static void dinvert(const double *m, double *o);

static bool oopen(limen_scene *s, const limen_drawable *d, int passed)
{
    if (d->kind != LIMEN_NODE_PORTAL || !d->visible)
        return false;
    limen_node q = limen_portal_get_partner(s, d->node);
    int md;
    limen_surface_get(s, d->node, NULL, NULL, NULL, &md);
    return q.id && limen_node_get_visible(s, q) && passed + 1 <= md;
}

/* Every piece of the scene, with holes or for a ghost. */
static void ogather(limen_scene *s, const limen_drawable *items, int count, int passed,
                    const ogate *ghost, ogate *const *holes, int nholes, oscene *o)
{
    o->n = 0;
    for (int i = 0; i < count; i++) {
        const limen_drawable *d = &items[i];
        if (!d->visible)
            continue;
        const float *m = d->world;
        switch (d->kind) {
        case LIMEN_NODE_SPHERE: {
            opiece pc = { .ball = 1, .node = d->node };
            double z[3] = { 0, 0, 0 };
            opoint(m, z, pc.c);
            pc.r = d->dims[0] * sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            opush(o, &pc);
            break;
        }
        case LIMEN_NODE_BOX: {
            for (int ax = 0; ax < 3; ax++) {
                for (int sg = -1; sg <= 1; sg += 2) {
                    double f[4][3];
                    int u = (ax + 1) % 3, v = (ax + 2) % 3;
                    const int su[4] = { -1, 1, 1, -1 }, sv[4] = { -1, -1, 1, 1 };
                    for (int c = 0; c < 4; c++) {
                        double l[3];
                        l[ax] = 0.5 * sg * d->dims[ax];
                        l[u] = 0.5 * su[c] * d->dims[u];
                        l[v] = 0.5 * sv[c] * d->dims[v];
                        opoint(m, l, f[c]);
                    }
                    ocut(o, d->node, (const double(*)[3])f, 4, ghost, holes, nholes);
                }
            }
            break;
        }
        case LIMEN_NODE_PORTAL:
        case LIMEN_NODE_QUAD:
        case LIMEN_NODE_MIRROR: {
            if (d->kind == LIMEN_NODE_PORTAL && oopen(s, d, passed))
                break;              /* an open portal is an opening; a closed one a wall */
            double f[4][3];
            const double l[4][3] = { { -0.5 * d->dims[0], -0.5 * d->dims[1], 0 },
                                     { 0.5 * d->dims[0], -0.5 * d->dims[1], 0 },
                                     { 0.5 * d->dims[0], 0.5 * d->dims[1], 0 },
                                     { -0.5 * d->dims[0], 0.5 * d->dims[1], 0 } };
            for (int c = 0; c < 4; c++)
                opoint(m, l[c], f[c]);
            ocut(o, d->node, (const double(*)[3])f, 4, ghost, holes, nholes);
            break;
        }
        case LIMEN_NODE_MESH: {
            const limen_mesh_geometry *g = d->mesh;
            for (int t = 0; g && t < g->triangle_count; t++) {
                double f[3][3];
                for (int c = 0; c < 3; c++) {
                    const float *pf = &g->positions[3 * g->indices[3 * t + c]];
                    double l[3] = { pf[0], pf[1], pf[2] };
                    opoint(m, l, f[c]);
                }
                ocut(o, d->node, (const double(*)[3])f, 3, ghost, holes, nholes);
            }
            break;
        }
        default: break;
        }
    }
}

/* Earliest root of a t^2 + b t + c = 0, or NAN. */
static double oroot(double a, double b, double c)
{
    if (!(fabs(a) > 1e-300))
        return NAN;
    double disc = b * b - 4 * a * c;
    if (disc < 0)
        return NAN;
    return (-b - sqrt(disc)) / (2 * a);
}

/* A polygon's normal as the sum of its edges' (Newell), so that clipping's nearly collinear
 * corners do not spoil it. */
static void onormal(const opiece *pc, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    for (int i = 0; i < pc->nv; i++) {
        const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
        n[0] += (a[1] * b[2] - a[2] * b[1]);
        n[1] += (a[2] * b[0] - a[0] * b[2]);
        n[2] += (a[0] * b[1] - a[1] * b[0]);
    }
}

/* Distance from p to a piece (for the start of an interval). */
static double odist(const double p[3], const opiece *pc)
{
    if (pc->ball) {
        double d[3] = { p[0] - pc->c[0], p[1] - pc->c[1], p[2] - pc->c[2] };
        return sqrt(odot(d, d)) - pc->r;    /* signed: inside a ball, moving in counts */
    }
    double n[3];
    onormal(pc, n);
    double ln = sqrt(odot(n, n)), best = INFINITY;
    if (ln > 0) {
        double sd = 0, f[3];
        for (int k = 0; k < 3; k++)
            sd += (p[k] - pc->v[0][k]) * n[k] / ln;
        for (int k = 0; k < 3; k++)
            f[k] = p[k] - sd * n[k] / ln;
        bool in = true;
        for (int i = 0; i < pc->nv; i++) {
            const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
            double e[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
            double w[3] = { f[0] - a[0], f[1] - a[1], f[2] - a[2] };
            double c[3] = { e[1] * w[2] - e[2] * w[1], e[2] * w[0] - e[0] * w[2],
                            e[0] * w[1] - e[1] * w[0] };
            in &= odot(c, n) >= 0;
        }
        if (in)
            return fabs(sd);
    }
    for (int i = 0; i < pc->nv; i++) {
        const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
        double e[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
        double w[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
        double t = odot(e, e) > 0 ? odot(w, e) / odot(e, e) : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double q[3] = { a[0] + t * e[0] - p[0], a[1] + t * e[1] - p[1], a[2] + t * e[2] - p[2] };
        best = fmin(best, sqrt(odot(q, q)));
    }
    return best;
}

/* The first time the sphere c0 + t v of radius r touches the piece (Fauerby: the face's
 * plane with the foot inside, each edge's line within the edge, each vertex), over all t. */
static double oentry(const double c0[3], const double v[3], double r, const opiece *pc)
{
    if (pc->ball) {
        double w[3] = { c0[0] - pc->c[0], c0[1] - pc->c[1], c0[2] - pc->c[2] };
        double R = r + pc->r;
        return oroot(odot(v, v), 2 * odot(w, v), odot(w, w) - R * R);
    }
    double best = INFINITY, n[3];
    onormal(pc, n);
    double ln = sqrt(odot(n, n));
    if (ln > 1e-300) {
        for (int k = 0; k < 3; k++)
            n[k] /= ln;
        double sd0 = 0, nv = odot(n, v);
        for (int k = 0; k < 3; k++)
            sd0 += (c0[k] - pc->v[0][k]) * n[k];
        if (fabs(nv) > 1e-300) {
            double t = fmin((r - sd0) / nv, (-r - sd0) / nv), f[3];
            double sdt = sd0 + t * nv;
            for (int k = 0; k < 3; k++)
                f[k] = c0[k] + t * v[k] - sdt * n[k];
            bool in = true;
            for (int i = 0; i < pc->nv; i++) {
                const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
                double e[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
                double w[3] = { f[0] - a[0], f[1] - a[1], f[2] - a[2] };
                double c[3] = { e[1] * w[2] - e[2] * w[1], e[2] * w[0] - e[0] * w[2],
                                e[0] * w[1] - e[1] * w[0] };
                in &= odot(c, n) >= 0;
            }
            if (in)
                best = t;
        }
    }
    for (int i = 0; i < pc->nv; i++) {
        const double *p = pc->v[i], *q = pc->v[(i + 1) % pc->nv];
        double e[3] = { q[0] - p[0], q[1] - p[1], q[2] - p[2] };
        double w0[3] = { c0[0] - p[0], c0[1] - p[1], c0[2] - p[2] };
        double ee = odot(e, e), ev = odot(e, v), ew = odot(e, w0);
        double t = oroot(ee * odot(v, v) - ev * ev, 2 * (ee * odot(w0, v) - ew * ev),
                         ee * (odot(w0, w0) - r * r) - ew * ew);
        if (t == t) {
            double f = (ew + t * ev) / ee;
            if (f >= 0 && f <= 1)
                best = fmin(best, t);
        }
        double tv = oroot(odot(v, v), 2 * odot(w0, v), odot(w0, w0) - r * r);
        if (tv == tv)
            best = fmin(best, tv);
    }
    return best;
}

/* The piece's contact on [ta, tb] by the rule: touching at ta counts if moving in. */
static double ocontact(const double c0[3], const double v[3], double r, const opiece *pc,
                       double ta, double tb)
{
    double p[3], q[3];
    for (int k = 0; k < 3; k++) {
        p[k] = c0[k] + ta * v[k];
        q[k] = c0[k] + (ta + 1e-7) * v[k];
    }
    double d0 = odist(p, pc);
    if (d0 <= r)
        return odist(q, pc) < d0 ? ta : NAN;
    double t = oentry(c0, v, r, pc);
    return t >= ta && t <= tb ? t : NAN;
}

static void ogate_make(limen_scene *s, const limen_drawable *d, const limen_drawable *pd,
                       double reach, ogate *g)
{
    const float *m = d->world, *pm = pd->world;
    g->node = d->node;
    /* X = W_B R_y(180) S(k) W_A^-1 in double (the float limen_surface_matrix would move a
     * carried body by a few 1e-7) */
    double wa[16], wb[16], wai[16], mid[16];
    for (int i = 0; i < 16; i++) {
        wa[i] = m[i];
        wb[i] = pm[i];
    }
    dinvert(wa, wai);
    double ks = (double)pd->dims[0] / d->dims[0];
    const double flip[16] = { -ks, 0, 0, 0, 0, ks, 0, 0, 0, 0, -ks, 0, 0, 0, 0, 1 };
    dmul(wb, flip, mid);
    dmul(mid, wai, g->x);
    g->k = sqrt(g->x[0] * g->x[0] + g->x[1] * g->x[1] + g->x[2] * g->x[2]);
    const float *ms[2] = { m, pm };
    const float *dims[2] = { d->dims, pd->dims };
    for (int e = 0; e < 2; e++) {
        double o[3] = { ms[e][12], ms[e][13], ms[e][14] };
        double ax[3] = { ms[e][0], ms[e][1], ms[e][2] }, ay[3] = { ms[e][4], ms[e][5], ms[e][6] };
        double az[3] = { ms[e][8], ms[e][9], ms[e][10] };
        double lx = sqrt(odot(ax, ax)), ly = sqrt(odot(ay, ay));
        double sgn = e == 0 ? 1 : -1;      /* the entry's prism outside; the partner's inside */
        double pts[4][3], nrm[4][3];
        for (int k = 0; k < 3; k++) {
            pts[0][k] = o[k] + 0.5 * dims[e][0] * ax[k];
            pts[1][k] = o[k] - 0.5 * dims[e][0] * ax[k];
            pts[2][k] = o[k] + 0.5 * dims[e][1] * ay[k];
            pts[3][k] = o[k] - 0.5 * dims[e][1] * ay[k];
            nrm[0][k] = sgn * ax[k] / lx;
            nrm[1][k] = -sgn * ax[k] / lx;
            nrm[2][k] = sgn * ay[k] / ly;
            nrm[3][k] = -sgn * ay[k] / ly;
        }
        for (int i = 0; i < 4; i++)
            mkplane(nrm[i], pts[i], e == 0 ? g->side[i] : g->pside[i]);
        mkplane(az, o, e == 0 ? g->plane : g->pside[4]);
        if (e == 0) {       /* the prism's back, as deep as the body reaches */
            double laz = sqrt(odot(az, az)), naz[3], deep[3];
            for (int k = 0; k < 3; k++) {
                naz[k] = -az[k];
                deep[k] = o[k] - reach * az[k] / laz;
            }
            mkplane(naz, deep, g->side[4]);
        }
    }
}

/* o = a b (column-major 4x4). */
static void dmul(const double *a, const double *b, double *o)
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            o[c * 4 + r] = 0;
            for (int k = 0; k < 4; k++)
                o[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
        }
}

/* Inverse of an affine matrix (3x3 part by cofactors, then the translation). */
static void dinvert(const double *m, double *o)
{
    double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
           i = m[10];
    double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    double r[9] = { (e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                    (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                    (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det };
    memset(o, 0, sizeof(double) * 16);
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++)
            o[col * 4 + row] = r[row * 3 + col];
        o[12 + row] = -(r[row * 3] * m[12] + r[row * 3 + 1] * m[13] + r[row * 3 + 2] * m[14]);
    }
    o[15] = 1;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct oresult {
    bool hit;
    double t;
    int portals;
    limen_node node;
} oresult;

/* The oracle's sweep of a sphere: everything brute force, contacts in closed form. */
static oresult osweep(limen_scene *s, limen_drawables *dl, const float from[3], const float to[3],
                      float radius, oscene *os)
{
    oresult res = { 0 };
    const limen_drawable *items;
    CHECK_OK(limen_drawables_build(dl, s));
    int count = limen_drawables_items(dl, &items);
    double c0[3], v[3], r = radius, t0 = 0;
    for (int k = 0; k < 3; k++) {
        c0[k] = from[k];
        v[k] = (double)to[k] - from[k];
    }
    for (int guard = 0; guard < 64; guard++) {
        ogate gates[32];
        int ng = 0, cross = -1;
        double tp = 1;
        for (int i = 0; i < count && ng < 32; i++) {
            if (!oopen(s, &items[i], res.portals))
                continue;
            int pi = limen_drawables_find(dl, limen_portal_get_partner(s, items[i].node));
            ogate_make(s, &items[i], &items[pi], r, &gates[ng]);
            /* crossing the rectangle from the front */
            double p0[3], p1[3];
            for (int k = 0; k < 3; k++) {
                p0[k] = c0[k] + t0 * v[k];
                p1[k] = c0[k] + v[k];
            }
            double d0 = pdist(gates[ng].plane, p0), d1 = pdist(gates[ng].plane, p1);
            if (d0 > 0 && d1 <= 0) {
                double f = d0 / (d0 - d1), t = t0 + f * (1 - t0), h[3];
                for (int k = 0; k < 3; k++)
                    h[k] = p0[k] + f * (p1[k] - p0[k]);
                bool in = true;
                for (int k = 0; k < 4; k++)
                    in &= pdist(gates[ng].side[k], h) <= 1e-9;
                if (in && t < tp) {
                    tp = t;
                    cross = ng;
                }
            }
            ng++;
        }
        double t1 = cross >= 0 ? tp : 1, cuts[40];
        int nc = 0;
        cuts[nc++] = t0;
        for (int i = 0; i < ng; i++) {
            double p0[3], p1[3];
            for (int k = 0; k < 3; k++) {
                p0[k] = c0[k] + t0 * v[k];
                p1[k] = c0[k] + t1 * v[k];
            }
            double d0 = pdist(gates[i].plane, p0), d1 = pdist(gates[i].plane, p1);
            if ((d0 > 1e-7 && d1 < -1e-7) || (d0 < -1e-7 && d1 > 1e-7))
                cuts[nc++] = t0 + (t1 - t0) * d0 / (d0 - d1);
        }
        qsort(cuts + 1, (size_t)(nc - 1), sizeof *cuts, cmpd);
        cuts[nc++] = t1;
        for (int c = 0; c + 1 < nc; c++) {
            double ta = cuts[c], tb = cuts[c + 1], mid[3];
            for (int k = 0; k < 3; k++)
                mid[k] = c0[k] + 0.5 * (ta + tb) * v[k];
            ogate *front[32];
            int nf = 0;
            for (int i = 0; i < ng; i++)
                if (pdist(gates[i].plane, mid) > 0)
                    front[nf++] = &gates[i];
            ogather(s, items, count, res.portals, NULL, front, nf, os);
            for (int i = 0; i < os->n; i++) {
                double t = ocontact(c0, v, r, &os->p[i], ta, tb);
                if (t == t && (!res.hit || t < res.t)) {
                    res.hit = true;
                    res.t = t;
                    res.node = os->p[i].node;
                }
            }
            for (int g = 0; g < nf; g++) {
                double gc[3], gv[3];
                dpoint(front[g]->x, c0, gc);
                dvec(front[g]->x, v, gv);
                ogather(s, items, count, res.portals, front[g], NULL, 0, os);
                for (int i = 0; i < os->n; i++) {
                    double t = ocontact(gc, gv, r * front[g]->k, &os->p[i], ta, tb);
                    if (t == t && os->p[i].ball) {  /* a ball counts where it touches in */
                        double at[3], dd[3], l;
                        for (int k = 0; k < 3; k++) {
                            at[k] = gc[k] + t * gv[k];
                            dd[k] = at[k] - os->p[i].c[k];
                        }
                        l = sqrt(odot(dd, dd));
                        bool in = l > 0;
                        for (int k = 0; k < 3; k++)
                            at[k] = os->p[i].c[k] + os->p[i].r * dd[k] / l;
                        for (int k = 0; k < 5; k++)
                            in &= pdist(front[g]->pside[k], at) >= 0;
                        if (!in)
                            continue;
                    }
                    if (t == t && (!res.hit || t < res.t)) {
                        res.hit = true;
                        res.t = t;
                        res.node = os->p[i].node;
                    }
                }
            }
            if (res.hit)
                return res;
        }
        if (cross < 0)
            return res;
        dpoint(gates[cross].x, c0, c0);
        dvec(gates[cross].x, v, v);
        r *= gates[cross].k;
        res.portals++;
        t0 = tp;
    }
    return res;
}

/* Whether a sphere at p clears every piece of the scene (uncut) by 1e-6. */
static bool clear_start(limen_scene *s, limen_drawables *dl, const float p[3], float r,
                        oscene *os)
{
    const limen_drawable *items;
    CHECK_OK(limen_drawables_build(dl, s));
    int count = limen_drawables_items(dl, &items);
    ogather(s, items, count, 0, NULL, NULL, 0, os);
    double c[3] = { p[0], p[1], p[2] };
    for (int i = 0; i < os->n; i++)
        if (odist(c, &os->p[i]) <= r + 1e-6)
            return false;
    return true;
}

/* A random scene: boxes, balls, planes, a mirror, a mesh, a wall with a portal a millimetre
 * in front, a tilted pair on a moving group and an unequal pair. */
static limen_scene *random_scene(limen_node *mover)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node n;
    for (int i = 0; i < 8; i++) {
        n = make(s, LIMEN_NODE_BOX, NULL, (float)rnd_in(-5, 5), (float)rnd_in(-5, 5),
                 (float)rnd_in(-5, 5), (float)rnd_in(0.2, 3), (float)rnd_in(0.2, 3),
                 (float)rnd_in(0.2, 3));
        CHECK_OK(limen_node_set_rotation(s, n, (float[3]){ (float)rnd_in(-3, 3),
                                         (float)rnd_in(-3, 3), (float)rnd_in(-3, 3) }));
    }
    for (int i = 0; i < 5; i++)
        make(s, LIMEN_NODE_SPHERE, NULL, (float)rnd_in(-5, 5), (float)rnd_in(-5, 5),
             (float)rnd_in(-5, 5), (float)rnd_in(0.2, 1.5), 0, 0);
    for (int i = 0; i < 3; i++) {
        n = make(s, i ? LIMEN_NODE_QUAD : LIMEN_NODE_MIRROR, NULL, (float)rnd_in(-5, 5),
                 (float)rnd_in(-5, 5), (float)rnd_in(-5, 5), (float)rnd_in(0.5, 4),
                 (float)rnd_in(0.5, 4), 0);
        face(s, n, (float)rnd_in(-1, 1), (float)rnd_in(-1, 1), (float)rnd_in(0.1, 1));
    }
    /* a bumpy sheet of 2 x 6 x 6 triangles */
    float pos[49 * 3];
    uint32_t idx[72 * 3];
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < 7; i++) {
            pos[3 * (j * 7 + i)] = (float)(i - 3);
            pos[3 * (j * 7 + i) + 1] = (float)rnd_in(-0.5, 0.5);
            pos[3 * (j * 7 + i) + 2] = (float)(j - 3);
        }
    int t = 0;
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++) {
            uint32_t a = (uint32_t)(j * 7 + i), b = a + 1, c = a + 7, d = a + 8;
            uint32_t tri[6] = { a, c, b, b, c, d };
            memcpy(&idx[3 * t], tri, sizeof tri);
            t += 2;
        }
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "sheet", &n));
    CHECK_OK(limen_mesh_set_triangles(s, n, &(limen_mesh_data){ .positions = pos,
                                      .vertex_count = 49, .indices = idx, .triangle_count = 72 }));
    CHECK_OK(limen_node_set_position(s, n, (float[3]){ (float)rnd_in(-3, 3), (float)rnd_in(-4, 4),
                                     (float)rnd_in(-3, 3) }));
    CHECK_OK(limen_node_set_rotation(s, n, (float[3]){ (float)rnd_in(-1, 1), (float)rnd_in(-3, 3),
                                     0 }));
    CHECK_OK(limen_node_set_scale(s, n, (float[3]){ 1.3f, 1.3f, 1.3f }));
    /* a wall with a portal in front of it; its partner tilted on a moving group */
    float wz = (float)rnd_in(-4, -2);
    make(s, LIMEN_NODE_BOX, "wall", 0, 0, wz - 0.1f, 6, 6, 0.2f);
    limen_node a = make(s, LIMEN_NODE_PORTAL, "a", (float)rnd_in(-1, 1), (float)rnd_in(-1, 1),
                        wz + 0.001f, 2, 2.5f, 0);
    *mover = make(s, LIMEN_NODE_GROUP, "mover", 0, 0, 0, 0, 0, 0);
    limen_node b = make(s, LIMEN_NODE_PORTAL, "b", (float)rnd_in(-3, 3), (float)rnd_in(-3, 3),
                        (float)rnd_in(2, 4), 2, 2.5f, 0);
    face(s, b, (float)rnd_in(-1, 1), (float)rnd_in(-1, 1), (float)rnd_in(-1, -0.2));
    CHECK_OK(limen_node_set_parent(s, b, *mover));
    CHECK_OK(limen_portal_link(s, a, b));
    /* an unequal pair: twice as wide out as in */
    limen_node c = make(s, LIMEN_NODE_PORTAL, "c", (float)rnd_in(-4, 4), (float)rnd_in(-4, 4),
                        (float)rnd_in(-4, 4), 1.5f, 1.5f, 0);
    face(s, c, (float)rnd_in(-1, 1), (float)rnd_in(-1, 1), (float)rnd_in(-1, 1));
    limen_node d = make(s, LIMEN_NODE_PORTAL, "d", (float)rnd_in(-4, 4), (float)rnd_in(-4, 4),
                        (float)rnd_in(-4, 4), 3, 3, 0);
    face(s, d, (float)rnd_in(-1, 1), (float)rnd_in(-1, 1), (float)rnd_in(-1, 1));
    CHECK_OK(limen_portal_link(s, c, d));
    return s;
}

/* 10,000 random sweeps against the oracle: the same hit, contact fraction within 1e-4,
 * the same portals passed. */
static void test_oracle(void)
{
    rng_state = 12345;
    int sweeps = 0, hits = 0, through = 0, bad = 0;
    oscene os = { 0 };
    limen_drawables *dl;
    CHECK_OK(limen_drawables_create(&dl));
    for (int sc = 0; sc < 20; sc++) {
        limen_node mover;
        limen_scene *s = random_scene(&mover);
        for (int i = 0; i < 500; i++, sweeps++) {
            if (i % 10 == 0)
                CHECK_OK(limen_node_set_position(s, mover, (float[3]){ (float)rnd_in(-1, 1),
                                                 (float)rnd_in(-1, 1), (float)rnd_in(-1, 1) }));
            float from[3], to[3], r = (float)rnd_in(0.05, 1.0);
            redraw:
            double len = rnd_in(0.1, 12);
            double way[3] = { rnd_in(-1, 1), rnd_in(-1, 1), rnd_in(-1, 1) };
            double l = sqrt(odot(way, way));
            for (int k = 0; k < 3; k++) {
                from[k] = (float)rnd_in(-6, 6);
                to[k] = (float)(from[k] + len * way[k] / l);
            }
            if (rnd() < 0.4) {      /* aimed at a portal's opening, from its front */
                static const char *const names[4] = { "a", "b", "c", "d" };
                limen_node pn;
                float w[16];
                CHECK_OK(limen_node_find(s, names[(int)(rnd() * 4) & 3], &pn));
                CHECK_OK(limen_node_world_matrix(s, pn, w));
                double u = rnd_in(-0.7, 0.7), v = rnd_in(-0.7, 0.7), f = rnd_in(0.05, 3);
                double u2 = rnd_in(-0.5, 0.5), v2 = rnd_in(-0.5, 0.5), b = rnd_in(0.1, 5);
                for (int k = 0; k < 3; k++) {
                    from[k] = (float)(w[12 + k] + u * w[k] + v * w[4 + k] + f * w[8 + k]);
                    to[k] = (float)(w[12 + k] + u2 * w[k] + v2 * w[4 + k] - b * w[8 + k]);
                }
            }
            /* start clear of everything: touching at the start is decided piece by
             * piece (moving in or not), which depends on how holes cut the pieces */
            if (!clear_start(s, dl, from, r, &os))
                goto redraw;
            limen_sweep_result got;
            CHECK_OK(limen_sweep_sphere(s, from, to, r, NULL, &got));
            oresult want = osweep(s, dl, from, to, r, &os);
            hits += want.hit;
            through += want.portals > 0;
            bool same = got.hit == want.hit && got.portals == want.portals &&
                        (!want.hit || fabs(got.fraction - want.t) <= 1e-4);
            if (!same && bad++ < 10)
                fprintf(stderr, "  scene %d sweep %d: got hit %d at %.7f (%d portals), oracle %d "
                        "at %.7f (%d portals)\n", sc, i, got.hit, (double)got.fraction,
                        got.portals, want.hit, want.t, want.portals),
                fprintf(stderr, "    from %.9g %.9g %.9g to %.9g %.9g %.9g r %.9g: %s / %s, "
                        "portal %s\n",
                        from[0], from[1], from[2], to[0], to[1], to[2], r,
                        got.node.id ? limen_node_get_name(s, got.node) : "-",
                        want.node.id ? limen_node_get_name(s, want.node) : "-",
                        got.portal.id ? limen_node_get_name(s, got.portal) : "-");
        }
        limen_scene_destroy(s);
    }
    limen_drawables_destroy(dl);
    free(os.p);
    printf("     oracle: %d sweeps, %d hits, %d through portals, %d differ\n", sweeps, hits,
           through, bad);
    CHECK(bad == 0);
    CHECK(hits > sweeps / 4 && through > sweeps / 50);
}

/* Distance between segments p0-p1 and q0-q1, by minimising over one parameter after
 * the other (the distance is convex in each): the test's own, not the library's. */
static double oseg_seg(const double p0[3], const double p1[3], const double q0[3],
                       const double q1[3])
{
    double best = INFINITY;
    double d1[3], d2[3];
    for (int k = 0; k < 3; k++) {
        d1[k] = p1[k] - p0[k];
        d2[k] = q1[k] - q0[k];
    }
    /* the end points against the other segment, and the interior stationary point */
    const double *pe[2] = { p0, p1 }, *qe[2] = { q0, q1 };
    for (int e = 0; e < 2; e++) {
        for (int side = 0; side < 2; side++) {
            const double *a = side ? qe[e] : pe[e], *o = side ? p0 : q0, *dd = side ? d1 : d2;
            double w[3] = { a[0] - o[0], a[1] - o[1], a[2] - o[2] }, l2 = odot(dd, dd);
            double t = l2 > 0 ? odot(w, dd) / l2 : 0;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            double q[3] = { o[0] + t * dd[0] - a[0], o[1] + t * dd[1] - a[1],
                            o[2] + t * dd[2] - a[2] };
            best = fmin(best, sqrt(odot(q, q)));
        }
    }
    double a = odot(d1, d1), b = odot(d1, d2), c = odot(d2, d2);
    double r[3] = { p0[0] - q0[0], p0[1] - q0[1], p0[2] - q0[2] };
    double dd = odot(d1, r), e = odot(d2, r), den = a * c - b * b;
    if (den > 1e-12 * a * c) {
        double sp = (b * e - c * dd) / den, tq = (a * e - b * dd) / den;
        if (sp >= 0 && sp <= 1 && tq >= 0 && tq <= 1) {
            double q[3];
            for (int k = 0; k < 3; k++)
                q[k] = p0[k] + sp * d1[k] - q0[k] - tq * d2[k];
            best = fmin(best, sqrt(odot(q, q)));
        }
    }
    return best;
}

/* Distance from segment a-b to a piece (0 where it passes through a polygon). */
static double oseg_piece(const double a[3], const double b[3], const opiece *pc)
{
    if (pc->ball) {
        double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
        double w[3] = { pc->c[0] - a[0], pc->c[1] - a[1], pc->c[2] - a[2] };
        double l2 = odot(ab, ab), t = l2 > 0 ? odot(w, ab) / l2 : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double q[3] = { a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2] };
        return odist(q, pc);
    }
    double n[3];
    onormal(pc, n);
    double ln = sqrt(odot(n, n));
    if (ln > 0) {
        double da = 0, db = 0;
        for (int k = 0; k < 3; k++) {
            da += (a[k] - pc->v[0][k]) * n[k] / ln;
            db += (b[k] - pc->v[0][k]) * n[k] / ln;
        }
        if ((da <= 0) != (db <= 0)) {
            double t = da / (da - db), x[3];
            for (int k = 0; k < 3; k++)
                x[k] = a[k] + t * (b[k] - a[k]);
            if (odist(x, pc) < 1e-12)
                return 0;
        }
    }
    double best = fmin(odist(a, pc), odist(b, pc));
    for (int i = 0; i < pc->nv; i++)
        best = fmin(best, oseg_seg(a, b, pc->v[i], pc->v[(i + 1) % pc->nv]));
    return best;
}

static double ocapsule_dist(const oscene *os, const double a[3], const double b[3])
{
    double best = INFINITY;
    for (int i = 0; i < os->n; i++)
        best = fmin(best, oseg_piece(a, b, &os->p[i]));
    return best;
}

/* Capsules, checked by distance (no portals here: they are hidden): 400 random sweeps in
 * the random scenes; at the reported contact the capsule is its radius from the nearest
 * piece, and at 40 times before it (or over the whole path, for a miss) no nearer. */
static void test_capsule_oracle(void)
{
    rng_state = 4242;
    oscene os = { 0 };
    limen_drawables *dl;
    CHECK_OK(limen_drawables_create(&dl));
    int sweeps = 0, hits = 0, bad = 0;
    for (int sc = 0; sc < 4; sc++) {
        limen_node mover, p;
        limen_scene *s = random_scene(&mover);
        static const char *const names[4] = { "a", "b", "c", "d" };
        for (int k = 0; k < 4; k++) {
            CHECK_OK(limen_node_find(s, names[k], &p));
            CHECK_OK(limen_node_set_visible(s, p, 0));
        }
        const limen_drawable *items;
        CHECK_OK(limen_drawables_build(dl, s));
        int count = limen_drawables_items(dl, &items);
        ogather(s, items, count, 0, NULL, NULL, 0, &os);
        for (int i = 0; i < 100; i++, sweeps++) {
            double a[3], b[3], d[3], r;
            do {
                r = rnd_in(0.05, 0.6);
                double len = rnd_in(0, 2), move = rnd_in(0.1, 8);
                double u[3] = { rnd_in(-1, 1), rnd_in(-1, 1), rnd_in(-1, 1) };
                double m[3] = { rnd_in(-1, 1), rnd_in(-1, 1), rnd_in(-1, 1) };
                double lu = sqrt(odot(u, u)), lm = sqrt(odot(m, m));
                for (int k = 0; k < 3; k++) {
                    a[k] = (float)rnd_in(-6, 6);
                    b[k] = (float)(a[k] + len * u[k] / lu);
                    d[k] = (float)(move * m[k] / lm);
                }
            } while (ocapsule_dist(&os, a, b) <= r + 1e-6);
            float fa[3] = { (float)a[0], (float)a[1], (float)a[2] };
            float fb[3] = { (float)b[0], (float)b[1], (float)b[2] };
            float fd[3] = { (float)d[0], (float)d[1], (float)d[2] };
            limen_sweep_result got;
            CHECK_OK(limen_sweep_capsule(s, fa, fb, (float)r, fd, NULL, &got));
            hits += got.hit;
            double f = got.hit ? got.fraction : 1;
            bool ok = true;
            for (int j = 0; j < 40 && ok; j++) {
                double t = (f - 1e-5) * j / 39.0, pa[3], pb[3];
                for (int k = 0; k < 3; k++) {
                    pa[k] = a[k] + t * d[k];
                    pb[k] = b[k] + t * d[k];
                }
                ok = ocapsule_dist(&os, pa, pb) > r - 1e-6;
            }
            if (got.hit) {
                double pa[3], pb[3];
                for (int k = 0; k < 3; k++) {
                    pa[k] = a[k] + f * d[k];
                    pb[k] = b[k] + f * d[k];
                }
                ok &= fabs(ocapsule_dist(&os, pa, pb) - r) < 1e-5;
            }
            if (!ok && bad++ < 5)
                fprintf(stderr, "  scene %d capsule %d: hit %d at %.7f disagrees\n", sc, i,
                        got.hit, f);
        }
        limen_scene_destroy(s);
    }
    limen_drawables_destroy(dl);
    free(os.p);
    printf("     capsules: %d sweeps, %d hits, %d disagree\n", sweeps, hits, bad);
    CHECK(bad == 0 && hits > sweeps / 5);
}

/* ------------------------------------------------------------------ rooms */

/* A closed room 10 x 4 x 10 of thin walls (0.02), with two pillars; a portal pair joins the
 * west and east walls and another the floor and the ceiling (a millimetre in front of each):
 * whatever passes one comes back into the same room. */
static limen_scene *loop_room(limen_node pillars[2])
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    make(s, LIMEN_NODE_BOX, "floor", 0, -0.01f, 0, 10.04f, 0.02f, 10.04f);
    make(s, LIMEN_NODE_BOX, "ceiling", 0, 4.01f, 0, 10.04f, 0.02f, 10.04f);
    make(s, LIMEN_NODE_BOX, "west", -5.01f, 2, 0, 0.02f, 4, 10.04f);
    make(s, LIMEN_NODE_BOX, "east", 5.01f, 2, 0, 0.02f, 4, 10.04f);
    make(s, LIMEN_NODE_BOX, "north", 0, 2, -5.01f, 10.04f, 4, 0.02f);
    make(s, LIMEN_NODE_BOX, "south", 0, 2, 5.01f, 10.04f, 4, 0.02f);
    pillars[0] = make(s, LIMEN_NODE_BOX, "p0", 2, 2, 2, 1, 4, 1);
    pillars[1] = make(s, LIMEN_NODE_CYLINDER, "p1", -2, 0, -2, 0.6f, 4, 0);
    limen_node w = make(s, LIMEN_NODE_PORTAL, "w", -4.999f, 1.5f, 1, 2, 2.5f, 0);
    face(s, w, 1, 0, 0);
    limen_node e = make(s, LIMEN_NODE_PORTAL, "e", 4.999f, 1.5f, -1, 2, 2.5f, 0);
    face(s, e, -1, 0, 0);
    CHECK_OK(limen_portal_link(s, w, e));
    limen_node f = make(s, LIMEN_NODE_PORTAL, "f", 0, 0.001f, -2, 2, 2, 0);
    face(s, f, 0, 1, 0);
    limen_node c = make(s, LIMEN_NODE_PORTAL, "c", 0, 3.999f, 2, 2, 2, 0);
    face(s, c, 0, -1, 0);
    CHECK_OK(limen_portal_link(s, f, c));
    return s;
}

static bool in_room(const float p[3])
{
    return p[0] > -5 && p[0] < 5 && p[1] > 0 && p[1] < 4 && p[2] > -5 && p[2] < 5;
}

/* Distance from p to the pillars (a box at (2, *, 2) of 1 x 1; a cylinder of 0.6 at (-2, -2)). */
static double pillar_dist(const float p[3])
{
    double dx = fmax(fabs(p[0] - 2) - 0.5, 0), dz = fmax(fabs(p[2] - 2) - 0.5, 0);
    double d0 = sqrt(dx * dx + dz * dz);
    double d1 = sqrt((p[0] + 2) * (p[0] + 2) + (p[2] + 2) * (p[2] + 2)) - 0.6;
    return fmin(d0, d1);
}

/* 100,000 fast slides (up to 60 units, three times the room, in one step): the body never
 * leaves the room nor enters a pillar. */
static void test_no_tunnelling(void)
{
    limen_node pillars[2];
    limen_scene *s = loop_room(pillars);
    limen_node body = make(s, LIMEN_NODE_SPHERE, "body", -3, 2, 3, 0.25f, 0, 0);
    rng_state = 777;
    int out = 0, inside = 0, crossed = 0;
    for (int i = 0; i < 100000; i++) {
        double len = rnd_in(0, 60), way[3] = { rnd_in(-1, 1), rnd_in(-1, 1), rnd_in(-1, 1) };
        double l = sqrt(odot(way, way));
        float d[3];
        for (int k = 0; k < 3; k++)
            d[k] = (float)(len * way[k] / l);
        float w[16];
        CHECK_OK(limen_node_world_matrix(s, body, w));
        float rad = 0.25f * sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        limen_slide_result r;
        CHECK_OK(limen_node_slide(s, body, d, rad, &r));
        crossed += r.crossed;
        CHECK_OK(limen_node_world_matrix(s, body, w));
        float p[3] = { w[12], w[13], w[14] };
        if (!in_room(p) && out++ < 5)
            fprintf(stderr, "  step %d: out of the room at %g %g %g\n", i, p[0], p[1], p[2]);
        if (pillar_dist(p) < 0.25 - 1e-3 && inside++ < 5)
            fprintf(stderr, "  step %d: in a pillar at %g %g %g\n", i, p[0], p[1], p[2]);
    }
    printf("     no tunnelling: 100000 slides, %d portals passed\n", crossed);
    CHECK(out == 0 && inside == 0);
    CHECK(crossed > 500);
    limen_scene_destroy(s);
}

/* A ball bounced for 100,000 steps (reflected at each contact, its velocity carried through
 * the portals) never leaves its room. */
static void test_bounce_loop(void)
{
    limen_node pillars[2];
    limen_scene *s = loop_room(pillars);
    limen_node ball = make(s, LIMEN_NODE_SPHERE, "ball", 0, 2, 0, 0.3f, 0, 0);
    double vel[3] = { 3.1, -2.3, 1.7 };
    const float dt = 0.05f;
    int out = 0, crossed = 0, bounces = 0;
    limen_sweep_opts o = { .ignore = ball };
    for (int i = 0; i < 100000; i++) {
        float w[16];
        CHECK_OK(limen_node_world_matrix(s, ball, w));
        float p[3] = { w[12], w[13], w[14] }, to[3];
        for (int k = 0; k < 3; k++)
            to[k] = p[k] + dt * (float)vel[k];
        limen_sweep_result r;
        CHECK_OK(limen_sweep_sphere(s, p, to, 0.3f, &o, &r));
        double f = r.fraction;
        if (r.hit) {
            double back = 1e-4 / (dt * sqrt(vel[0] * vel[0] + vel[1] * vel[1] + vel[2] * vel[2]));
            f = fmax(0, f - back);
        }
        float step[3];
        for (int k = 0; k < 3; k++)
            step[k] = (float)(f * dt * vel[k]);
        limen_move_result mr;
        CHECK_OK(limen_node_move(s, ball, step, &mr));
        crossed += mr.crossed;
        if (mr.crossed) {
            double v2[3];
            for (int k = 0; k < 3; k++)
                v2[k] = mr.matrix[k] * vel[0] + mr.matrix[4 + k] * vel[1] +
                        mr.matrix[8 + k] * vel[2];
            memcpy(vel, v2, sizeof v2);
        }
        if (r.hit && r.portals == mr.crossed) {
            double vn = vel[0] * r.normal[0] + vel[1] * r.normal[1] + vel[2] * r.normal[2];
            if (vn < 0)
                for (int k = 0; k < 3; k++)
                    vel[k] -= 2 * vn * r.normal[k];
            bounces++;
        }
        CHECK_OK(limen_node_world_matrix(s, ball, w));
        float q[3] = { w[12], w[13], w[14] };
        if (!in_room(q) && out++ < 5)
            fprintf(stderr, "  step %d: out of the room at %g %g %g\n", i, q[0], q[1], q[2]);
    }
    printf("     bounce: 100000 steps, %d bounces, %d portals passed\n", bounces, crossed);
    CHECK(out == 0);
    CHECK(crossed > 100 && bounces > 100);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "known", test_known },
    { "refuse", test_refuse },
    { "hole", test_hole },
    { "both_sides", test_both_sides },
    { "twice", test_twice },
    { "many_holes", test_many_holes },
    { "unequal", test_unequal },
    { "mesh", test_mesh },
    { "big_mesh", test_big_mesh },
    { "slide", test_slide },
    { "lua", test_lua },
    { "oracle", test_oracle },
    { "capsule_oracle", test_capsule_oracle },
    { "no_tunnelling", test_no_tunnelling },
    { "bounce_loop", test_bounce_loop },
    { 0 }
};

int main(int argc, char **argv)
{
    return scratch_main(argc, argv, cases);
}
