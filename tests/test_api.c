/* test_api.c - the API's shape as a user meets it: the version (one source, limen.h), and
 * the defaults functions (one per desc), which must return what the calls apply. */
#include <limen.h>
#include <stdio.h>
#include <string.h>

#include "check.h"

static void test_version(void)
{
    char parts[32];
    snprintf(parts, sizeof parts, "%d.%d.%d", LIMEN_VERSION_MAJOR, LIMEN_VERSION_MINOR,
             LIMEN_VERSION_PATCH);
    CHECK(strcmp(LIMEN_VERSION, parts) == 0);
    CHECK(strcmp(limen_version(), LIMEN_VERSION) == 0);
    CHECK(limen_version_number() == LIMEN_VERSION_NUMBER);
    CHECK(LIMEN_VERSION_NUMBER ==
          LIMEN_VERSION_MAJOR * 10000 + LIMEN_VERSION_MINOR * 100 + LIMEN_VERSION_PATCH);
}

static void test_limits_defaults(void)
{
    limen_limits l = limen_limits_defaults(NULL, 0, 0);
    CHECK(l.clip == LIMEN_CLIP_OBLIQUE && l.depth_rule == LIMEN_DEPTH_RULE_OWN);
    CHECK(l.max_views == LIMEN_DEFAULT_MAX_VIEWS && LIMEN_DEFAULT_MAX_VIEWS == 1024);
    CHECK(l.lod_pixels == LIMEN_LOD_DEFAULT);
    CHECK(l.budget.view_pixels == (int64_t)LIMEN_DEFAULT_VIEW_SCREENS * 640 * 480);
    CHECK(l.budget.surface_tests == LIMEN_DEFAULT_SURFACE_TESTS);
    CHECK(l.budget.triangles == LIMEN_BUDGET_TRIANGLES_DEFAULT);
    l = limen_limits_defaults(&(limen_limits){ .depth = 5, .max_views = 7,
                                               .lod_pixels = LIMEN_LOD_FULL,
                                               .budget.surface_tests = 9 }, 100, 50);
    CHECK(l.depth == 0);                    /* OWN ignores depth */
    CHECK(l.max_views == 7 && l.lod_pixels == LIMEN_LOD_FULL && l.budget.surface_tests == 9);
    CHECK(l.budget.view_pixels == (int64_t)LIMEN_DEFAULT_VIEW_SCREENS * 100 * 50);
    l = limen_limits_defaults(&(limen_limits){ .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 5 },
                              0, 0);
    CHECK(l.depth == 5);
}

/* a camera facing a mirror that faces it: a tree of two views */
static limen_scene *mirror_scene(void)
{
    limen_scene *s = NULL;
    limen_node cam, m;
    if (limen_scene_create(&(limen_scene_desc){ 0 }, &s))
        return NULL;
    limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam);
    limen_scene_set_camera(s, cam);
    limen_node_create(s, LIMEN_NODE_MIRROR, "m", &m);
    limen_node_set_position(s, m, (float[3]){ 0, 0, -3 });
    return s;
}

