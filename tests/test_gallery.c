/* test_gallery.c - every gallery scene with both renderers and all clip methods, and per
 * scene the facts that a wrong virtual camera would break. */
#include <stdbool.h>
#include <stdlib.h>

#include "check.h"
#include "limen.h"
#include "load.h"

#define W 160
#define H 120

static const char *const scenes[] = {
    "scenes/plain.lua",        "scenes/mirror_room.lua", "scenes/corridor.lua",
    "scenes/kaleidoscope.lua", "scenes/periscope.lua",   "scenes/water.lua",
    "scenes/portals.lua",      "scenes/tunnel.lua",      "scenes/portal_mirror.lua",
    "scenes/portal_sizes.lua", "scenes/moving_portal.lua", "scenes/flythrough.lua",
    "scenes/hall_of_mirrors.lua", "scenes/portal_rooms.lua", "scenes/portal_statue.lua",
    "scenes/level.lua", "scenes/materials.lua", NULL,
};

static limen_renderer *renderer(int w, int h)
{
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r);
    CHECK_MSG(st == LIMEN_OK, "renderer: %s", limen_renderer_error(r));
    return r;
}

/* Renders into a new buffer (w*h*3) or returns NULL after a failed check. */
static unsigned char *frame(limen_renderer *r, limen_scene *s, limen_render_opts o)
{
    int w, h;
    limen_renderer_get_size(r, &w, &h);
    unsigned char *rgb = malloc((size_t)w * h * 3);
    limen_status st = limen_render_frame(r, s, &o, NULL);
    CHECK_MSG(st == LIMEN_OK, "render: %s", limen_renderer_error(r));
    if (st || limen_renderer_read_rgb(r, rgb)) {
        free(rgb);
        return NULL;
    }
    return rgb;
}

static double share(const unsigned char *a, const unsigned char *b, int w, int h)
{
    limen_diff d;
    if (!a || !b || limen_image_diff(a, b, w, h, 8, &d, NULL))
        return 1.0;
    return d.bad_share;
}

static void test_methods_and_clips_agree(void)
{
    limen_renderer *r = renderer(W, H);
    for (int i = 0; scenes[i] && r; i++) {
        limen_script *sc = check_load_script(scenes[i]);
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        unsigned char *img[2][3];
        for (int m = 0; m < 2; m++)
            for (int c = 0; c < 3; c++)
                img[m][c] = frame(r, s, (limen_render_opts){ .method = m, .limits.clip = c });
        /* the two renderers of one tree agree, for every clip method */
        for (int c = 0; c < 3; c++) {
            double d = share(img[0][c], img[1][c], W, H);
            CHECK_MSG(d <= 0.005, "%s clip %d: stencil and texture differ on %.2f%%", scenes[i],
                      c, 100 * d);
        }
        /* the oblique near plane and the user clip plane cut the same thing */
        double d = share(img[0][0], img[0][1], W, H);
        CHECK_MSG(d <= 0.005, "%s: oblique and plane differ on %.2f%%", scenes[i], 100 * d);
        for (int m = 0; m < 2; m++)
            for (int c = 0; c < 3; c++)
                free(img[m][c]);
        limen_script_destroy(sc);
    }
    limen_renderer_destroy(r);
}

