/* test_plan.c - the view planner, without GL: which views exist, and what a wrong virtual
 * camera would get wrong. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/plan.h"
#include "hall.h"
#include "limen.h"

#define W 320
#define H 240

static limen_scene *scene_with_camera(const float eye[3], const float at[3])
{
    limen_scene *s = NULL;
    limen_node cam;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_node_look_at(s, cam, eye, at, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    return s;
}

static limen_node surface(limen_scene *s, limen_node_kind kind, const char *name,
                          const float pos[3], const float normal[3], float w, float h)
{
    limen_node n;
    CHECK_OK(limen_node_create(s, kind, name, &n));
    CHECK_OK(limen_node_set_position(s, n, pos));
    CHECK_OK(limen_node_set_facing(s, n, normal, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, n, (float[3]){ w, h, 0 }));
    return n;
}

static limen_plan *plan(limen_scene *s, limen_plan_desc d)
{
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    if (!d.width) {
        d.width = W;
        d.height = H;
    }
    limen_status st = limen_plan_build(p, s, &d);
    CHECK_MSG(st == LIMEN_OK, "plan_build: %s", limen_scene_error(s));
    return p;
}

static bool finite_view(const limen_view *v)
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(v->view[i]) || !isfinite(v->proj[i]))
            return false;
    for (int i = 0; i < 4; i++)
        if (!isfinite(v->clip_plane[i]))
            return false;
    return true;
}

/* Column-major M * (p, 1). */
static void xform(const float m[16], const float p[3], float out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
}

/* Two mirrors facing each other at z = -3 and z = +3; the camera between them looks at
 * the far one, slightly off-axis. */
static limen_scene *corridor(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0.3f, 1.5f, 1 }, (float[3]){ 0, 1.5f, -3 });
    limen_node a = surface(s, LIMEN_NODE_MIRROR, "front", (float[3]){ 0, 1.5f, -3 },
                           (float[3]){ 0, 0, 1 }, 4, 3);
    limen_node b = surface(s, LIMEN_NODE_MIRROR, "back", (float[3]){ 0, 1.5f, 3 },
                           (float[3]){ 0, 0, -1 }, 4, 3);
    CHECK_OK(limen_surface_set_max_depth(s, a, 64));
    CHECK_OK(limen_surface_set_max_depth(s, b, 64));
    return s;
}

static void test_corridor_one_view_per_level(void)
{
    limen_scene *s = corridor();
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                           .depth = 16 } });
    CHECK(limen_plan_count(p) == 17);
    int per_level[17] = { 0 };
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i);
        CHECK(v->depth >= 0 && v->depth <= 16);
        if (v->depth >= 0 && v->depth <= 16)
            per_level[v->depth]++;
        CHECK(finite_view(v));
        /* each view's parent is one level up, and draw order puts parents first */
        if (i > 0) {
            CHECK(v->parent >= 0 && v->parent < i);
            CHECK(limen_plan_view(p, v->parent)->depth == v->depth - 1);
        }
        /* alternating surfaces, alternating winding */
        CHECK(v->front_face_cw == (v->depth & 1));
        CHECK(v->stencil == v->depth);
    }
    for (int d = 0; d <= 16; d++)
        CHECK_MSG(per_level[d] == 1, "level %d has %d views", d, per_level[d]);
    /* the first reflection looks through the front mirror; its eye is the mirrored eye */
    const limen_view *v1 = limen_plan_view(p, 1);
    CHECK(strcmp(limen_node_get_name(s, v1->through), "front") == 0);
    CHECK(v1->kind == LIMEN_VIEW_MIRROR);
    CHECK_NEAR(v1->eye[0], 0.3, 1e-5);
    CHECK_NEAR(v1->eye[2], -7, 1e-5);
    /* its clip plane is the mirror's plane, facing the room */
    CHECK_NEAR(v1->clip_plane[2], 1, 1e-6);
    CHECK_NEAR(v1->clip_plane[3], 3, 1e-5);
    /* scissors nest and shrink */
    for (int i = 1; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i), *u = limen_plan_view(p, v->parent);
        CHECK(v->scissor[0] >= u->scissor[0] && v->scissor[1] >= u->scissor[1]);
        CHECK(v->scissor[0] + v->scissor[2] <= u->scissor[0] + u->scissor[2]);
        CHECK(v->scissor[1] + v->scissor[3] <= u->scissor[1] + u->scissor[3]);
        CHECK(v->scissor[2] > 0 && v->scissor[3] > 0);
    }
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_corridor_eye_positions(void)
{
    /* the eye at depth k sits where unfolding the corridor puts it: mirrors at z = -3 and
     * z = 3 reflect z alternately: z_k = -6 - z_{k-1} (front), 6 - z (back) */
    limen_scene *s = corridor();
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                           .depth = 32 } });
    CHECK(limen_plan_count(p) == 33);
    double z = 1;
    for (int d = 1; d <= 32; d++) {
        z = (d & 1) ? -6 - z : 6 - z;
        for (int i = 0; i < limen_plan_count(p); i++) {
            const limen_view *v = limen_plan_view(p, i);
            if (v->depth != d)
                continue;
            CHECK_NEAR(v->eye[2], z, 1e-4 * fabs(z));
            CHECK_NEAR(v->eye[0], 0.3, 1e-5);
            /* the view matrix maps the eye to the origin */
            float o[3];
            xform(v->view, v->eye, o);
            CHECK_NEAR(o[0], 0, 1e-3);
            CHECK_NEAR(o[2], 0, 1e-3);
        }
    }
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_surface_limits(void)
{
    limen_scene *s = corridor();
    limen_node front;
    CHECK_OK(limen_node_find(s, "front", &front));
    CHECK_OK(limen_surface_set_max_depth(s, front, 3));
    /* front allows views up to depth 3, back up to 64: depths 1 (front), 2 (back), 3 (front),
     * 4 (back) and then front would be 5 > 3 */
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    CHECK(limen_plan_count(p) == 5);
    CHECK(limen_plan_truncated(p) == 1);
    limen_plan_destroy(p);
    /* a global depth of 0: no recursion */
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 0 } });
    CHECK(limen_plan_count(p) == 1);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static int deepest(const limen_plan *p)
{
    int d = 0;
    for (int i = 0; i < limen_plan_count(p); i++)
        d = limen_plan_view(p, i)->depth > d ? limen_plan_view(p, i)->depth : d;
    return d;
}