static void test_plan_desc_defaults(void)
{
    limen_plan_desc d = limen_plan_desc_defaults(NULL);
    CHECK(d.width == LIMEN_DEFAULT_WIDTH && d.height == LIMEN_DEFAULT_HEIGHT);
    CHECK(d.width == 640 && d.height == 480);
    CHECK(d.limits.max_views == 1024 && d.limits.lod_pixels == LIMEN_LOD_DEFAULT);
    CHECK(d.limits.budget.view_pixels == 64LL * 640 * 480);
    d = limen_plan_desc_defaults(&(limen_plan_desc){ .width = 100, .height = 50 });
    CHECK(d.width == 100 && d.height == 50);
    CHECK(d.limits.budget.view_pixels == 64LL * 100 * 50);

    /* what the planner applies: a zero desc plans the same tree as the filled one, over a
     * 640 x 480 image */
    limen_scene *s = mirror_scene();
    limen_plan *a = NULL, *b = NULL;
    CHECK(s && limen_plan_create(&a) == LIMEN_OK && limen_plan_create(&b) == LIMEN_OK);
    if (!s || !a || !b)
        goto done;
    limen_plan_desc filled = limen_plan_desc_defaults(NULL);
    CHECK_OK(limen_plan_build(a, s, NULL));
    CHECK_OK(limen_plan_build(b, s, &filled));
    CHECK(limen_plan_count(a) == 2 && limen_plan_count(b) == 2);
    const limen_view *ra = limen_plan_view(a, 0), *rb = limen_plan_view(b, 0);
    CHECK(ra && rb && ra->scissor[2] == 640 && ra->scissor[3] == 480);
    CHECK(ra && rb && memcmp(ra, rb, sizeof *ra) == 0);
    limen_plan_work wa, wb;
    limen_plan_get_work(a, &wa);
    limen_plan_get_work(b, &wb);
    CHECK(memcmp(&wa, &wb, sizeof wa) == 0);
    /* the default view-pixel budget follows the image: at 100 x 50 it holds 64 such
     * screens, so one screen's budget less than that stops the mirror's view */
    limen_plan_desc small = { .width = 100, .height = 50 };
    small.limits.budget.view_pixels = 100 * 50;
    CHECK_OK(limen_plan_build(a, s, &small));
    CHECK(limen_plan_count(a) == 1 && limen_plan_truncated(a) == 1);
done:
    limen_plan_destroy(a);
    limen_plan_destroy(b);
    limen_scene_destroy(s);
}

static void test_renderer_desc_defaults(void)
{
    limen_renderer_desc d = limen_renderer_desc_defaults(NULL);
    CHECK(d.backend == LIMEN_BACKEND_OSMESA && d.width == 640 && d.height == 480);
    CHECK(d.depth_bits == 24 && d.msaa == 0);
    d = limen_renderer_desc_defaults(
        &(limen_renderer_desc){ .depth_range = LIMEN_DEPTH_ZO_REVERSED, .width = 32 });
    CHECK(d.depth_bits == 32 && d.width == 32 && d.height == 480);
    /* what the renderer applies */
    limen_renderer *r = NULL;
    if (limen_renderer_create(&(limen_renderer_desc){ 0 }, &r) == LIMEN_OK) {
        int w = 0, h = 0;
        limen_renderer_get_size(r, &w, &h);
        d = limen_renderer_desc_defaults(NULL);
        CHECK(w == d.width && h == d.height);
    } else {
        CHECK_MSG(0, "renderer: %s", limen_renderer_error(r));
    }
    limen_renderer_destroy(r);
    limen_render_opts o = limen_render_opts_defaults(NULL, 320, 200);
    CHECK(o.method == LIMEN_METHOD_STENCIL && o.texture_scale == 1);
    CHECK(o.limits.budget.view_pixels == 64LL * 320 * 200);
}

static void test_trace_and_script_defaults(void)
{
    limen_trace_desc t = limen_trace_desc_defaults(NULL);
    CHECK(t.width == 640 && t.height == 480 && t.threads >= 1);
    CHECK(t.limits.max_views == 1024);
    t = limen_trace_desc_defaults(&(limen_trace_desc){ .threads = 3, .width = 8 });
    CHECK(t.threads == 3 && t.width == 8 && t.height == 480);

    limen_script_desc sd = limen_script_desc_defaults(NULL);
    CHECK(sd.trusted == 0 && sd.print == NULL);
    CHECK(sd.instruction_budget == 50000000 && sd.memory_cap == 64LL * 1024 * 1024);
    sd = limen_script_desc_defaults(&(limen_script_desc){ .instruction_budget = -1,
                                                         .memory_cap = 12345 });
    CHECK(sd.instruction_budget == -1 && sd.memory_cap == 12345);
    CHECK(limen_scene_desc_defaults(NULL).max_nodes == 0);
    CHECK(limen_scene_desc_defaults(&(limen_scene_desc){ .max_nodes = 9 }).max_nodes == 9);
}