/* Nothing behind the mirror shows in it with oblique or plane clipping; with none it does. */
static void test_mirror_room_hides_what_is_behind(void)
{
    limen_script *sc = check_load_script("scenes/mirror_room.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_renderer *r = renderer(W, H);
    const char *behind[] = { "behind", "back wall" };
    /* the mirror's own pixels: where it shows a magenta fill with recursion off */
    limen_node mirror;
    CHECK_OK(limen_node_find(s, "mirror", &mirror));
    float fill[3];
    CHECK_OK(limen_surface_get(s, mirror, NULL, NULL, fill, NULL));
    CHECK_OK(limen_surface_set_fill(s, mirror, (float[3]){ 1, 0, 1 }));
    limen_render_opts no_recursion = { .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP } };
    unsigned char *mask = r ? frame(r, s, no_recursion) : NULL;
    CHECK_OK(limen_surface_set_fill(s, mirror, fill));
    for (int c = 0; c < 3 && mask; c++) {
        limen_render_opts o = { .limits.clip = c };
        unsigned char *with = frame(r, s, o);
        const limen_plan *p = limen_renderer_plan(r);
        CHECK(limen_plan_count(p) >= 2);
        const limen_view *mv = limen_plan_view(p, 1);
        limen_node n;
        for (int k = 0; k < 2; k++) {
            CHECK_OK(limen_node_find(s, behind[k], &n));
            CHECK_OK(limen_node_set_visible(s, n, 0));
        }
        unsigned char *without = frame(r, s, o);
        for (int k = 0; k < 2; k++) {
            CHECK_OK(limen_node_find(s, behind[k], &n));
            CHECK_OK(limen_node_set_visible(s, n, 1));
        }
        /* count changed pixels where the mirror is */
        long changed = 0, total = 0;
        if (with && without && mv) {
            for (size_t k = 0; k < (size_t)W * H * 3; k += 3) {
                if (mask[k] != 255 || mask[k + 1] != 0 || mask[k + 2] != 255)
                    continue;
                total++;
                changed += memcmp(with + k, without + k, 3) != 0;
            }
        }
        CHECK(total > W * H / 20);
        if (c == LIMEN_CLIP_NONE)
            CHECK_MSG(changed > total / 10, "clip none: only %ld of %ld mirror pixels changed",
                      changed, total);
        else
            CHECK_MSG(changed == 0, "clip %d: %ld of %ld mirror pixels show what is behind it",
                      c, changed, total);
        free(with);
        free(without);
    }
    free(mask);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
}

static int count_mirrors_above(const limen_plan *p, const limen_view *v)
{
    int n = 0;
    for (; v && v->parent >= 0; v = limen_plan_view(p, v->parent))
        n += v->kind == LIMEN_VIEW_MIRROR;
    return n;
}

static limen_plan *plan_scene(limen_scene *s, limen_plan_desc d)
{
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    d.width = W;
    d.height = H;
    limen_status st = limen_plan_build(p, s, &d);
    CHECK_MSG(st == LIMEN_OK, "plan: %s", limen_scene_error(s));
    return p;
}

static void test_corridor_depth_16(void)
{
    limen_script *sc = check_load_script("scenes/corridor.lua");
    if (!sc)
        return;
    limen_plan *p = plan_scene(limen_script_scene(sc),
                               (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                              .depth = 16 } });
    int per_level[17] = { 0 };
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i);
        if (v->depth <= 16)
            per_level[v->depth]++;
        CHECK(v->front_face_cw == (v->depth & 1));
    }
    for (int d = 0; d <= 16; d++)
        CHECK_MSG(per_level[d] == 1, "level %d has %d views", d, per_level[d]);
    CHECK(limen_plan_count(p) == 17);
    limen_plan_destroy(p);
    limen_script_destroy(sc);
}

static void test_kaleidoscope_budget(void)
{
    limen_script *sc = check_load_script("scenes/kaleidoscope.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_plan *p = plan_scene(s,
                               (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                              .depth = 8 } });
    /* the documented default budget is 1024 views */
    CHECK(limen_plan_count(p) <= 1024);
    int deepest = 0;
    for (int i = 0; i < limen_plan_count(p); i++)
        deepest = limen_plan_view(p, i)->depth > deepest ? limen_plan_view(p, i)->depth : deepest;
    CHECK(deepest >= 3 && deepest <= 8);
    printf("     kaleidoscope depth 8 at %dx%d: %d views, deepest %d, %d stopped by limits\n", W,
           H, limen_plan_count(p), deepest, limen_plan_truncated(p));
    limen_plan_destroy(p);
    /* a small budget holds, and is spent on the shallow levels first */
    p = plan_scene(s, (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                     .depth = 8, .max_views = 10 } });
    CHECK(limen_plan_count(p) == 10);
    int shallow = 0;
    for (int i = 0; i < limen_plan_count(p); i++)
        shallow += limen_plan_view(p, i)->depth <= 2;
    CHECK(shallow == 10);
    limen_plan_destroy(p);
    limen_script_destroy(sc);
}