/* A cap only lowers a surface's own max_depth; an override replaces it, up or down. */
static void test_depth_rules(void)
{
    limen_scene *s = corridor();
    limen_node front, back;
    CHECK_OK(limen_node_find(s, "front", &front));
    CHECK_OK(limen_node_find(s, "back", &back));
    CHECK_OK(limen_surface_set_max_depth(s, front, 4));
    CHECK_OK(limen_surface_set_max_depth(s, back, 4));
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    CHECK(deepest(p) == 4);
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 40 } });
    CHECK_MSG(deepest(p) == 4, "a cap of 40 took the corridor to depth %d", deepest(p));
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 2 } });
    CHECK(deepest(p) == 2);
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                               .depth = 40 } });
    CHECK_MSG(deepest(p) == 40, "an override of 40 reached depth %d", deepest(p));
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                               .depth = 1 } });
    CHECK(deepest(p) == 1);
    limen_plan_destroy(p);
    /* the depth is ignored under the default rule; bad rules and depths are refused */
    p = plan(s, (limen_plan_desc){ .limits = { .depth = 1 } });
    CHECK(deepest(p) == 4);
    limen_plan_destroy(p);
    CHECK_OK(limen_plan_create(&p));
    CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .limits = { .depth_rule = 3 } }) ==
          LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "depth rule") != NULL);
    CHECK(limen_plan_build(p, s, &(limen_plan_desc){
              .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE, .depth = 256 } }) ==
          LIMEN_ERR_ARG);
    CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .limits = { .adaptive = 2 } }) ==
          LIMEN_ERR_ARG);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_surface_culling(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 0 }, (float[3]){ 0, 1, -5 });
    /* behind the camera, facing it: off screen */
    surface(s, LIMEN_NODE_MIRROR, "behind", (float[3]){ 0, 1, 5 }, (float[3]){ 0, 0, -1 }, 2, 2);
    /* in view but facing away: no view (its back is drawn) */
    surface(s, LIMEN_NODE_MIRROR, "away", (float[3]){ -2, 1, -5 }, (float[3]){ 0, 0, -1 }, 1, 1);
    /* far off to the side */
    surface(s, LIMEN_NODE_MIRROR, "aside", (float[3]){ 50, 1, -5 }, (float[3]){ 0, 0, 1 }, 1, 1);
    /* tiny and far: under a pixel */
    surface(s, LIMEN_NODE_MIRROR, "speck", (float[3]){ 0, 1, -90 }, (float[3]){ 0, 0, 1 },
            0.001f, 0.001f);
    /* the one that counts */
    surface(s, LIMEN_NODE_MIRROR, "seen", (float[3]){ 1, 1, -5 }, (float[3]){ 0, 0, 1 }, 1, 1);
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    CHECK(limen_plan_count(p) == 2);
    if (limen_plan_count(p) == 2)
        CHECK(strcmp(limen_node_get_name(s, limen_plan_view(p, 1)->through), "seen") == 0);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_portal_view(void)
{
    /* blue at x = -4 facing +x, orange at x = +4 facing -x; camera at the origin looks at
     * blue. Through blue it must see out of orange, looking further along -x... from x = 4
     * towards -x: the eye lands 4 units behind orange (x = 8), still looking along -x. */
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 0 }, (float[3]){ -4, 1, 0 });
    limen_node a = surface(s, LIMEN_NODE_PORTAL, "blue", (float[3]){ -4, 1, 0 },
                           (float[3]){ 1, 0, 0 }, 1, 2);
    limen_node b = surface(s, LIMEN_NODE_PORTAL, "orange", (float[3]){ 4, 1, 0 },
                           (float[3]){ -1, 0, 0 }, 1, 2);
    CHECK_OK(limen_portal_link(s, a, b));
    CHECK_OK(limen_surface_set_max_depth(s, a, 1));
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    CHECK(limen_plan_count(p) == 2);
    const limen_view *v = limen_plan_view(p, 1);
    if (v) {
        CHECK(v->kind == LIMEN_VIEW_PORTAL);
        CHECK(v->front_face_cw == 0);
        CHECK_NEAR(v->eye[0], 8, 1e-5);
        CHECK_NEAR(v->eye[1], 1, 1e-5);
        CHECK_NEAR(v->eye[2], 0, 1e-5);
        /* looking along -x: a point at x = 0 is in front (negative view z) */
        float o[3];
        xform(v->view, (float[3]){ 0, 1, 0 }, o);
        CHECK(o[2] < 0 && fabsf(o[0]) < 1e-4f);
        /* clip plane is orange's, facing -x: the room side of orange is visible */
        CHECK_NEAR(v->clip_plane[0], -1, 1e-6);
        CHECK_NEAR(v->clip_plane[3], 4, 1e-5);
    }
    limen_plan_destroy(p);
    /* an unpaired portal shows its fill: no view */
    CHECK_OK(limen_node_destroy(s, b));
    p = plan(s, (limen_plan_desc){ 0 });
    CHECK(limen_plan_count(p) == 1);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_portal_pairing_rules(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 5 }, (float[3]){ 0, 1, 0 });
    limen_node a = surface(s, LIMEN_NODE_PORTAL, "a", (float[3]){ -1, 1, 0 },
                           (float[3]){ 0, 0, 1 }, 1, 2);
    limen_node b = surface(s, LIMEN_NODE_PORTAL, "b", (float[3]){ 1, 1, 0 },
                           (float[3]){ 0, 0, 1 }, 2, 4);
    limen_node c = surface(s, LIMEN_NODE_PORTAL, "c", (float[3]){ 3, 1, 0 },
                           (float[3]){ 0, 0, 1 }, 1, 1);
    limen_node m = surface(s, LIMEN_NODE_MIRROR, "m", (float[3]){ 3, 1, 0 },
                           (float[3]){ 0, 0, 1 }, 1, 1);
    CHECK(limen_portal_link(s, a, a) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "itself") != NULL);
    CHECK(limen_portal_link(s, a, c) == LIMEN_ERR_ARG);     /* 1x2 against 1x1 */
    CHECK(strstr(limen_scene_error(s), "ratio") != NULL);
    CHECK(limen_portal_link(s, a, m) == LIMEN_ERR_ARG);
    CHECK_OK(limen_portal_link(s, a, b));                   /* twice the size is fine */
    CHECK(limen_portal_get_partner(s, a).id == b.id && limen_portal_get_partner(s, b).id == a.id);
    /* the matrix scales by 2 and turns 180 degrees about y */
    float x[16], o[3];
    CHECK_OK(limen_surface_matrix(s, a, x));
    xform(x, (float[3]){ -1, 1.5f, 0.5f }, o);  /* 0.5 up and 0.5 in front of a */
    CHECK_NEAR(o[0], 1, 1e-5);
    CHECK_NEAR(o[1], 2, 1e-5);
    CHECK_NEAR(o[2], -1, 1e-5);                 /* 1 behind b: the path continues */
    limen_scene_destroy(s);
}