/* Each public enum ends with a _COUNT member: one past the last value, which every call
 * refuses as it refuses any unknown value, and the last value below it is accepted. */
static void test_enum_counts(void)
{
    CHECK(LIMEN_STATUS_COUNT == LIMEN_ERR_UNSUPPORTED + 1);
    for (int i = 0; i < LIMEN_STATUS_COUNT; i++)
        CHECK(strcmp(limen_status_string((limen_status)i), "unknown status") != 0);
    CHECK(strcmp(limen_status_string(LIMEN_STATUS_COUNT), "unknown status") == 0);
    CHECK(LIMEN_DEPTH_RANGE_COUNT == 3 && LIMEN_CLIP_COUNT == 3 && LIMEN_VIEW_KIND_COUNT == 3);
    CHECK(LIMEN_SURFACE_STATE_COUNT == 3 && LIMEN_DEPTH_RULE_COUNT == 3 && LIMEN_CULL_COUNT == 2);
    CHECK(LIMEN_BACKEND_COUNT == 3 && LIMEN_METHOD_COUNT == 3 && LIMEN_FILL_COUNT == 2);
    CHECK(LIMEN_NODE_KIND_COUNT == LIMEN_NODE_MESH + 1);

    float proj[16];
    CHECK(limen_perspective(1, 1, 0.1f, 10, LIMEN_DEPTH_RANGE_COUNT - 1, proj) == LIMEN_OK);
    CHECK(limen_perspective(1, 1, 0.1f, 10, LIMEN_DEPTH_RANGE_COUNT, proj) == LIMEN_ERR_ARG);
    limen_scene *s = mirror_scene();
    limen_plan *p = NULL;
    CHECK(s && limen_plan_create(&p) == LIMEN_OK);
    if (s && p) {
        CHECK_OK(limen_plan_build(p, s, &(limen_plan_desc){ .cull = LIMEN_CULL_COUNT - 1 }));
        CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .cull = LIMEN_CULL_COUNT }) ==
              LIMEN_ERR_ARG);
        CHECK(limen_plan_build(p, s, &(limen_plan_desc){ .range = LIMEN_DEPTH_RANGE_COUNT }) ==
              LIMEN_ERR_ARG);
        limen_plan_desc d = { 0 };
        d.limits.clip = LIMEN_CLIP_COUNT - 1;
        CHECK_OK(limen_plan_build(p, s, &d));
        d.limits.clip = LIMEN_CLIP_COUNT;
        CHECK(limen_plan_build(p, s, &d) == LIMEN_ERR_ARG);
        d.limits.clip = 0;
        d.limits.depth_rule = LIMEN_DEPTH_RULE_COUNT - 1;
        CHECK_OK(limen_plan_build(p, s, &d));
        d.limits.depth_rule = LIMEN_DEPTH_RULE_COUNT;
        CHECK(limen_plan_build(p, s, &d) == LIMEN_ERR_ARG);
    }
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* One node lookup (limen__node_lookup, and its const twin) behind every call: a status and,
 * for a call that may write, a message that names the call and says what is wrong. */
