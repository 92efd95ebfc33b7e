/* test_scene.c - the scene graph: handles, hierarchy, transforms, validation. No GL. */
#include <stdlib.h>

#include "check.h"
#include "limen.h"

static limen_scene *new_scene(void)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    return s;
}

/* Column-major M * (x, y, z, 1). */
static void xform(const float m[16], const float p[3], float out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
}

static void test_handles(void)
{
    limen_scene *s = new_scene();
    limen_node a, b;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "a", &a));
    CHECK(limen_node_valid(s, a));
    CHECK(limen_scene_node_count(s) == 1);
    CHECK_OK(limen_node_destroy(s, a));
    CHECK(!limen_node_valid(s, a));
    /* the slot is reused, but the old handle stays dead */
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "b", &b));
    CHECK(limen_node_valid(s, b) && !limen_node_valid(s, a));
    CHECK(limen_node_set_position(s, a, (float[3]){ 1, 2, 3 }) == LIMEN_ERR_HANDLE);
    CHECK(strstr(limen_last_error(s), "stale") != NULL);
    CHECK(limen_node_destroy(s, a) == LIMEN_ERR_HANDLE);
    CHECK(limen_node_set_position(s, (limen_node){ 0 }, (float[3]){ 1, 2, 3 }) ==
          LIMEN_ERR_HANDLE);
    CHECK(limen_node_set_position(s, (limen_node){ 0xFFFFFFFFu }, (float[3]){ 1, 2, 3 }) ==
          LIMEN_ERR_HANDLE);
    CHECK(limen_node_name(s, a) == NULL);
    CHECK(strcmp(limen_node_name(s, b), "b") == 0);
    limen_node found;
    CHECK_OK(limen_node_find(s, "b", &found));
    CHECK(found.id == b.id);
    CHECK(limen_node_find(s, "a", &found) != LIMEN_OK);
    CHECK(limen_node_create(s, (limen_node_kind)99, "x", &found) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

static void test_capacity(void)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ .max_nodes = 100 }, &s));
    limen_node n;
    for (int i = 0; i < 100; i++)
        CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, NULL, &n));
    CHECK(limen_node_create(s, LIMEN_NODE_GROUP, NULL, &n) == LIMEN_ERR_NOMEM);
    CHECK(n.id == 0);
    limen_scene_destroy(s);
}

static void test_hierarchy(void)
{
    limen_scene *s = new_scene();
    limen_node root, arm, hand;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "root", &root));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "arm", &arm));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "hand", &hand));
    /* hand created before its parent's parent is set: order must not matter */
    CHECK_OK(limen_node_set_parent(s, hand, arm));
    CHECK_OK(limen_node_set_parent(s, arm, root));
    CHECK_OK(limen_node_set_position(s, root, (float[3]){ 10, 0, 0 }));
    CHECK_OK(limen_node_set_rotation(s, root, (float[3]){ 0, (float)M_PI_2, 0 }));
    CHECK_OK(limen_node_set_position(s, arm, (float[3]){ 0, 0, 2 }));
    CHECK_OK(limen_node_set_scale(s, arm, (float[3]){ 2, 2, 2 }));
    CHECK_OK(limen_node_set_position(s, hand, (float[3]){ 1, 0, 0 }));
    float w[16], o[3];
    CHECK_OK(limen_node_world_matrix(s, hand, w));
    xform(w, (float[3]){ 0, 0, 0 }, o);
    /* root turns +Z to +X and +X to -Z: arm at (10+2, 0, 0), hand 2 units along -Z */
    CHECK_NEAR(o[0], 12, 1e-5);
    CHECK_NEAR(o[1], 0, 1e-5);
    CHECK_NEAR(o[2], -2, 1e-5);
    /* moving the root moves the hand */
    CHECK_OK(limen_node_set_position(s, root, (float[3]){ 0, 5, 0 }));
    CHECK_OK(limen_node_world_matrix(s, hand, w));
    xform(w, (float[3]){ 0, 0, 0 }, o);
    CHECK_NEAR(o[0], 2, 1e-5);
    CHECK_NEAR(o[1], 5, 1e-5);
    /* cycles are refused and leave the tree as it was */
    CHECK(limen_node_set_parent(s, root, hand) == LIMEN_ERR_CYCLE);
    CHECK(strstr(limen_last_error(s), "cycle") != NULL);
    CHECK(limen_node_set_parent(s, arm, arm) == LIMEN_ERR_CYCLE);
    CHECK(limen_node_get_parent(s, root).id == 0);
    /* destroying the middle node re-parents its child to the root */
    CHECK_OK(limen_node_destroy(s, arm));
    CHECK(limen_node_get_parent(s, hand).id == root.id);
    CHECK_OK(limen_node_set_parent(s, hand, (limen_node){ 0 }));
    CHECK(limen_node_get_parent(s, hand).id == 0);
    limen_scene_destroy(s);
}