/* Three mirrors forming a triangular tube along -z, normals inward; the eye at the open end
 * looks down the tube. */
static limen_scene *kaleidoscope(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0.1f, 0.05f, 0.5f }, (float[3]){ 0, 0, -10 });
    for (int k = 0; k < 3; k++) {
        float a = (float)(2 * M_PI * k / 3.0 + M_PI / 2);
        float n[3] = { cosf(a), sinf(a), 0 }, pos[3] = { -cosf(a), -sinf(a), -5 };
        char name[8];
        snprintf(name, sizeof name, "m%d", k);
        limen_node m;
        CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, name, &m));
        CHECK_OK(limen_node_set_position(s, m, pos));
        CHECK_OK(limen_node_set_facing(s, m, n, (float[3]){ 0, 0, -1 }));
        CHECK_OK(limen_node_set_dims(s, m, (float[3]){ 2 * sqrtf(3), 10, 0 }));
        CHECK_OK(limen_surface_set_max_depth(s, m, 32));
    }
    return s;
}

static void test_budget_kaleidoscope(void)
{
    /* branching views, held by the budget, shallow levels first */
    limen_scene *s = kaleidoscope();
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                           .depth = 8, .max_views = 40 } });
    CHECK(limen_plan_count(p) == 40);
    CHECK(limen_plan_truncated(p) > 0);
    /* breadth first: no view deeper than a level that is still incomplete... at least all
     * depth-1 views exist */
    int d1 = 0, maxd = 0;
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i);
        d1 += v->depth == 1;
        maxd = v->depth > maxd ? v->depth : maxd;
        CHECK(finite_view(v));
    }
    CHECK(d1 == 3);
    CHECK(maxd <= 8);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_oblique_fallback(void)
{
    /* the eye 0.01 in front of a mirror, closer than the near plane (0.05): plane clip */
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 0.01f }, (float[3]){ 1, 1, -0.2f });
    surface(s, LIMEN_NODE_MIRROR, "m", (float[3]){ 0, 1, 0 }, (float[3]){ 0, 0, 1 }, 4, 4);
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                           .depth = 1 } });
    CHECK(limen_plan_count(p) == 2);
    if (limen_plan_count(p) == 2) {
        CHECK(limen_plan_view(p, 1)->clip == LIMEN_CLIP_PLANE);
        CHECK(finite_view(limen_plan_view(p, 1)));
    }
    limen_plan_destroy(p);
    limen_scene_destroy(s);
    /* a comfortable distance: oblique */
    s = scene_with_camera((float[3]){ 0, 1, 2 }, (float[3]){ 0, 1, 0 });
    surface(s, LIMEN_NODE_MIRROR, "m", (float[3]){ 0, 1, 0 }, (float[3]){ 0, 0, 1 }, 4, 4);
    p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 1 } });
    CHECK(limen_plan_count(p) == 2 && limen_plan_view(p, 1)->clip == LIMEN_CLIP_OBLIQUE);
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .limits = { .clip = LIMEN_CLIP_NONE,
                                               .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 1 } });
    CHECK(limen_plan_count(p) == 2 && limen_plan_view(p, 1)->clip == LIMEN_CLIP_NONE);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* The plan's JSON, through a temporary file, into buf (cut at size - 1 bytes). */
