/* test_truth.c - the rasterizer against the ray-traced truth: every gallery scene, both
 * methods, oblique and plane clipping, depths 0, 1, 2 and the scene's own, at 320x240 and
 * 640x480, and scenes whose surfaces cross each other. At most 0.5% of pixels may differ by more than 8/255 in any channel. And the
 * metric has teeth: clipping switched off, or a portal without its half turn, fails it by a
 * wide margin. Prints one line per scene and size with the worst share and the times. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "hall.h"
#include "limen.h"
#include "load.h"
#include "core/testing.h"

#define BOUND 0.005

static const char *const scenes[] = {
    "plain", "mirror_room", "corridor", "kaleidoscope", "periscope", "water", "portals",
    "tunnel", "portal_mirror", "portal_sizes", "moving_portal", "flythrough",
    "hall_of_mirrors", "portal_rooms", "portal_statue", "level", "materials", NULL,
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static limen_script *load(const char *name)
{
    char path[256];
    snprintf(path, sizeof path, strchr(name, '/') ? "%s" : "scenes/%s.lua", name);
    return check_load_script(path);
}

/* depth < 0: the scene's own limits, else capped at depth */
static limen_limits depth_limits(int depth)
{
    return depth < 0 ? (limen_limits){ 0 }
                     : (limen_limits){ .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = depth };
}

static unsigned char *trace(limen_scene *s, int w, int h, int depth, double *ms)
{
    unsigned char *rgb = malloc((size_t)w * h * 3);
    double t0 = now_ms();
    limen_status st = limen_trace_image(
        s, &(limen_trace_desc){ .width = w, .height = h, .limits = depth_limits(depth) },
        rgb);
    *ms = now_ms() - t0;
    CHECK_MSG(st == LIMEN_OK, "trace: %s", limen_scene_error(s));
    return rgb;
}

static double bad_share(limen_renderer *r, limen_scene *s, limen_render_opts o,
                        const unsigned char *truth, int w, int h, double *ms)
{
    unsigned char *rgb = malloc((size_t)w * h * 3);
    limen_frame_stats st = { 0 };
    limen_status rc = limen_render_frame(r, s, &o, &st);
    CHECK_MSG(rc == LIMEN_OK, "render: %s", limen_renderer_error(r));
    limen_diff d = { 1.0, 0, 0, 0 };
    if (!rc && !limen_renderer_read_rgb(r, rgb))
        limen_image_diff(rgb, truth, w, h, 8, &d, NULL);
    if (ms)
        *ms = st.ms;
    free(rgb);
    return d.bad_share;
}

/* Every scene of the list, both methods, both clip methods, depths 0, 1, 2 and the
 * scene's own, against the truth. */
static void scenes_at(const char *const *list, int w, int h)
{
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r);
    CHECK_MSG(st == LIMEN_OK, "renderer: %s", limen_renderer_error(r));
    const int depths[] = { 0, 1, 2, -1 };
    for (int i = 0; list[i] && !st; i++) {
        limen_script *sc = load(list[i]);
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        double worst[2] = { 0, 0 }, trace_ms = 0, render_ms[2] = { 0, 0 };
        for (int k = 0; k < 4; k++) {
            double tms;
            unsigned char *truth = trace(s, w, h, depths[k], &tms);
            if (depths[k] < 0)
                trace_ms = tms;
            for (int m = 0; m < 2; m++) {
                for (int c = 0; c < 2; c++) {
                    limen_render_opts o = { .method = m, .limits = depth_limits(depths[k]) };
                    o.limits.clip = c;
                    double rms = 0;
                    double d = bad_share(r, s, o, truth, w, h, &rms);
                    if (depths[k] < 0 && c == 0)
                        render_ms[m] = rms;
                    worst[m] = d > worst[m] ? d : worst[m];
                    CHECK_MSG(d <= BOUND, "%s %dx%d %s clip %s depth %d: %.3f%% of pixels off",
                              list[i], w, h, m ? "texture" : "stencil", c ? "plane" : "oblique",
                              depths[k], 100 * d);
                }
            }
            free(truth);
        }
        /* worst over depths and clip methods; times at the scene's own depth, oblique */
        printf("     %-14s %dx%d  worst: stencil %.3f%%, texture %.3f%%  trace %.0f ms, "
               "render: stencil %.1f ms, texture %.1f ms\n",
               list[i], w, h, 100 * worst[0], 100 * worst[1], trace_ms, render_ms[0],
               render_ms[1]);
        limen_script_destroy(sc);
    }
    limen_renderer_destroy(r);
}