static void test_rotation_order(void)
{
    /* rotate = {90, 90, 0} degrees: X first, then Y. +Y goes to +Z under X, then to +X
     * under Y. Applied in the other order it would go to -Z. */
    limen_scene *s = new_scene();
    limen_node n;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "n", &n));
    CHECK_OK(limen_node_set_rotation(s, n, (float[3]){ (float)M_PI_2, (float)M_PI_2, 0 }));
    float w[16], o[3];
    CHECK_OK(limen_node_world_matrix(s, n, w));
    xform(w, (float[3]){ 0, 1, 0 }, o);
    CHECK_NEAR(o[0], 1, 1e-6);
    CHECK_NEAR(o[1], 0, 1e-6);
    CHECK_NEAR(o[2], 0, 1e-6);
    limen_scene_destroy(s);
}

static void test_facing(void)
{
    limen_scene *s = new_scene();
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, "m", &m));
    float normal[3] = { 1, 0, 1 }, up[3] = { 0, 1, 0 };
    CHECK_OK(limen_node_set_facing(s, m, normal, up));
    float w[16];
    CHECK_OK(limen_node_world_matrix(s, m, w));
    /* local +Z is the normalised normal, local +Y is up, frame is right-handed */
    CHECK_NEAR(w[8], M_SQRT1_2, 1e-6);
    CHECK_NEAR(w[10], M_SQRT1_2, 1e-6);
    CHECK_NEAR(w[5], 1, 1e-6);
    float det = w[0] * (w[5] * w[10] - w[9] * w[6]) - w[4] * (w[1] * w[10] - w[9] * w[2]) +
                w[8] * (w[1] * w[6] - w[5] * w[2]);
    CHECK_NEAR(det, 1, 1e-6);
    /* a floor: normal +Y with no up given still makes a frame */
    CHECK_OK(limen_node_set_facing(s, m, (float[3]){ 0, 1, 0 }, NULL));
    CHECK_OK(limen_node_set_facing(s, m, (float[3]){ 0, -1, 0 }, NULL));
    CHECK(limen_node_set_facing(s, m, (float[3]){ 0, 0, 0 }, NULL) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_node_set_facing(s, m, (float[3]){ 0, 1, 0 }, (float[3]){ 0, 2, 0 }) ==
          LIMEN_ERR_DEGENERATE);
    CHECK(limen_node_set_facing(s, m, (float[3]){ NAN, 1, 0 }, NULL) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

static void test_look_at(void)
{
    limen_scene *s = new_scene();
    limen_node cam;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 3, 2, 1 }, (float[3]){ 0, 1, -4 },
                                (float[3]){ 0, 1, 0 }));
    float view[16], proj[16], o[3];
    CHECK_OK(limen_camera_matrices(s, 4.0f / 3.0f, LIMEN_DEPTH_NO, view, proj));
    xform(view, (float[3]){ 3, 2, 1 }, o);
    CHECK_NEAR(o[0], 0, 1e-5);
    CHECK_NEAR(o[1], 0, 1e-5);
    CHECK_NEAR(o[2], 0, 1e-5);
    xform(view, (float[3]){ 0, 1, -4 }, o);
    CHECK_NEAR(o[0], 0, 1e-5);
    CHECK_NEAR(o[1], 0, 1e-5);
    CHECK(o[2] < 0);
    CHECK(limen_node_look_at(s, cam, (float[3]){ 1, 1, 1 }, (float[3]){ 1, 1, 1 }, NULL) ==
          LIMEN_ERR_DEGENERATE);
    limen_node box;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "box", &box));
    CHECK(limen_scene_set_camera(s, box) == LIMEN_ERR_HANDLE);
    CHECK(limen_camera_set_lens(s, cam, 0, 0.1f, 10) == LIMEN_ERR_ARG);
    CHECK(limen_camera_set_lens(s, cam, 1, 0.1f, 0.05f) == LIMEN_ERR_ARG);
    CHECK(limen_camera_set_lens(s, cam, 1, -1, 10) == LIMEN_ERR_ARG);
    CHECK_OK(limen_camera_set_lens(s, cam, 1, 0.1f, 10));
    CHECK_OK(limen_node_destroy(s, cam));
    CHECK(limen_scene_get_camera(s).id == 0);
    CHECK(limen_camera_matrices(s, 1, LIMEN_DEPTH_NO, view, proj) != LIMEN_OK);
    CHECK(strstr(limen_last_error(s), "camera") != NULL);
    limen_scene_destroy(s);
}

