/* test_crossing.c - moving through portals: a camera walking through a portal sees no
 * flicker on either side of the crossing (every frame within the ground-truth bound, the
 * near plane never showing the portal's edge or the wall behind it), and a shape half way
 * through a portal shows on both sides, cut at the portal planes. */
#include <stdlib.h>

#include "check.h"
#include "limen.h"

#define W 320
#define H 240
#define BOUND 0.005

/* A room with a wall at z = 0 holding portal "in" (facing +z) and, far away, "out" in an
 * open field facing -x; a red ball and a blue box on each side to see where one is. */
static limen_scene *room(limen_node *cam, limen_node *in, limen_node *out)
{
    limen_scene *s;
    limen_node n;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_scene_set_background(s, (float[3]){ 0.4f, 0.6f, 0.9f }));
    CHECK_OK(limen_scene_set_ambient(s, 0.3f));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "sun", &n));
    CHECK_OK(limen_node_set_position(s, n, (float[3]){ 2, 6, 4 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "floor", &n));
    CHECK_OK(limen_node_set_facing(s, n, (float[3]){ 0, 1, 0 }, NULL));
    CHECK_OK(limen_node_set_dims(s, n, (float[3]){ 40, 40, 0 }));
    CHECK_OK(limen_node_set_checker(s, n, (float[3]){ 0.8f, 0.8f, 0.8f },
                                    (float[3]){ 0.3f, 0.3f, 0.3f }, 1));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "wall", &n));
    CHECK_OK(limen_node_set_position(s, n, (float[3]){ 0, 1.5f, -0.01f }));
    CHECK_OK(limen_node_set_dims(s, n, (float[3]){ 8, 3, 0 }));
    CHECK_OK(limen_node_set_color(s, n, (float[3]){ 0.9f, 0.8f, 0.5f }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "in", in));
    CHECK_OK(limen_node_set_position(s, *in, (float[3]){ 0, 1.2f, 0 }));
    CHECK_OK(limen_node_set_dims(s, *in, (float[3]){ 1.2f, 2.2f, 0 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "out", out));
    CHECK_OK(limen_node_set_position(s, *out, (float[3]){ 15, 1.2f, 0 }));
    CHECK_OK(limen_node_set_facing(s, *out, (float[3]){ -1, 0, 0 }, NULL));
    CHECK_OK(limen_node_set_dims(s, *out, (float[3]){ 1.2f, 2.2f, 0 }));
    CHECK_OK(limen_portal_link(s, *in, *out));
    const float spots[4][3] = { { -1.5f, 0.5f, 2 }, { 1.5f, 0.4f, 1.5f },
                                { 12, 0.5f, -1 }, { 11, 0.4f, 1.5f } };
    for (int i = 0; i < 4; i++) {
        CHECK_OK(limen_node_create(s, i & 1 ? LIMEN_NODE_BOX : LIMEN_NODE_SPHERE, NULL, &n));
        CHECK_OK(limen_node_set_position(s, n, spots[i]));
        CHECK_OK(limen_node_set_dims(s, n, (float[3]){ i & 1 ? 0.8f : 0.5f, 0.8f, 0.8f }));
        CHECK_OK(limen_node_set_color(s, n, i & 1 ? (float[3]){ 0.1f, 0.2f, 0.9f }
                                                  : (float[3]){ 0.9f, 0.1f, 0.1f }));
    }
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", cam));
    CHECK_OK(limen_node_look_at(s, *cam, (float[3]){ 0.15f, 1.5f, 3 }, (float[3]){ 0.1f, 1.3f, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, *cam));
    return s;
}

/* Share of pixels off the traced truth, per method. */
static void against_truth(limen_renderer *r, limen_scene *s, double share[2])
{
    unsigned char *truth = malloc(W * H * 3), *img = malloc(W * H * 3);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, truth));
    for (int m = 0; m < 2; m++) {
        limen_diff d = { 1, 0, 0, 0 };
        if (!limen_render_frame(r, s, &(limen_render_opts){ .method = m }, NULL) &&
            !limen_renderer_read_rgb(r, img))
            limen_image_diff(img, truth, W, H, 8, &d, NULL);
        share[m] = d.bad_share;
    }
    free(truth);
    free(img);
}