static void test_node_lookup(void)
{
    limen_scene *s = mirror_scene();
    CHECK(s != NULL);
    if (!s)
        return;
    limen_node ball, gone, m;
    CHECK_OK(limen_node_find(s, "m", &m));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "gone", &gone));
    CHECK_OK(limen_node_destroy(s, gone));

    CHECK(limen_node_set_position(s, gone, (float[3]){ 0, 0, 0 }) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s),
                 "limen_node_set_position: stale or foreign node handle") == 0);
    CHECK(limen_node_set_position(s, (limen_node){ 0 }, (float[3]){ 0, 0, 0 }) ==
          LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "limen_node_set_position: null node handle") == 0);
    CHECK(limen_node_set_position(NULL, ball, (float[3]){ 0, 0, 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_surface_set_tint(s, ball, (float[3]){ 1, 1, 1 }) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "tint: 'ball' is not a mirror or a portal") == 0);
    CHECK(limen_portal_link(s, m, gone) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "portal_link: stale or foreign node handle") == 0);
    CHECK_OK(limen_surface_set_tint(s, m, (float[3]){ 1, 1, 1 }));

    /* const readers: a status, and the message stays as it was */
    limen_node_set_position(s, gone, (float[3]){ 0, 0, 0 });
    float rgb[3], p[3];
    CHECK(limen_surface_get(s, ball, rgb, NULL, NULL, NULL) == LIMEN_ERR_HANDLE);
    CHECK(limen_surface_get(s, gone, rgb, NULL, NULL, NULL) == LIMEN_ERR_HANDLE);
    CHECK(limen_surface_get(NULL, m, rgb, NULL, NULL, NULL) == LIMEN_ERR_ARG);
    CHECK_OK(limen_surface_get(s, m, rgb, NULL, NULL, NULL));
    CHECK(limen_node_get_position(s, gone, p) == LIMEN_ERR_HANDLE);
    CHECK(limen_portal_get_partner(s, m).id == 0);
    CHECK(strcmp(limen_scene_error(s),
                 "limen_node_set_position: stale or foreign node handle") == 0);
    limen_scene_destroy(s);
}

/* The calls that looked handles up by hand (meshes, textures, move, slide) go through the one
 * lookup: its two messages and its kind check, named like every other call's; limen_mesh_get,
 * a const reader, returns a status and leaves the message as it was. */
static void test_node_lookup_everywhere(void)
{
    limen_scene *s = mirror_scene();
    CHECK(s != NULL);
    if (!s)
        return;
    limen_node ball, gone, mesh;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "statue", &mesh));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "gone", &gone));
    CHECK_OK(limen_node_destroy(s, gone));
    const float d[3] = { 0.1f, 0, 0 };
    CHECK(limen_node_move(s, gone, d, NULL) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "move: stale or foreign node handle") == 0);
    CHECK(limen_node_move(s, (limen_node){ 0 }, d, NULL) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "move: null node handle") == 0);
    CHECK(limen_node_move(NULL, ball, d, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_node_slide(s, gone, d, 0.1f, NULL) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "slide: stale or foreign node handle") == 0);
    CHECK(limen_node_set_texture(s, ball, "none.png") == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "texture: 'ball' is a sphere, which takes no texture") == 0);
    CHECK(limen_mesh_set_smooth(s, ball, 1) == LIMEN_ERR_HANDLE);
    CHECK(strcmp(limen_scene_error(s), "mesh_set_smooth: 'ball' is not a mesh") == 0);
    CHECK(limen_mesh_set_smooth(NULL, mesh, 1) == LIMEN_ERR_ARG);

    /* a const reader: the status alone */
    limen_mesh_info info;
    CHECK(limen_mesh_get(s, ball, &info) == LIMEN_ERR_HANDLE);
    CHECK(limen_mesh_get(s, gone, &info) == LIMEN_ERR_HANDLE);
    CHECK(limen_mesh_get(s, mesh, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_mesh_get(NULL, mesh, &info) == LIMEN_ERR_ARG);
    CHECK_OK(limen_mesh_get(s, mesh, &info));
    CHECK(info.triangle_count == 0);
    CHECK(strcmp(limen_scene_error(s), "mesh_set_smooth: 'ball' is not a mesh") == 0);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "node_lookup", test_node_lookup },
    { "node_lookup_everywhere", test_node_lookup_everywhere },
    { "enum_counts", test_enum_counts },
    { "version", test_version },
    { "limits_defaults", test_limits_defaults },
    { "plan_desc_defaults", test_plan_desc_defaults },
    { "renderer_desc_defaults", test_renderer_desc_defaults },
    { "trace_and_script_defaults", test_trace_and_script_defaults },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