static void test_validation(void)
{
    limen_scene *s = new_scene();
    limen_node b, l;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "b", &b));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "l", &l));
    CHECK(limen_node_set_dims(s, b, (float[3]){ -1, 0, 0 }) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_last_error(s), "positive") != NULL);
    CHECK(limen_node_set_dims(s, b, (float[3]){ NAN, 0, 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_dims(s, b, (float[3]){ INFINITY, 0, 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_dims(s, l, (float[3]){ 1, 1, 1 }) == LIMEN_ERR_ARG);
    CHECK_OK(limen_node_set_dims(s, b, (float[3]){ 2, 0, 0 }));
    float d[3];
    CHECK_OK(limen_node_get_dims(s, b, d));
    CHECK(d[0] == 2);
    CHECK(limen_node_set_color(s, b, (float[3]){ 1.5f, 0, 0 }) == LIMEN_ERR_ARG);
    CHECK_OK(limen_node_set_color(s, l, (float[3]){ 1.5f, 1.5f, 1.5f }));  /* intensity */
    CHECK(limen_node_set_scale(s, b, (float[3]){ 0, 1, 1 }) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_node_set_position(s, b, (float[3]){ 0, NAN, 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_position(s, b, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_scene_set_ambient(s, 1.5f) == LIMEN_ERR_ARG);
    CHECK(limen_scene_set_ambient(s, NAN) == LIMEN_ERR_ARG);
    CHECK(limen_scene_set_background(s, (float[3]){ 0, -1, 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_checker(s, b, (float[3]){ 1, 1, 1 }, (float[3]){ 0, 0, 0 }, -1) ==
          LIMEN_ERR_ARG);
    float sing[16] = { 0 };
    CHECK(limen_node_set_local_matrix(s, b, sing) == LIMEN_ERR_DEGENERATE);
    limen_scene_destroy(s);
    limen_scene_destroy(NULL);
    CHECK(limen_scene_create(NULL, NULL) == LIMEN_ERR_ARG);
}

static void test_local_matrix(void)
{
    limen_scene *s = new_scene();
    limen_node n;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "n", &n));
    float m[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 4, 5, 6, 1 }, w[16], p[3];
    CHECK_OK(limen_node_set_local_matrix(s, n, m));
    CHECK_OK(limen_node_world_matrix(s, n, w));
    CHECK(w[12] == 4 && w[13] == 5 && w[14] == 6);
    CHECK_OK(limen_node_get_position(s, n, p));
    CHECK(p[0] == 4 && p[1] == 5 && p[2] == 6);
    /* a TRS setter takes over again */
    CHECK_OK(limen_node_set_position(s, n, (float[3]){ 1, 1, 1 }));
    CHECK_OK(limen_node_world_matrix(s, n, w));
    CHECK(w[12] == 1 && w[13] == 1 && w[14] == 1);
    limen_scene_destroy(s);
}

static void test_overflowing_world(void)
{
    /* scales in range whose product overflows a float: refused by name, not rendered */
    limen_scene *s = new_scene();
    limen_node g[5], cam, ball;
    for (int i = 0; i < 5; i++) {
        CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, i == 4 ? "deepest" : NULL, &g[i]));
        CHECK_OK(limen_node_set_scale(s, g[i], (float[3]){ 1e9f, 1e9f, 1e9f }));
        if (i)
            CHECK_OK(limen_node_set_parent(s, g[i], g[i - 1]));
    }
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    CHECK_OK(limen_node_set_parent(s, ball, g[4]));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_scene_set_camera(s, cam));
    limen_plan *p;
    CHECK_OK(limen_plan_create(&p));
    CHECK(limen_plan_build(p, s, NULL) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_last_error(s), "group 'deepest': its world transform is not finite"));
    limen_hit h;
    CHECK(limen_ray_cast(s, (float[3]){ 0, 0, 0 }, (float[3]){ 0, 0, -1 }, -1, &h) ==
          LIMEN_ERR_ARG);
    /* back in range: fine again */
    CHECK_OK(limen_node_set_parent(s, ball, (limen_node){ 0 }));
    CHECK_OK(limen_node_destroy(s, g[4]));
    CHECK_OK(limen_plan_build(p, s, NULL));
    limen_plan_destroy(p);
    /* names must be UTF-8 */
    CHECK(limen_node_create(s, LIMEN_NODE_GROUP, "\xff\xfe", &cam) == LIMEN_ERR_ARG);
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "caf\xc3\xa9", &cam));
    limen_scene_destroy(s);
}