static void plan_json(const limen_plan *p, limen_scene *s, char *buf, size_t size)
{
    char path[] = "/tmp/limen-plan-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0)
        close(fd);
    CHECK_OK(limen_plan_write_json(p, s, path));
    FILE *f = fopen(path, "r");
    size_t n = f ? fread(buf, 1, size - 1, f) : 0;
    buf[n] = 0;
    if (f)
        fclose(f);
    remove(path);
}

static void test_json(void)
{
    limen_scene *s = corridor();
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                           .depth = 2 } });
    char buf[16384];
    plan_json(p, s, buf, sizeof buf);
    CHECK(strstr(buf, "\"views\": [") != NULL);
    CHECK(strstr(buf, "\"through\": \"front\"") != NULL);
    CHECK(strstr(buf, "\"front_face\": \"cw\"") != NULL);
    CHECK(strstr(buf, "\"parent\": null") != NULL);
    CHECK(strstr(buf, "\"clip_plane\": null") != NULL);
    CHECK(strstr(buf, "\"kind\": \"mirror\"") != NULL);
    /* each view's surfaces, as limen_plan_view_surfaces lists them */
    CHECK(strstr(buf, "\"surfaces\": [{\"node\": \"front\", \"state\": \"recurse\", "
                      "\"child\": 1, \"rect\": [") != NULL);
    CHECK(strstr(buf, "\"state\": \"fill\", \"child\": null") != NULL);
    CHECK(strstr(buf, "\"clones\": []") != NULL);
    CHECK(strstr(buf, "nan") == NULL && strstr(buf, "inf") == NULL);
    CHECK(limen_plan_write_json(p, s, "/nonexistent/dir/plan.json") == LIMEN_ERR_IO);
    CHECK(limen_plan_write_json(p, s, "/dev/full") == LIMEN_ERR_IO);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* A plan of a scene without mirrors or portals: one view that sees no surface (the public
 * list was NULL plus an offset). */
static void test_plan_without_surfaces(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 5 }, (float[3]){ 0, 1, 0 });
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    const limen_view_surface *vs = (const limen_view_surface *)p;
    CHECK(limen_plan_count(p) == 1);
    CHECK(limen_plan_view_surfaces(p, 0, &vs) == 0 && vs == NULL);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* A sphere through a portal is listed among the clones, with the portal it enters; an
 * unnamed node is named by its label. */