static void test_gallery_320x240(void)
{
    scenes_at(scenes, 320, 240);
}

static void test_gallery_640x480(void)
{
    scenes_at(scenes, 640, 480);
}

/* Surfaces that cross the exit plane of a nested view: mirror walls wider than their room,
 * poking through their neighbours; leaning walls and an X of mirrors crossing each other;
 * mirror fins reaching through a portal's wall and opening. What lies beyond the exit plane
 * must be cut there in every view, the surfaces (drawn with depth clamping) included. */
static void test_crossing_surfaces(void)
{
    static const char *const crossing[] = {
        "tests/scenes/mirror_box_crossing.lua", "tests/scenes/mirror_cross.lua",
        "tests/scenes/portal_crossing.lua", NULL,
    };
    scenes_at(crossing, 320, 240);
}

/* A scene with its camera ("eye", the scene's), a lamp and two nodes of the kinds given, and
 * a renderer of w x h; false (both gone, the failure checked) if they cannot be made. */
static bool stage(int w, int h, limen_scene **s, limen_renderer **r, limen_node *cam,
                  limen_node *lamp, limen_node_kind ka, const char *na, limen_node *a,
                  limen_node_kind kb, const char *nb, limen_node *b)
{
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, s));
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, r));
    if (!*s || !*r || limen_node_create(*s, LIMEN_NODE_CAMERA, "eye", cam) ||
        limen_node_create(*s, LIMEN_NODE_LIGHT, "lamp", lamp) ||
        limen_node_create(*s, ka, na, a) || limen_node_create(*s, kb, nb, b) ||
        limen_scene_set_camera(*s, *cam)) {
        CHECK_MSG(0, "scene: %s", *s ? limen_scene_error(*s) : "none");
        limen_scene_destroy(*s);
        limen_renderer_destroy(*r);
        return false;
    }
    return true;
}

/* Tiled textures (limen_node_set_texture_repeat), by amounts that are not whole, on a plane
 * and a box: both methods stay within the bound of the truth, and the tiling shows (the
 * frame is far from the untiled one). */
static void test_texture_repeat(void)
{
    const int w = 320, h = 240;
    limen_scene *s = NULL;
    limen_renderer *r = NULL;
    limen_node cam, lamp, wall, crate;
    if (!stage(w, h, &s, &r, &cam, &lamp, LIMEN_NODE_QUAD, "wall", &wall, LIMEN_NODE_BOX, "crate",
               &crate))
        return;
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0.6f, 0.8f, 3.2f }, (float[3]){ 0, 0.4f, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_position(s, lamp, (float[3]){ 1, 2.5f, 2 }));
    CHECK_OK(limen_node_set_dims(s, wall, (float[3]){ 4, 3, 0 }));
    CHECK_OK(limen_node_set_position(s, wall, (float[3]){ 0, 0.5f, -0.6f }));
    CHECK_OK(limen_node_set_texture(s, wall, "scenes/data/bricks.png"));
    CHECK_OK(limen_node_set_position(s, crate, (float[3]){ 0.2f, 0.2f, 0.5f }));
    CHECK_OK(limen_node_set_rotation(s, crate, (float[3]){ 0.3f, 0.6f, 0 }));
    CHECK_OK(limen_node_set_dims(s, crate, (float[3]){ 0.9f, 0.7f, 0.8f }));
    CHECK_OK(limen_node_set_texture(s, crate, "scenes/data/tiles.png"));
    double ms;
    unsigned char *plain = trace(s, w, h, -1, &ms);
    CHECK_OK(limen_node_set_texture_repeat(s, wall, (float[2]){ 2.6f, 1.7f }));
    CHECK_OK(limen_node_set_texture_repeat(s, crate, (float[2]){ 1.5f, 2.25f }));
    unsigned char *truth = trace(s, w, h, -1, &ms);
    limen_diff tiled;
    CHECK_OK(limen_image_diff(plain, truth, w, h, 8, &tiled, NULL));
    CHECK_MSG(tiled.bad_share > 0.3, "tiling changed only %.1f%% of the pixels",
              100 * tiled.bad_share);
    for (int m = 0; m < 2; m++) {
        double d = bad_share(r, s, (limen_render_opts){ .method = m }, truth, w, h, NULL);
        printf("     tiled wall and crate, %s: %.3f%% of pixels off\n", m ? "texture" : "stencil",
               100 * d);
        CHECK_MSG(d <= BOUND, "%.3f%% of pixels off", 100 * d);
    }
    free(plain);
    free(truth);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* Mean absolute difference of two RGB images over every channel, in 8-bit steps. */