/* The winding flips at mirrors and only at mirrors, in every scene. */
static void test_winding(void)
{
    for (int i = 0; scenes[i]; i++) {
        limen_script *sc = check_load_script(scenes[i]);
        if (!sc)
            continue;
        limen_plan *p = plan_scene(limen_script_scene(sc), (limen_plan_desc){ 0 });
        for (int k = 0; k < limen_plan_count(p); k++) {
            const limen_view *v = limen_plan_view(p, k);
            CHECK_MSG(v->front_face_cw == (count_mirrors_above(p, v) & 1), "%s view %d",
                      scenes[i], k);
        }
        limen_plan_destroy(p);
        limen_script_destroy(sc);
    }
}

static void test_portal_mirror_chain(void)
{
    limen_script *sc = check_load_script("scenes/portal_mirror.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_plan *p = plan_scene(s, (limen_plan_desc){ 0 });
    /* a portal seen in the mirror, and the far mirror seen through that portal */
    bool portal_in_mirror = false, mirror_in_portal = false;
    for (int k = 0; k < limen_plan_count(p); k++) {
        const limen_view *v = limen_plan_view(p, k);
        const limen_view *u = v->parent >= 0 ? limen_plan_view(p, v->parent) : NULL;
        if (u && v->kind == LIMEN_VIEW_PORTAL && u->kind == LIMEN_VIEW_MIRROR)
            portal_in_mirror = true;
        if (u && v->kind == LIMEN_VIEW_MIRROR && u->kind == LIMEN_VIEW_PORTAL)
            mirror_in_portal = true;
    }
    CHECK(portal_in_mirror);
    CHECK(mirror_in_portal);
    limen_plan_destroy(p);
    limen_script_destroy(sc);
}

static void test_moving_portal_moves(void)
{
    limen_script *sc = check_load_script("scenes/moving_portal.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    CHECK(limen_script_animated(sc));
    limen_renderer *r = renderer(W, H);
    if (!r)
        return;
    int rect[2][4];
    unsigned char *img[2];
    for (int f = 0; f < 2; f++) {
        CHECK_OK(limen_script_update(sc, f ? 1.3 : 0.0));
        img[f] = frame(r, s, (limen_render_opts){ 0 });
        const limen_view *v = limen_plan_view(limen_renderer_plan(r), 1);
        CHECK(v != NULL && v->kind == LIMEN_VIEW_PORTAL);
        if (v)
            memcpy(rect[f], v->scissor, sizeof rect[f]);
    }
    /* the portal's screen rectangle follows its node */
    CHECK(rect[0][0] != rect[1][0]);
    CHECK(share(img[0], img[1], W, H) > 0.01);
    free(img[0]);
    free(img[1]);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
}

static void test_texture_scale(void)
{
    limen_script *sc = check_load_script("scenes/corridor.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_renderer *r = renderer(W, H);
    unsigned char *full = frame(r, s, (limen_render_opts){ .method = LIMEN_METHOD_TEXTURE });
    unsigned char *half = frame(r, s, (limen_render_opts){ .method = LIMEN_METHOD_TEXTURE,
                                                           .texture_scale = 0.5f });
    double d = share(full, half, W, H);
    /* lower resolution blurs the reflections: some difference, but the same picture */
    CHECK_MSG(d > 0.001 && d < 0.25, "texture scale 0.5 differs on %.2f%%", 100 * d);
    CHECK(limen_render_frame(r, s, &(limen_render_opts){ .texture_scale = 1.5f }, NULL) ==
          LIMEN_ERR_ARG);
    free(full);
    free(half);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
}

/* Column-major M * (p, 1) with the perspective divide. */
static void project(const float m[16], const float p[3], float out[3])
{
    float r[4];
    for (int i = 0; i < 4; i++)
        r[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
    for (int i = 0; i < 3; i++)
        out[i] = r[i] / r[3];
}

static void mat_mul(const float a[16], const float b[16], float out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float v = 0;
            for (int k = 0; k < 4; k++)
                v += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = v;
        }
}

/* A marker must appear exactly where its image through the surface must be: the marker's
 * position carried back through the surface (X^-1 p), projected by the real camera. With
 * ambient 1 the marker's colour is its albedo, exactly. */
static void marker_through(limen_node_kind kind)
{
    limen_scene *s;
    limen_node cam, a, b = { 0 }, marker;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_scene_set_ambient(s, 1));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0.4f, 1.2f, 3 }, (float[3]){ 0, 1, -2 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_node_create(s, kind, "a", &a));
    CHECK_OK(limen_node_set_position(s, a, (float[3]){ 0, 1, -2 }));
    CHECK_OK(limen_node_set_rotation(s, a, (float[3]){ 0.1f, 0.3f, 0 }));
    CHECK_OK(limen_node_set_dims(s, a, (float[3]){ 3, 2, 0 }));
    float where[3] = { 0.5f, 0.9f, 4.0f };     /* in front of the mirror, behind the camera */
    if (kind == LIMEN_NODE_PORTAL) {
        CHECK_OK(limen_node_create(s, kind, "b", &b));
        CHECK_OK(limen_node_set_position(s, b, (float[3]){ 10, 1, 0 }));
        CHECK_OK(limen_node_set_rotation(s, b, (float[3]){ 0, -1.2f, 0.05f }));
        CHECK_OK(limen_node_set_dims(s, b, (float[3]){ 4.5f, 3, 0 }));
        CHECK_OK(limen_portal_link(s, a, b));
        /* in front of b, where the view through a comes out */
        float wb[16];
        CHECK_OK(limen_node_world_matrix(s, b, wb));
        float local[3] = { 0.3f, -0.2f, 2.5f };
        project(wb, local, where);
    }
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "marker", &marker));
    CHECK_OK(limen_node_set_position(s, marker, where));
    CHECK_OK(limen_node_set_dims(s, marker, (float[3]){ 0.06f, 0, 0 }));
    CHECK_OK(limen_node_set_color(s, marker, (float[3]){ 0, 1, 0 }));

    const int w = 320, h = 240;
    limen_renderer *r = renderer(w, h);
    for (int m = 0; m < 2 && r; m++) {
        unsigned char *img = frame(r, s, (limen_render_opts){ .method = m });
        float x[16], xinv_p[3], view[16], proj[16], vp[16], ndc[3];
        CHECK_OK(limen_surface_matrix(s, a, x));
        /* X^-1 p: solve by carrying p through the inverse of a rigid-plus-scale X */
        {
            double det = 0;
            (void)det;
            /* invert the 3x3 part and the translation numerically (Cramer) */
            double m3[9] = { x[0], x[1], x[2], x[4], x[5], x[6], x[8], x[9], x[10] };
            double c[3] = { where[0] - x[12], where[1] - x[13], where[2] - x[14] };
            double d = m3[0] * (m3[4] * m3[8] - m3[7] * m3[5]) -
                       m3[3] * (m3[1] * m3[8] - m3[7] * m3[2]) +
                       m3[6] * (m3[1] * m3[5] - m3[4] * m3[2]);
            for (int k = 0; k < 3; k++) {
                double t[9];
                memcpy(t, m3, sizeof t);
                t[k * 3 + 0] = c[0];
                t[k * 3 + 1] = c[1];
                t[k * 3 + 2] = c[2];
                double dk = t[0] * (t[4] * t[8] - t[7] * t[5]) - t[3] * (t[1] * t[8] - t[7] * t[2]) +
                            t[6] * (t[1] * t[5] - t[4] * t[2]);
                xinv_p[k] = (float)(dk / d);
            }
        }
        CHECK_OK(limen_camera_matrices(s, (float)w / h, LIMEN_DEPTH_NO, view, proj));
        mat_mul(proj, view, vp);
        project(vp, xinv_p, ndc);
        int px = (int)((ndc[0] + 1) * 0.5f * w), py = (int)((1 - ndc[1]) * 0.5f * h);
        CHECK_MSG(px > 0 && px < w && py > 0 && py < h, "marker image off screen (%d, %d)", px, py);
        if (img && px > 0 && px < w && py > 0 && py < h) {
            const unsigned char *c = img + ((size_t)py * w + px) * 3;
            CHECK_MSG(c[0] == 0 && c[1] == 255 && c[2] == 0,
                      "%s, method %d: pixel (%d, %d) is (%d %d %d), not the marker",
                      kind == LIMEN_NODE_MIRROR ? "mirror" : "portal", m, px, py, c[0], c[1], c[2]);
            /* and the marker does not show where the portal matrix without its half turn
             * would put it (in front of a, mirrored left-right and in depth) */
            float wa[16], unturned[3], local[3] = { -0.3f, -0.2f, 2.5f };
            CHECK_OK(limen_node_world_matrix(s, a, wa));
            project(wa, local, unturned);
            project(vp, unturned, ndc);
            int qx = (int)((ndc[0] + 1) * 0.5f * w), qy = (int)((1 - ndc[1]) * 0.5f * h);
            if (kind == LIMEN_NODE_PORTAL && qx > 0 && qx < w && qy > 0 && qy < h &&
                (abs(qx - px) > 4 || abs(qy - py) > 4)) {
                const unsigned char *q = img + ((size_t)qy * w + qx) * 3;
                CHECK(!(q[0] == 0 && q[1] == 255 && q[2] == 0));
            }
        }
        free(img);
    }
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