static void test_json_clones(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 0, 6 }, (float[3]){ 0, 0, 0 });
    limen_node a = surface(s, LIMEN_NODE_PORTAL, "", (float[3]){ 0, 0, 0 },
                           (float[3]){ 0, 0, 1 }, 2, 2);
    limen_node b = surface(s, LIMEN_NODE_PORTAL, "exit", (float[3]){ 10, 0, 0 },
                           (float[3]){ 0, 0, 1 }, 2, 2);
    CHECK_OK(limen_node_set_label(s, a, "door.lua:3"));
    CHECK_OK(limen_portal_link(s, a, b));
    limen_node ball;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    const limen_clone *c;
    CHECK(limen_plan_clones(p, &c) == 1);
    char buf[16384];
    plan_json(p, s, buf, sizeof buf);
    CHECK_MSG(strstr(buf, "\"clones\": [\n  {\"node\": \"ball\", \"portal\": \"door.lua:3\", "
                          "\"matrix\": [") != NULL, "%s", buf);
    CHECK(strstr(buf, "\"copy_keep\": [") != NULL);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static void test_move_through_portal(void)
{
    /* blue at x = -4 facing +x, orange at x = +4 facing -x (as in test_portal_view) */
    limen_scene *s = scene_with_camera((float[3]){ 0, 1, 0 }, (float[3]){ -4, 1, 0 });
    limen_node a = surface(s, LIMEN_NODE_PORTAL, "blue", (float[3]){ -4, 1, 0 },
                           (float[3]){ 1, 0, 0 }, 1, 2);
    limen_node b = surface(s, LIMEN_NODE_PORTAL, "orange", (float[3]){ 4, 1, 0 },
                           (float[3]){ -1, 0, 0 }, 1, 2);
    CHECK_OK(limen_portal_link(s, a, b));
    limen_node cam = limen_scene_get_camera(s), eye_child;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "badge", &eye_child));
    CHECK_OK(limen_node_set_parent(s, eye_child, cam));
    CHECK_OK(limen_node_set_position(s, eye_child, (float[3]){ 0, 0, -1 }));  /* ahead */
    /* step from x = -3.9 to x = -4.3 at y = 1.2, z = 0.1: through blue's rectangle */
    CHECK_OK(limen_node_set_position(s, cam, (float[3]){ -3.9f, 1.2f, 0.1f }));
    limen_move_result mr;
    CHECK_OK(limen_node_move(s, cam, (float[3]){ -0.4f, 0, 0 }, &mr));
    CHECK(mr.crossed == 1 && mr.portal.id == a.id);
    float w[16], o[3];
    CHECK_OK(limen_node_world_matrix(s, cam, w));
    /* 0.3 past blue's plane comes out 0.3 in front of orange: x = 3.7. The half turn maps
     * blue's left (+z seen from the room) onto orange's left: z stays 0.1 */
    CHECK_NEAR(w[12], 3.7, 1e-5);
    CHECK_NEAR(w[13], 1.2, 1e-5);
    CHECK_NEAR(w[14], 0.1, 1e-5);
    /* it looked along -x into blue; now it looks along -x out of orange */
    CHECK_NEAR(w[8], 1, 1e-5);  /* local +Z (backwards) is world +x */
    /* the velocity carried: -x stays -x */
    CHECK_NEAR(mr.matrix[0], 1, 1e-5);
    /* the child came along, still one unit ahead */
    CHECK_OK(limen_node_world_matrix(s, eye_child, w));
    CHECK_NEAR(w[12], 2.7, 1e-5);
    /* walking back through orange comes out 0.2 in front of blue */
    CHECK_OK(limen_node_move(s, cam, (float[3]){ 0.5f, 0, 0 }, &mr));
    CHECK(mr.crossed == 1 && mr.portal.id == b.id);
    CHECK_OK(limen_node_world_matrix(s, cam, w));
    CHECK_NEAR(w[12], -3.8, 1e-5);
    /* beside the rectangle: no teleport */
    CHECK_OK(limen_node_set_position(s, cam, (float[3]){ -3.9f, 1.0f, 0.9f }));
    CHECK_OK(limen_node_move(s, cam, (float[3]){ -0.4f, 0, 0 }, &mr));
    CHECK(mr.crossed == 0);
    CHECK_OK(limen_node_get_position(s, cam, o));
    CHECK_NEAR(o[0], -4.3, 1e-5);
    /* from behind: no teleport */
    CHECK_OK(limen_node_set_position(s, cam, (float[3]){ -4.2f, 1, 0 }));
    CHECK_OK(limen_node_move(s, cam, (float[3]){ 0.4f, 0, 0 }, &mr));
    CHECK(mr.crossed == 0);
    CHECK(limen_node_move(s, cam, (float[3]){ NAN, 0, 0 }, &mr) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ extremes of scale */

/* Two facing mirrors a billion units wide and ten apart recurse as deep as allowed, and the
 * tracer passes as many surfaces (the on-plane tolerance grew with the coordinates: 1e-6 of
 * 5e8 put each mirror behind the other). */
static void test_huge_facing_mirrors(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    surface(s, LIMEN_NODE_MIRROR, "a", (float[3]){ 0, 0, 0 }, (float[3]){ 0, 0, 1 }, 1e9f, 1e9f);
    surface(s, LIMEN_NODE_MIRROR, "b", (float[3]){ 0, 0, 10 }, (float[3]){ 0, 0, -1 }, 1e9f,
            1e9f);
    limen_plan *p = plan(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 6 } });
    CHECK_MSG(limen_plan_count(p) == 7, "%d views, expected a chain of 7",
              limen_plan_count(p));
    for (int i = 0; i < limen_plan_count(p); i++)
        CHECK(finite_view(limen_plan_view(p, i)));
    limen_hit h;
    CHECK_OK(limen_ray_cast(s, (float[3]){ 0, 0, 5 }, (float[3]){ 0.01f, 0.02f, -1 },
                            &(limen_limits){ .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 6 }, &h));
    CHECK(h.surface_count == 6);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* Scales in range whose product along a parent chain leaves [1e-9, 1e9] for a camera or a
 * portal: planner (so renderer), tracer and ray casts refuse with one message, and no plan
 * or JSON with infinities comes out. */