static double mean_error(const unsigned char *a, const unsigned char *b, size_t n)
{
    double sum = 0;
    for (size_t i = 0; i < n * 3; i++)
        sum += abs((int)a[i] - (int)b[i]);
    return sum / (double)(n * 3);
}

/* Filter f on test_mipmaps' floor and wall. */
static void floor_filter(limen_scene *s, limen_node floor, limen_texture_filter f)
{
    CHECK_OK(limen_node_set_texture_filter(s, floor, f));
    limen_node wall;
    if (limen_node_find(s, "wall", &wall) == LIMEN_OK)
        CHECK_OK(limen_node_set_texture_filter(s, wall, f));
}

/* Mipmaps (limen_node_set_texture_filter): a distant tiled floor and a sloping mesh wall,
 * directly, in a mirror and through a scaled portal. With every filter both methods stay within the bound of the
 * truth (the tracer picks each pixel's level from its ray differentials as OpenGL does from
 * its neighbours). Against an area-averaged truth (a trace at 4 x 4 the pixels with the full
 * image, box-filtered down), the trilinear frames, traced and rendered, are at least twice
 * as close as the frames without mipmaps, which speckle in the distance. */
static void test_mipmaps(void)
{
    const int w = 320, h = 240, k = 4;
    limen_scene *s = NULL;
    limen_renderer *r = NULL;
    limen_node cam, lamp, floor, mirror, a, b;
    if (!stage(w, h, &s, &r, &cam, &lamp, LIMEN_NODE_QUAD, "floor", &floor, LIMEN_NODE_MIRROR,
               "mirror", &mirror))
        return;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "a", &a));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "b", &b));
    /* looking down on it from 10 m: the tiles shrink to a few pixels and less */
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0, 10, 4 }, (float[3]){ 0.3f, 0, -8 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_position(s, lamp, (float[3]){ 0, 6, 0 }));
    CHECK_OK(limen_node_set_rotation(s, floor, (float[3]){ -1.5707963f, 0, 0 }));
    CHECK_OK(limen_node_set_position(s, floor, (float[3]){ 0, 0, -20 }));
    CHECK_OK(limen_node_set_dims(s, floor, (float[3]){ 60, 60, 0 }));
    CHECK_OK(limen_node_set_texture(s, floor, "scenes/data/tiles.png"));
    CHECK_OK(limen_node_set_texture_repeat(s, floor, (float[2]){ 80, 80 }));
    /* the mirror's front (+Z) away from the point it "looks at" */
    CHECK_OK(limen_node_look_at(s, mirror, (float[3]){ 2.6f, 1.4f, -3 }, (float[3]){ 3.6f, 1.6f, -5 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, mirror, (float[3]){ 2.2f, 2, 0 }));
    CHECK_OK(limen_node_look_at(s, a, (float[3]){ -2.2f, 1.1f, -1 }, (float[3]){ -2.2f, 1.1f, -9 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, a, (float[3]){ 1.6f, 1.6f, 0 }));
    CHECK_OK(limen_node_look_at(s, b, (float[3]){ 4, 2.5f, -14 }, (float[3]){ 2, 3.5f, -10 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, b, (float[3]){ 3.2f, 3.2f, 0 }));
    CHECK_OK(limen_portal_link(s, a, b));
    /* a wall of triangles with texture coordinates of their own, sloping away: its level
     * comes from the triangle's texture-coordinate gradient */
    limen_node wall;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "wall", &wall));
    static const float wall_pos[] = { 0, 0, 0, 12, 0, -14, 12, 3, -14, 0, 2, 0 };
    static const float wall_uv[] = { 0, 0, 6, 0, 6, 1.5f, 0, 1 };
    static const uint32_t wall_idx[] = { 0, 1, 2, 0, 2, 3 };
    CHECK_OK(limen_mesh_set_triangles(s, wall, &(limen_mesh_data){
        .positions = wall_pos, .uvs = wall_uv, .vertex_count = 4, .indices = wall_idx,
        .triangle_count = 2 }));
    CHECK_OK(limen_node_set_position(s, wall, (float[3]){ -9, 0, -1 }));
    CHECK_OK(limen_node_set_texture(s, wall, "scenes/data/bricks.png"));
    CHECK_OK(limen_node_set_texture_repeat(s, wall, (float[2]){ 4, 4 }));
    /* the area-averaged truth */
    floor_filter(s, floor, LIMEN_FILTER_LINEAR);
    unsigned char *big = malloc((size_t)w * h * k * k * 3), *area = malloc((size_t)w * h * 3);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = w * k, .height = h * k }, big));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                int sum = 0;
                for (int j = 0; j < k; j++)
                    for (int i = 0; i < k; i++)
                        sum += big[(((size_t)(y * k + j) * w * k) + (size_t)(x * k + i)) * 3 + c];
                area[((size_t)y * w + x) * 3 + c] = (unsigned char)((sum + k * k / 2) / (k * k));
            }
    free(big);
    const limen_texture_filter filters[3] = { LIMEN_FILTER_TRILINEAR, LIMEN_FILTER_LINEAR,
                                              LIMEN_FILTER_NEAREST };
    const char *names[3] = { "trilinear", "linear", "nearest" };
    double err[3][3];   /* filter; trace, stencil, texture */
    unsigned char *rgb = malloc((size_t)w * h * 3);
    for (int f = 0; f < 3; f++) {
        floor_filter(s, floor, filters[f]);
        double ms;
        unsigned char *truth = trace(s, w, h, -1, &ms);
        err[f][0] = mean_error(truth, area, (size_t)w * h);
        for (int m = 0; m < 2; m++) {
            double d = bad_share(r, s, (limen_render_opts){ .method = m }, truth, w, h, NULL);
            CHECK_MSG(d <= BOUND, "%s, %s: %.3f%% of pixels off", names[f],
                      m ? "texture" : "stencil", 100 * d);
            limen_render_frame(r, s, &(limen_render_opts){ .method = m }, NULL);
            CHECK_OK(limen_renderer_read_rgb(r, rgb));
            err[f][1 + m] = mean_error(rgb, area, (size_t)w * h);
            printf("     tiled floor, %s, %s: %.3f%% of pixels off the trace; mean error to "
                   "the area average: trace %.2f, render %.2f\n", names[f],
                   m ? "texture" : "stencil", 100 * d, err[f][0], err[f][1 + m]);
        }
        free(truth);
    }
    for (int i = 0; i < 3; i++)
        CHECK_MSG(2 * err[0][i] <= err[1][i],
                  "%s: trilinear %.2f from the area average, linear %.2f (not twice as far)",
                  i == 0 ? "trace" : i == 1 ? "stencil" : "texture", err[0][i], err[1][i]);
    free(rgb);
    free(area);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* Meshes are not convex: drawn first in a view that sees no surface (the camera's here, and
 * the mirror's), a bunny must still hide its own far side. Its levels of detail, picked per
 * view under a pixel of error, stay within the bound of the full mesh's truth. */
static void test_statue(void)
{
    const int w = 320, h = 240;
    limen_scene *s = NULL;
    limen_renderer *r = NULL;
    limen_node cam, lamp, bunny, mirror;
    if (!stage(w, h, &s, &r, &cam, &lamp, LIMEN_NODE_MESH, "bunny", &bunny, LIMEN_NODE_MIRROR,
               "mirror", &mirror))
        return;
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0.2f, 0.9f, 1.6f }, (float[3]){ 0, 0.6f, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_position(s, lamp, (float[3]){ 2, 3, 3 }));
    CHECK_OK(limen_mesh_load(s, bunny, "scenes/data/bunny.obj"));
    CHECK_OK(limen_node_set_scale(s, bunny, (float[3]){ 0.1f, 0.1f, 0.1f }));
    CHECK_OK(limen_node_set_color(s, bunny, (float[3]){ 0.9f, 0.8f, 0.7f }));
    /* a mirror at the right of the picture, its front (+Z) turned toward the bunny */
    CHECK_OK(limen_node_look_at(s, mirror, (float[3]){ 1.1f, 0.6f, -0.4f },
                                (float[3]){ 2.1f, 0.6f, -1.2f }, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, mirror, (float[3]){ 1.2f, 1.2f, 0 }));
    double ms;
    unsigned char *truth = trace(s, w, h, -1, &ms);
    const float bounds[2] = { LIMEN_LOD_FULL, 0 };
    for (int m = 0; m < 2; m++)
        for (int b = 0; b < 2; b++) {
            limen_render_opts o = { .method = m, .limits.lod_pixels = bounds[b] };
            double d = bad_share(r, s, o, truth, w, h, NULL);
            printf("     bunny and a mirror, %s, %s: %.3f%% of pixels off\n",
                   m ? "texture" : "stencil", b ? "levels of detail" : "full mesh", 100 * d);
            CHECK_MSG(d <= BOUND, "%.3f%% of pixels off", 100 * d);
        }
    free(truth);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* A field of statues before a mirror: the bunnies share one mesh, so each view draws them
 * in a few batches (one per level of detail in use), not one call each; each keeps its own
 * turn and colour (per-instance values). With the full mesh the picture stays within the
 * bound, flat and smooth; at the default level-of-detail bound it draws a fraction of the
 * triangles and stays within 1% (the bound for the field: coarser levels shade
 * with other normals than the full mesh, which the tracer samples). */
static void test_field(void)
{
    const int w = 320, h = 240, n = 100;
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r));
    for (int smooth = 0; smooth < 2 && r; smooth++) {
        limen_scene *s = bunnies_create(n, "scenes/data/bunny.obj", smooth, 7);
        CHECK_MSG(s != NULL, "the field cannot be made");
        if (!s)
            break;
        double ms;
        unsigned char *truth = trace(s, w, h, -1, &ms);
        for (int m = 0; m < 2; m++) {
            limen_frame_stats st[2] = { { 0 } };
            double d[2];
            for (int lod = 0; lod < 2; lod++) {
                limen_render_opts o = { .method = m,
                                        .limits.lod_pixels = lod ? 0 : LIMEN_LOD_FULL };
                CHECK_OK(limen_render_frame(r, s, &o, &st[lod]));
                d[lod] = bad_share(r, s, o, truth, w, h, NULL);
                printf("     %d bunnies (%s) and a mirror, %s, %s: %.3f%% of pixels off, "
                       "%d views, %d draw calls, %llu triangles\n", n,
                       smooth ? "smooth" : "flat", m ? "texture" : "stencil",
                       lod ? "levels of detail" : "full mesh", 100 * d[lod], st[lod].views,
                       st[lod].draw_calls, (unsigned long long)st[lod].triangles);
                CHECK_MSG(st[lod].views == 2, "%d views", st[lod].views);
                CHECK_MSG(st[lod].draw_calls <= 40, "%d draw calls for %d bunnies in %d views",
                          st[lod].draw_calls, n, st[lod].views);
            }
            CHECK_MSG(d[0] <= BOUND, "%.3f%% of pixels off", 100 * d[0]);
            CHECK_MSG(d[1] <= 0.01, "%.3f%% of pixels off with levels of detail", 100 * d[1]);
            CHECK_MSG(2 * st[1].triangles < st[0].triangles,
                      "levels of detail drew %llu triangles, the full mesh %llu",
                      (unsigned long long)st[1].triangles, (unsigned long long)st[0].triangles);
        }
        free(truth);
        limen_scene_destroy(s);
    }
    limen_renderer_destroy(r);
}