static void test_marker_in_mirror(void)
{
    marker_through(LIMEN_NODE_MIRROR);
}

static void test_marker_through_portal(void)
{
    marker_through(LIMEN_NODE_PORTAL);
}

/* Where recursion stops, the previous frame's picture of the surface continues the corridor:
 * at depth 3 it comes closer to the depth-16 picture than the fill colour does (measured at
 * 160x120: 0.76% of pixels off against 1.13%), for both
 * renderers. */
static void test_fill_previous(void)
{
    limen_script *sc = check_load_script("scenes/corridor.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_renderer *r = renderer(W, H);
    limen_render_opts depth16 = { .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 16 } };
    unsigned char *deep = frame(r, s, depth16);
    for (int m = 0; m < 2 && deep; m++) {
        limen_render_opts o = { .method = m, .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                         .depth = 3 } };
        unsigned char *plain = frame(r, s, o);
        o.fill = LIMEN_FILL_PREVIOUS;
        unsigned char *prev = NULL;
        for (int f = 0; f < 3; f++) {
            free(prev);
            prev = frame(r, s, o);
        }
        double d_plain = share(plain, deep, W, H), d_prev = share(prev, deep, W, H);
        CHECK_MSG(d_prev < 0.8 * d_plain, "method %d: fill previous %.2f%%, colour %.2f%% from depth 16",
                  m, 100 * d_prev, 100 * d_plain);
        free(plain);
        free(prev);
    }
    free(deep);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
}