static void check_refused_by_all(limen_scene *s, const char *name)
{
    char first[512];
    limen_plan *p;
    CHECK_OK(limen_plan_create(&p));
    CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .width = W, .height = H }) ==
          LIMEN_ERR_ARG);
    snprintf(first, sizeof first, "%s", limen_scene_error(s));
    CHECK_MSG(strstr(first, name) && strstr(first, "between 1e-9 and 1e9"), "planner: %s", first);
    unsigned char *rgb = malloc(W * H * 3);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, rgb) ==
          LIMEN_ERR_ARG);
    CHECK_MSG(strcmp(limen_scene_error(s), first) == 0, "tracer: %s", limen_scene_error(s));
    limen_hit h;
    CHECK(limen_ray_cast(s, (float[3]){ 0, 0, 0 }, (float[3]){ 0, 0, -1 }, NULL, &h) ==
          LIMEN_ERR_ARG);
    CHECK_MSG(strcmp(limen_scene_error(s), first) == 0, "ray cast: %s", limen_scene_error(s));
    free(rgb);
    limen_plan_destroy(p);
}

static void test_tiny_parents_refused(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    limen_node g[3], cam = limen_scene_get_camera(s);
    for (int i = 0; i < 3; i++) {
        CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, NULL, &g[i]));
        CHECK_OK(limen_node_set_scale(s, g[i], (float[3]){ 1e-9f, 1e-9f, 1e-9f }));
        if (i)
            CHECK_OK(limen_node_set_parent(s, g[i], g[i - 1]));
    }
    CHECK_OK(limen_node_set_parent(s, cam, g[2]));
    check_refused_by_all(s, "camera 'cam'");
    CHECK_OK(limen_node_set_parent(s, cam, (limen_node){ 0 }));
    limen_node a = surface(s, LIMEN_NODE_PORTAL, "in", (float[3]){ 0, 0, 0 },
                           (float[3]){ 0, 0, 1 }, 1, 1);
    limen_node b = surface(s, LIMEN_NODE_PORTAL, "out", (float[3]){ 0, 0, 0 },
                           (float[3]){ 0, 0, 1 }, 1, 1);
    CHECK_OK(limen_portal_link(s, a, b));
    CHECK_OK(limen_node_set_parent(s, b, g[2]));
    check_refused_by_all(s, "portal 'out'");
    CHECK_OK(limen_node_set_parent(s, b, g[1]));   /* 1e-18: still out */
    check_refused_by_all(s, "portal 'out'");
    CHECK_OK(limen_node_set_parent(s, b, g[0]));   /* 1e-9: in range, planned */
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    for (int i = 0; i < limen_plan_count(p); i++)
        CHECK(finite_view(limen_plan_view(p, i)));
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ frame budget */

/* 2,000 mirrors stacked 1 mm apart (twelve lines of a safe script) made one 640x480 frame
 * take 1,024 views, each testing and drawing every mirror: minutes and most of a gigabyte.
 * The frame budget bounds it; counts, not times. */