/* The metric must catch a wrong picture, by a wide margin. */
static void test_metric_has_teeth(void)
{
    const int w = 320, h = 240;
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r));
    double ms;
    /* no clipping: what stands behind the mirror leaks into it */
    limen_script *sc = load("mirror_room");
    if (sc && r) {
        unsigned char *truth = trace(limen_script_scene(sc), w, h, -1, &ms);
        double d = bad_share(r, limen_script_scene(sc),
                             (limen_render_opts){ .limits.clip = LIMEN_CLIP_NONE },
                             truth, w, h, NULL);
        printf("     mirror_room with --clip none: %.2f%% of pixels off\n", 100 * d);
        CHECK_MSG(d > 10 * BOUND, "clip none is off by only %.3f%%", 100 * d);
        free(truth);
    }
    limen_script_destroy(sc);
    /* a portal matrix without its half turn */
    const char *portal_scenes[] = { "portals", "tunnel", NULL };
    for (int i = 0; portal_scenes[i] && r; i++) {
        sc = load(portal_scenes[i]);
        if (!sc)
            continue;
        unsigned char *truth = trace(limen_script_scene(sc), w, h, -1, &ms);
        for (int m = 0; m < 2; m++) {
            limen__scene_set_faults(limen_script_scene(sc), LIMEN_FAULT_PORTAL_NO_TURN);
            double d = bad_share(r, limen_script_scene(sc), (limen_render_opts){ .method = m },
                                 truth, w, h, NULL);
            limen__scene_set_faults(limen_script_scene(sc), 0);
            printf("     %s with the portal's turn left out (%s): %.2f%% of pixels off\n",
                   portal_scenes[i], m ? "texture" : "stencil", 100 * d);
            CHECK_MSG(d > 4 * BOUND, "a portal without its turn is off by only %.3f%%", 100 * d);
        }
        free(truth);
        limen_script_destroy(sc);
    }
    limen_renderer_destroy(r);
}