/* The oblique projection in all three clip-space conventions cuts the same picture. */
static void test_depth_modes_agree(void)
{
    const char *some[] = { "scenes/mirror_room.lua", "scenes/corridor.lua", "scenes/portals.lua",
                           "scenes/tunnel.lua", NULL };
    for (int i = 0; some[i]; i++) {
        limen_script *sc = check_load_script(some[i]);
        if (!sc)
            continue;
        unsigned char *img[3] = { NULL, NULL, NULL };
        for (int m = 0; m < 3; m++) {
            limen_renderer *r = NULL;
            limen_status st = limen_renderer_create(
                &(limen_renderer_desc){ .width = W, .height = H, .depth_range = m }, &r);
            CHECK_MSG(st == LIMEN_OK, "depth mode %d: %s", m, limen_renderer_error(r));
            if (!st)
                img[m] = frame(r, limen_script_scene(sc), (limen_render_opts){ 0 });
            limen_renderer_destroy(r);
        }
        for (int m = 1; m < 3; m++) {
            double d = share(img[0], img[m], W, H);
            CHECK_MSG(d <= 0.005, "%s: depth mode %d differs from no on %.2f%%", some[i], m,
                      100 * d);
        }
        for (int m = 0; m < 3; m++)
            free(img[m]);
        limen_script_destroy(sc);
    }
}

static const check_case cases[] = {
    { "depth_modes_agree", test_depth_modes_agree },
    { "fill_previous", test_fill_previous },
    { "marker_in_mirror", test_marker_in_mirror },
    { "marker_through_portal", test_marker_through_portal },
    { "methods_and_clips_agree", test_methods_and_clips_agree },
    { "mirror_room_hides_what_is_behind", test_mirror_room_hides_what_is_behind },
    { "corridor_depth_16", test_corridor_depth_16 },
    { "kaleidoscope_budget", test_kaleidoscope_budget },
    { "winding", test_winding },
    { "portal_mirror_chain", test_portal_mirror_chain },
    { "moving_portal_moves", test_moving_portal_moves },
    { "texture_scale", test_texture_scale },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