static void test_frame_budget_bounds_stacked_mirrors(void)
{
    enum { N = 2000, FW = 640, FH = 480 };
    limen_scene *s = scene_with_camera((float[3]){ 0, 0, 3 }, (float[3]){ 0, 0, 0 });
    for (int i = 0; i < N; i++)
        surface(s, LIMEN_NODE_MIRROR, NULL, (float[3]){ 0, 0, -0.001f * (float)i },
                (float[3]){ 0, 0, 1 }, 4, 3);
    limen_plan *p = plan(s, (limen_plan_desc){ .width = FW, .height = FH });
    limen_plan_work w;
    limen_plan_get_work(p, &w);
    const int64_t screen = (int64_t)FW * FH;
    /* the defaults: 64 screens of drawing, 131072 surface tests, each exceeded by at most
     * one view's own work (every surface in its scissor) */
    CHECK_MSG(w.view_pixels <= 64 * screen + (int64_t)(N + 1) * screen,
              "%lld pixels drawn", (long long)w.view_pixels);
    CHECK_MSG(w.surface_tests <= 131072 + N, "%lld surface tests", (long long)w.surface_tests);
    CHECK(w.views == limen_plan_count(p) && w.views < 70);
    CHECK(w.truncated > 0 && (w.budgets_hit & (LIMEN_BUDGET_VIEW_PIXELS |
                                               LIMEN_BUDGET_SURFACE_TESTS)));
    CHECK(w.truncated == limen_plan_truncated(p));
    /* memory follows the work: the planner's per-view surface lists */
    int listed = 0;
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view_surface *vs;
        listed += limen_plan_view_surfaces(p, i, &vs);
    }
    CHECK_MSG(listed <= w.surface_tests, "%d surfaces listed", listed);
    /* every surface of the tree is still drawn: as a view or as its fill colour */
    const limen_view_surface *vs;
    CHECK(limen_plan_view_surfaces(p, 0, &vs) == N);

    /* a budget the caller sets: one surface test more than the root's allows no child */
    limen_plan_destroy(p);
    p = plan(s, (limen_plan_desc){ .width = FW, .height = FH,
                                   .limits.budget = { .view_pixels = INT64_MAX,
                                                      .surface_tests = N + 1 } });
    limen_plan_get_work(p, &w);
    CHECK(w.views == 1 && w.surface_tests == N && (w.budgets_hit & LIMEN_BUDGET_SURFACE_TESTS));
    limen_plan_destroy(p);
    limen_plan_create(&p);
    CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .limits.budget = { .view_pixels = -1 } }) ==
          LIMEN_ERR_ARG);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ the things of a view */

/* A box mesh of 12 triangles (a unit cube). */
static void cube_mesh(limen_scene *s, limen_node m)
{
    static const float pos[24] = { -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f,
                                   -0.5f, 0.5f,  -0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f, 0.5f,
                                   0.5f,  0.5f,  0.5f,  -0.5f, 0.5f,  0.5f };
    static const uint32_t idx[36] = { 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                      3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5 };
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){ .positions = pos,
                                                               .vertex_count = 8,
                                                               .indices = idx,
                                                               .triangle_count = 12 }));
}

/* The mirror corridor with shapes along it and behind its mirrors: spheres, boxes and cube
 * meshes (some hidden), so that each level of views sees other ones. */
static limen_scene *corridor_with_shapes(void)
{
    limen_scene *s = corridor();
    static const limen_node_kind kinds[3] = { LIMEN_NODE_SPHERE, LIMEN_NODE_BOX,
                                              LIMEN_NODE_MESH };
    for (int i = 0; i < 30; i++) {
        limen_node n;
        CHECK_OK(limen_node_create(s, kinds[i % 3], NULL, &n));
        if (kinds[i % 3] == LIMEN_NODE_MESH)
            cube_mesh(s, n);
        float x = -6.0f + 0.4f * (float)i, z = -4.0f + 0.27f * (float)i;
        CHECK_OK(limen_node_set_position(s, n, (float[3]){ x, 1.0f + 0.05f * (float)i, z }));
        CHECK_OK(limen_node_set_scale(s, n, (float[3]){ 0.3f, 0.3f, 0.3f }));
        if (i % 7 == 3)
            CHECK_OK(limen_node_set_visible(s, n, 0));
    }
    return s;
}

/* What the scene's spatial index gives for view i of a built plan, asked again after the
 * build (as limen_plan_view_things did on every call) and sorted (never put in order
 * through the slots' bitmap, as the build may), as handles; their count. */
static int index_things(limen_plan *p, limen_scene *s, int i, limen_node *out, int max)
{
    p->sort_hits = true;
    int n = limen__plan_view_shapes(p, s, &p->found[p->dfs_to_bfs[i]]);
    p->sort_hits = false;
    for (int k = 0; k < n && k < max; k++)
        out[k] = limen__node_handle(s, p->shape_hits[k]);
    return n;
}

/* The things stored with each view equal what the index gives for it after the build, in
 * node order, visible ones only: in a hall of portals, a corridor of mirrors, and with a
 * triangle budget that drops views after their things were listed. */