/* The stencil method gives each view a stencil value of its own up to 255 views, and counts
 * nesting depth beyond: a tree on each side of that line, against the truth and against the
 * texture method (which uses no stencil). */
static void test_stencil_values(void)
{
    const int w = 320, h = 240;
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r));
    limen_script *sc = load("tests/scenes/mirror_box.lua");
    unsigned char *rgb[2] = { malloc((size_t)w * h * 3), malloc((size_t)w * h * 3) };
    const int depths[2] = { 6, 8 };
    for (int k = 0; k < 2 && sc && r; k++) {
        limen_scene *s = limen_script_scene(sc);
        double ms;
        unsigned char *truth = trace(s, w, h, depths[k], &ms);
        for (int m = 0; m < 2; m++) {
            limen_render_opts o = { .method = m, .limits = depth_limits(depths[k]) };
            CHECK_OK(limen_render_frame(r, s, &o, NULL));
            CHECK_OK(limen_renderer_read_rgb(r, rgb[m]));
        }
        int views = limen_plan_count(limen_renderer_plan(r));
        CHECK_MSG(k == 0 ? views <= 255 : views > 255, "depth %d: %d views, not on the %s side of 255",
                  depths[k], views, k == 0 ? "lower" : "upper");
        limen_diff dt = { 1, 0, 0, 0 }, dm = { 1, 0, 0, 0 };
        limen_image_diff(rgb[0], truth, w, h, 8, &dt, NULL);
        limen_image_diff(rgb[0], rgb[1], w, h, 8, &dm, NULL);
        printf("     mirror_box depth %d, %d views: stencil %.3f%% off the truth, %.4f%% off the "
               "texture method\n", depths[k], views, 100 * dt.bad_share, 100 * dm.bad_share);
        CHECK_MSG(dt.bad_share <= BOUND, "%.3f%% off the truth", 100 * dt.bad_share);
        CHECK_MSG(dm.bad_share <= 0.0005, "%.4f%% off the texture method", 100 * dm.bad_share);
        free(truth);
    }
    free(rgb[0]);
    free(rgb[1]);
    limen_script_destroy(sc);
    limen_renderer_destroy(r);
}

static const check_case cases[] = {
    { "gallery_320x240", test_gallery_320x240 },
    { "stencil_values", test_stencil_values },
    { "crossing_surfaces", test_crossing_surfaces },
    { "gallery_640x480", test_gallery_640x480 },
    { "statue", test_statue },
    { "texture_repeat", test_texture_repeat },
    { "mipmaps", test_mipmaps },
    { "field", test_field },
    { "metric_has_teeth", test_metric_has_teeth },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