static void test_walk_through(void)
{
    limen_node cam, in, out;
    limen_scene *s = room(&cam, &in, &out);
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    /* walk towards the portal; steps shrink near the plane, where the near plane (0.05)
     * crosses it, then go on past it */
    const float z[] = { 3, 1, 0.3f, 0.1f, 0.06f, 0.04f, 0.02f, 0.005f, 0.0005f,
                        -0.0005f, -0.005f, -0.03f, -0.06f, -0.2f, -1 };
    float at = 3, dir[3] = { 0, 0, -1 };    /* the walker's velocity, carried through */
    int crossed = 0;
    for (size_t i = 0; i < sizeof z / sizeof z[0] && r; i++) {
        limen_move_result mr;
        float len = at - z[i];
        CHECK_OK(limen_node_move(s, cam, (float[3]){ len * dir[0], len * dir[1], len * dir[2] },
                                 &mr));
        at = z[i];
        crossed += mr.crossed;
        if (mr.crossed) {
            float v[3];
            for (int k = 0; k < 3; k++)
                v[k] = mr.matrix[k] * dir[0] + mr.matrix[4 + k] * dir[1] + mr.matrix[8 + k] * dir[2];
            memcpy(dir, v, sizeof v);
        }
        double share[2];
        against_truth(r, s, share);
        float p[3];
        limen_node_get_position(s, cam, p);
        printf("     step %2zu (%.4f %s the portal, x = %.4f): stencil %.3f%%, texture %.3f%%\n",
               i, fabsf(z[i]), crossed ? "past" : "before", p[0], 100 * share[0], 100 * share[1]);
        CHECK_MSG(share[0] <= BOUND && share[1] <= BOUND, "step %zu: %.3f%% / %.3f%% off", i,
                  100 * share[0], 100 * share[1]);
    }
    CHECK(crossed == 1);
    float p[3];
    CHECK_OK(limen_node_get_position(s, cam, p));
    CHECK_NEAR(p[0], 15 - 1, 1e-3);     /* 1 past "in" is 1 in front of "out" */
    CHECK_NEAR(dir[0], -1, 1e-5);       /* walking along -x out of "out" */
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

static void test_shape_half_through(void)
{
    limen_node cam, in, out, ball;
    limen_scene *s = room(&cam, &in, &out);
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "half", &ball));
    CHECK_OK(limen_node_set_position(s, ball, (float[3]){ 0.1f, 1.0f, 0.1f }));
    CHECK_OK(limen_node_set_dims(s, ball, (float[3]){ 0.35f, 0, 0 }));
    CHECK_OK(limen_node_set_color(s, ball, (float[3]){ 0.1f, 0.9f, 0.2f }));
    /* look from the side at the far end, where the ball comes out */
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 12.5f, 1.6f, 1.5f }, (float[3]){ 15, 1.1f, 0 },
                                (float[3]){ 0, 1, 0 }));
    limen_plan *p;
    CHECK_OK(limen_plan_create(&p));
    CHECK_OK(limen_plan_build(p, s, &(limen_plan_desc){ .width = W, .height = H }));
    const limen_clone *c;
    CHECK(limen_plan_clones(p, &c) == 1);
    if (limen_plan_clones(p, &c) == 1) {
        CHECK(c->node.id == ball.id && c->portal.id == in.id);
        /* the copy's centre: 0.1 in front of "in" is 0.1 behind "out", at x = 15.1 */
        CHECK_NEAR(c->matrix[12] + c->matrix[0] * 0.1f + c->matrix[4] * 1.0f + c->matrix[8] * 0.1f,
                   15.1, 1e-4);
    }
    limen_plan_destroy(p);
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    double share[2];
    against_truth(r, s, share);
    printf("     the copy seen at the far end: stencil %.3f%%, texture %.3f%%\n", 100 * share[0],
           100 * share[1]);
    CHECK(share[0] <= BOUND && share[1] <= BOUND);
    /* the copy is really there: the green of the ball shows beside "out" */
    unsigned char *img = malloc(W * H * 3);
    CHECK_OK(limen_render_frame(r, s, NULL, NULL));
    CHECK_OK(limen_renderer_read_rgb(r, img));
    int green = 0;
    for (int i = 0; i < W * H; i++)
        green += img[3 * i + 1] > 120 && img[3 * i] < 60 && img[3 * i + 2] < 80;
    CHECK_MSG(green > 100, "only %d green pixels", green);
    /* and from the room side the ball is cut at the portal: its front half only */
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 1.5f, 1.4f, 2.5f }, (float[3]){ 0, 1, 0 },
                                (float[3]){ 0, 1, 0 }));
    against_truth(r, s, share);
    printf("     the ball seen in the room: stencil %.3f%%, texture %.3f%%\n", 100 * share[0],
           100 * share[1]);
    CHECK(share[0] <= BOUND && share[1] <= BOUND);
    free(img);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* The gallery's fly-through, frame by frame: out through the pair and back, every frame
 * within the bound, and the camera back where it started. */
static void test_flythrough_script(void)
{
    limen_script *sc = NULL;
    limen_status st = limen_script_load("scenes/flythrough.lua", NULL, &sc);
    CHECK_MSG(st == LIMEN_OK, "%s", limen_script_error(sc));
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    limen_scene *s = st ? NULL : limen_script_scene(sc);
    float start[3] = { 0, 0, 0 }, p[3];
    if (s)
        CHECK_OK(limen_node_get_position(s, limen_scene_get_camera(s), start));
    for (int f = 1; f <= 16 && s && r; f++) {
        double t = 0.5 * f;
        CHECK_OK(limen_script_update(sc, t));
        double share[2];
        against_truth(r, s, share);
        CHECK_MSG(share[0] <= BOUND && share[1] <= BOUND, "t = %.1f: %.3f%% / %.3f%% off", t,
                  100 * share[0], 100 * share[1]);
        CHECK_OK(limen_node_get_position(s, limen_scene_get_camera(s), p));
        if (f == 8)
            CHECK_MSG(p[0] > 16, "at t = 4 the camera is on the terrace (x = %.2f)", p[0]);
    }
    if (s) {
        CHECK_OK(limen_node_get_position(s, limen_scene_get_camera(s), p));
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(p[k], start[k], 1e-3);
    }
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
}

static const check_case cases[] = {
    { "flythrough_script", test_flythrough_script },
    { "walk_through", test_walk_through },
    { "shape_half_through", test_shape_half_through },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