static void test_things_stored(void)
{
    enum { MAX = 4096 };
    limen_node *want = malloc(sizeof *want * MAX);
    limen_scene *scenes[3] = { hall_create(1500, 12, 7), corridor_with_shapes(),
                               corridor_with_shapes() };
    /* in the hall (many shapes a view: the lists are put in order through a bitmap of the
     * slots), some spheres hidden too */
    for (int k = 0, n = 0; k < scenes[0]->cap; k++)
        if (limen__alive(&scenes[0]->nodes[k]) && scenes[0]->nodes[k].kind == LIMEN_NODE_SPHERE &&
            n++ % 5 == 2)
            CHECK_OK(limen_node_set_visible(scenes[0], limen__node_handle(scenes[0], k), 0));
    limen_plan_desc descs[3] = { { 0 }, { 0 }, { .limits.budget.triangles = 12 * 60 } };
    for (int c = 0; c < 3; c++) {
        limen_scene *s = scenes[c];
        limen_plan *p = plan(s, descs[c]);
        limen_plan_work w;
        limen_plan_get_work(p, &w);
        CHECK_MSG(limen_plan_count(p) > 3, "scene %d: %d views, %lld triangles", c,
                  limen_plan_count(p), (long long)w.triangles);
        if (c == 2)
            CHECK_MSG(w.budgets_hit & LIMEN_BUDGET_TRIANGLES, "budgets hit: %u", w.budgets_hit);
        int differ = 0, total = 0, distinct = 0, prev = -1;
        for (int i = 0; i < limen_plan_count(p); i++) {
            const limen_node *got;
            int n = limen_plan_things(p, i, &got);
            int m = index_things(p, s, i, want, MAX);
            CHECK(m >= 0 && m <= MAX);
            differ += n != m || (n && memcmp(got, want, sizeof *got * (size_t)n));
            for (int k = 0; k < n; k++) {
                CHECK(limen_node_valid(s, got[k]) && limen_node_get_visible(s, got[k]));
                CHECK(k == 0 || (uint32_t)got[k - 1].id < (uint32_t)got[k].id);
            }
            distinct += n != prev;
            prev = n;
            total += n;
            /* the deprecated copy gives the same */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
            int copied = limen_plan_view_things(p, s, i, want, MAX);
#pragma GCC diagnostic pop
            CHECK(copied == n && (!n || !memcmp(got, want, sizeof *got * (size_t)n)));
        }
        CHECK_MSG(differ == 0, "scene %d: %d views whose things differ from the index's", c,
                  differ);
        CHECK_MSG(total > 0 && distinct > 1, "scene %d: %d things, %d distinct counts", c,
                  total, distinct);
        limen_plan_destroy(p);
        limen_scene_destroy(s);
    }
    free(want);
}

/* The things of every view lie in one array for the whole plan, view after view in draw
 * order, and building the plan of the same scene again allocates nothing: the arrays keep
 * their place and size. */
static void test_things_one_array(void)
{
    limen_scene *s = hall_create(800, 10, 11);
    limen_plan *p = plan(s, (limen_plan_desc){ 0 });
    int count = limen_plan_count(p);
    CHECK(count > 3);
    const limen_node *base = NULL, *next = NULL;
    int total = 0;
    for (int i = 0; i < count; i++) {
        const limen_node *t;
        int n = limen_plan_things(p, i, &t);
        CHECK((n == 0) == (t == NULL));
        if (!n)
            continue;
        if (!base)
            base = t;
        CHECK_MSG(!next || t == next, "view %d's things do not follow the last view's", i);
        next = t + n;
        total += n;
    }
    CHECK(base && next - base == total);
    const limen_node *none;
    CHECK(limen_plan_things(p, count, &none) == 0 && none == NULL);
    CHECK(limen_plan_things(p, -1, &none) == 0 && none == NULL);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"   /* the old name still works */
    CHECK(limen_plan_view_things(p, s, count, NULL, 0) == -1);
    CHECK(limen_plan_view_things(p, NULL, 0, NULL, 0) == limen_plan_things(p, 0, &none));
#pragma GCC diagnostic pop

    /* a second frame of the same scene: no array grows, none moves */
    const limen_node *things = p->things;
    const int caps[] = { p->found_cap, p->views_cap, p->things_cap, p->thing_slots_cap,
                         p->shape_hits_cap, p->things_first_cap, p->view_surfaces_cap,
                         p->public_surfaces_cap };
    CHECK_OK(limen_plan_build(p, s, &(limen_plan_desc){ .width = W, .height = H }));
    const int again[] = { p->found_cap, p->views_cap, p->things_cap, p->thing_slots_cap,
                          p->shape_hits_cap, p->things_first_cap, p->view_surfaces_cap,
                          p->public_surfaces_cap };
    CHECK(limen_plan_count(p) == count);
    CHECK(!memcmp(caps, again, sizeof caps) && p->things == things);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "things_stored", test_things_stored },
    { "things_one_array", test_things_one_array },
    { "move_through_portal", test_move_through_portal },
    { "corridor_one_view_per_level", test_corridor_one_view_per_level },
    { "corridor_eye_positions", test_corridor_eye_positions },
    { "surface_limits", test_surface_limits },
    { "depth_rules", test_depth_rules },
    { "json_clones", test_json_clones },
    { "surface_culling", test_surface_culling },
    { "portal_view", test_portal_view },
    { "portal_pairing_rules", test_portal_pairing_rules },
    { "budget_kaleidoscope", test_budget_kaleidoscope },
    { "oblique_fallback", test_oblique_fallback },
    { "json", test_json },
    { "plan_without_surfaces", test_plan_without_surfaces },
    { "huge_facing_mirrors", test_huge_facing_mirrors },
    { "tiny_parents_refused", test_tiny_parents_refused },
    { "frame_budget_bounds_stacked_mirrors", test_frame_budget_bounds_stacked_mirrors },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