/* What a renderer draws, in one list: every live node that draws or lights, hidden ones
 * marked, in pool order, with what the getters give; a node the plan names is found in
 * constant time, a stale handle or a group not at all. */
static void test_drawables(void)
{
    limen_scene *s = new_scene();
    limen_node grp, box, lamp, cam, ball, mir, gone;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "grp", &grp));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "gone", &gone));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "box", &box));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "lamp", &lamp));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, "mir", &mir));
    CHECK_OK(limen_node_destroy(s, gone));
    CHECK_OK(limen_node_set_parent(s, box, grp));
    CHECK_OK(limen_node_set_position(s, grp, (float[3]){ 1, 2, 3 }));
    CHECK_OK(limen_node_set_scale(s, box, (float[3]){ 2, 2, 2 }));
    CHECK_OK(limen_node_set_dims(s, box, (float[3]){ 1, 2, 2 }));
    CHECK_OK(limen_node_set_checker(s, box, (float[3]){ 1, 0, 0 }, (float[3]){ 0, 0, 1 }, 0.25f));
    CHECK_OK(limen_node_set_label(s, box, "room.lua:7"));
    CHECK_OK(limen_node_set_color(s, lamp, (float[3]){ 0.5f, 0.6f, 0.7f }));
    CHECK_OK(limen_node_set_visible(s, ball, 0));
    CHECK_OK(limen_surface_set_tint(s, mir, (float[3]){ 0.9f, 0.8f, 0.7f }));
    CHECK_OK(limen_surface_set_fill(s, mir, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_background(s, (float[3]){ 0.1f, 0.2f, 0.3f }));
    CHECK_OK(limen_scene_set_ambient(s, 0.25f));

    limen_drawables *d = NULL;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = (const limen_drawable *)1;
    CHECK(limen_drawables_items(d, &it) == 0 && it == NULL);
    CHECK_OK(limen_drawables_build(d, s));
    int n = limen_drawables_items(d, &it);
    CHECK(n == 4);
    const limen_node want[4] = { box, lamp, ball, mir };
    for (int i = 0; i < 4 && i < n; i++) {
        CHECK(it[i].node.id == want[i].id);
        CHECK(limen_drawables_find(d, want[i]) == i);
        CHECK(it[i].kind == limen_node_get_kind(s, want[i]));
        CHECK(it[i].visible == limen_node_get_visible(s, want[i]));
        float m[16];
        CHECK_OK(limen_node_world_matrix(s, want[i], m));
        CHECK(memcmp(m, it[i].world, sizeof m) == 0);
    }
    CHECK(limen_drawables_find(d, grp) == -1 && limen_drawables_find(d, cam) == -1);
    CHECK(limen_drawables_find(d, gone) == -1 && limen_drawables_find(d, (limen_node){ 0 }) == -1);
    CHECK(limen_drawables_find(d, (limen_node){ 0xFFFFFFFFu }) == -1);
    if (n == 4) {
        /* the box: under a group, scaled; its bounding sphere is in world units */
        CHECK(it[0].dims[1] == 2 && it[0].cell == 0.25f && it[0].color[0] == 1 &&
              it[0].checker[2] == 1);
        CHECK_NEAR(it[0].centre[0], 1, 1e-6);
        CHECK_NEAR(it[0].centre[2], 3, 1e-6);
        CHECK_NEAR(it[0].radius, 3.0, 1e-6);   /* 2 * 0.5 * |(1, 2, 2)| */
        CHECK(strcmp(it[0].name, "box") == 0 && strcmp(it[0].label, "room.lua:7") == 0);
        CHECK(it[1].color[2] == 0.7f && it[1].tint[0] == 0);
        CHECK(it[2].visible == 0);
        CHECK(it[3].tint[0] == 0.9f && it[3].fill[1] == 1 && it[3].back[0] == 0.5f);
    }
    float bg[3], amb;
    limen_drawables_environment(d, bg, &amb);
    CHECK(bg[0] == 0.1f && bg[2] == 0.3f && amb == 0.25f);

    /* a list is a snapshot: a node made later is not in it until the next build, and then
     * it takes the destroyed box's slot, so its place in pool order */
    limen_node late;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "late", &late));
    CHECK(limen_drawables_find(d, late) == -1);
    CHECK_OK(limen_drawables_build(d, s));
    CHECK(limen_drawables_items(d, NULL) == 5 && limen_drawables_find(d, late) == 0);

    /* a world matrix that overflows is refused, as by the planner, and the list is empty */
    CHECK_OK(limen_node_set_scale(s, grp, (float[3]){ 1e30f, 1e30f, 1e30f }));
    CHECK_OK(limen_node_set_scale(s, box, (float[3]){ 1e30f, 1e30f, 1e30f }));
    CHECK(limen_drawables_build(d, s) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_last_error(s), "not finite") != NULL);
    CHECK(limen_drawables_items(d, &it) == 0 && limen_drawables_find(d, lamp) == -1);
    CHECK(limen_drawables_build(NULL, s) == LIMEN_ERR_ARG);
    CHECK(limen_drawables_build(d, NULL) == LIMEN_ERR_ARG);
    limen_drawables_destroy(d);
    limen_drawables_destroy(NULL);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "overflowing_world", test_overflowing_world },
    { "handles", test_handles },
    { "capacity", test_capacity },
    { "hierarchy", test_hierarchy },
    { "rotation_order", test_rotation_order },
    { "facing", test_facing },
    { "look_at", test_look_at },
    { "validation", test_validation },
    { "local_matrix", test_local_matrix },
    { "drawables", test_drawables },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
