/* test_render.c - the plain renderer: shading against the formula of docs/DESIGN.md, the
 * background, both backends, depth conventions, MSAA, statistics and errors. */
#include <stdlib.h>

#include "check.h"
#include "ray.h"
#include "core/testing.h"
#include "limen.h"

#define W 160
#define H 120

typedef struct fixture {
    limen_scene *s;
    limen_node cam, ball, floor, light;
} fixture;

static const float AMBIENT = 0.25f;
static const float BALL_C[3] = { 0.3f, 1.0f, 0.0f }, BALL_R = 0.6f;
static const float LIGHT[3] = { 2, 4, 3 };
static const float EYE[3] = { 0, 1.2f, 4 };

static void build(fixture *f)
{
    CHECK_OK(limen_scene_create(NULL, &f->s));
    limen_scene *s = f->s;
    CHECK_OK(limen_scene_set_background(s, (float[3]){ 0.1f, 0.2f, 0.3f }));
    CHECK_OK(limen_scene_set_ambient(s, AMBIENT));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &f->cam));
    CHECK_OK(limen_node_look_at(s, f->cam, EYE, BALL_C, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, f->cam));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "light", &f->light));
    CHECK_OK(limen_node_set_position(s, f->light, LIGHT));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &f->ball));
    CHECK_OK(limen_node_set_position(s, f->ball, BALL_C));
    CHECK_OK(limen_node_set_dims(s, f->ball, (float[3]){ BALL_R, 0, 0 }));
    CHECK_OK(limen_node_set_color(s, f->ball, (float[3]){ 1, 0.5f, 0 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "floor", &f->floor));
    CHECK_OK(limen_node_set_facing(s, f->floor, (float[3]){ 0, 1, 0 }, NULL));
    CHECK_OK(limen_node_set_dims(s, f->floor, (float[3]){ 6, 6, 0 }));
    CHECK_OK(limen_node_set_checker(s, f->floor, (float[3]){ 0.8f, 0.8f, 0.8f },
                                    (float[3]){ 0.2f, 0.2f, 0.2f }, 1.0f));
}

static unsigned char *render(limen_scene *s, limen_renderer_desc d, limen_frame_stats *st)
{
    limen_renderer *r = NULL;
    d.width = W;
    d.height = H;
    limen_status rc = limen_renderer_create(&d, &r);
    CHECK_MSG(rc == LIMEN_OK, "renderer_create: %s", r ? limen_renderer_error(r) : "");
    unsigned char *rgb = calloc(W * H * 3, 1);
    if (!rc) {
        CHECK_OK(limen_render_frame(r, s, NULL, st));
        CHECK_OK(limen_renderer_read_rgb(r, rgb));
    }
    limen_renderer_destroy(r);
    return rgb;
}

/* The ray through the centre of pixel (x, y) (row 0 at the top), from the camera's matrices,
 * as a rasterizer samples it. */
static void pixel_ray(limen_scene *s, int x, int y, double o[3], double d[3])
{
    float view[16], proj[16];
    limen_camera_matrices(s, (float)W / H, LIMEN_DEPTH_NO, view, proj);
    double ndc_x = 2.0 * (x + 0.5) / W - 1.0, ndc_y = 1.0 - 2.0 * (y + 0.5) / H;
    /* view-space direction: x * tan, y * tan, -1 (proj is a symmetric perspective) */
    double vx = ndc_x / proj[0], vy = ndc_y / proj[5], vz = -1.0;
    /* view is rigid: world direction = R^T v, eye = -R^T t */
    for (int i = 0; i < 3; i++) {
        d[i] = view[i * 4 + 0] * vx + view[i * 4 + 1] * vy + view[i * 4 + 2] * vz;
        o[i] = -(view[i * 4 + 0] * view[12] + view[i * 4 + 1] * view[13] +
                 view[i * 4 + 2] * view[14]);
    }
}

/* docs/DESIGN.md's shading formula at point p with normal n, in 8-bit. */
static void shade(const double p[3], const double n[3], const float albedo[3], int out[3])
{
    double l[3] = { LIGHT[0] - p[0], LIGHT[1] - p[1], LIGHT[2] - p[2] };
    double ll = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    double nl = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]) / ll;
    double k = AMBIENT + (1 - AMBIENT) * (nl > 0 ? nl : 0);
    for (int i = 0; i < 3; i++)
        out[i] = (int)lround(fmin(1.0, albedo[i] * k) * 255.0);
}

static int px_diff(const unsigned char *img, int x, int y, const int want[3])
{
    const unsigned char *p = img + (y * W + x) * 3;
    int m = 0;
    for (int i = 0; i < 3; i++)
        m = abs(p[i] - want[i]) > m ? abs(p[i] - want[i]) : m;
    return m;
}

static void test_sphere_and_background(void)
{
    fixture f;
    build(&f);
    limen_frame_stats st = { 0 };
    unsigned char *img = render(f.s, (limen_renderer_desc){ 0 }, &st);
    /* the pixel nearest the sphere's centre: ray-sphere hit, true normal, formula */
    int cx = W / 2, cy = H / 2;
    double o[3], d[3];
    pixel_ray(f.s, cx, cy, o, d);
    double oc[3] = { o[0] - BALL_C[0], o[1] - BALL_C[1], o[2] - BALL_C[2] };
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - BALL_R * BALL_R;
    double t = (-b - sqrt(b * b - a * c)) / a;
    double p[3], n[3];
    for (int i = 0; i < 3; i++) {
        p[i] = o[i] + t * d[i];
        n[i] = (p[i] - BALL_C[i]) / BALL_R;
    }
    int want[3];
    shade(p, n, (float[3]){ 1, 0.5f, 0 }, want);
    CHECK_MSG(px_diff(img, cx, cy, want) <= 1, "sphere centre (%d %d %d), predicted (%d %d %d)",
              img[(cy * W + cx) * 3], img[(cy * W + cx) * 3 + 1], img[(cy * W + cx) * 3 + 2],
              want[0], want[1], want[2]);
    /* top-left corner sees nothing: the background */
    int bg[3] = { (int)lround(0.1 * 255), (int)lround(0.2 * 255), (int)lround(0.3 * 255) };
    CHECK(px_diff(img, 0, 0, bg) <= 1);
    CHECK(px_diff(img, W - 1, 0, bg) <= 1);
    /* statistics: one view, every pixel counted, at least the sphere's pixels shaded */
    CHECK(st.views == 1);
    CHECK(st.pixels == (uint64_t)W * H);
    CHECK(st.samples > 0 && st.samples < st.pixels * 2);
    CHECK(st.ms > 0);
    free(img);
    limen_scene_destroy(f.s);
}

static void test_floor_checker(void)
{
    fixture f;
    build(&f);
    unsigned char *img = render(f.s, (limen_renderer_desc){ 0 }, NULL);
    /* every bottom-row pixel hits the floor: predict its cell and shading */
    int checked = 0, bad = 0;
    for (int x = 0; x < W; x += 7) {
        int y = H - 1;
        double o[3], d[3];
        pixel_ray(f.s, x, y, o, d);
        double t = -o[1] / d[1];
        double p[3] = { o[0] + t * d[0], 0, o[2] + t * d[2] };
        if (t <= 0 || fabs(p[0]) > 3 || fabs(p[2]) > 3)
            continue;
        /* floor's local x is world x, local y is world -z */
        double u = p[0], v = -p[2];
        if (fabs(u - round(u)) < 0.03 || fabs(v - round(v)) < 0.03)
            continue;   /* too near a cell edge to call */
        int k = (int)(floor(u) + floor(v));
        const float *alb = (k & 1) ? (float[3]){ 0.2f, 0.2f, 0.2f } : (float[3]){ 0.8f, 0.8f, 0.8f };
        int want[3];
        shade(p, (double[3]){ 0, 1, 0 }, alb, want);
        checked++;
        bad += px_diff(img, x, y, want) > 1;
    }
    CHECK(checked > 5);
    CHECK_MSG(bad == 0, "%d of %d floor pixels off the formula", bad, checked);
    free(img);
    limen_scene_destroy(f.s);
}

/* share of pixels whose largest channel differs by more than 8 */
static double differ(const unsigned char *a, const unsigned char *b)
{
    int n = 0;
    for (int i = 0; i < W * H; i++) {
        int m = 0;
        for (int c = 0; c < 3; c++)
            m = abs(a[i * 3 + c] - b[i * 3 + c]) > m ? abs(a[i * 3 + c] - b[i * 3 + c]) : m;
        n += m > 8;
    }
    return (double)n / (W * H);
}

static void test_backends_agree(void)
{
    fixture f;
    build(&f);
    unsigned char *a = render(f.s, (limen_renderer_desc){ .backend = LIMEN_BACKEND_OSMESA }, NULL);
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(&(limen_renderer_desc){ .backend = LIMEN_BACKEND_EGL,
                                                                    .width = W, .height = H },
                                            &r);
    CHECK_MSG(st == LIMEN_OK, "EGL renderer: %s", r ? limen_renderer_error(r) : "");
    limen_renderer_destroy(r);
    unsigned char *b = render(f.s, (limen_renderer_desc){ .backend = LIMEN_BACKEND_EGL }, NULL);
    double share = differ(a, b);
    CHECK_MSG(share == 0.0, "osmesa and egl differ on %.4f of the pixels", share);
    free(a);
    free(b);
    limen_scene_destroy(f.s);
}

static void test_depth_conventions(void)
{
    fixture f;
    build(&f);
    unsigned char *no = render(f.s, (limen_renderer_desc){ .depth_range = LIMEN_DEPTH_NO }, NULL);
    unsigned char *zo = render(f.s, (limen_renderer_desc){ .depth_range = LIMEN_DEPTH_ZO }, NULL);
    unsigned char *rz =
        render(f.s, (limen_renderer_desc){ .depth_range = LIMEN_DEPTH_ZO_REVERSED }, NULL);
    CHECK_MSG(differ(no, zo) < 0.001, "no vs zo: %.4f", differ(no, zo));
    CHECK_MSG(differ(no, rz) < 0.001, "no vs zo-reversed: %.4f", differ(no, rz));
    free(no);
    free(zo);
    free(rz);
    limen_scene_destroy(f.s);
}

static void test_msaa(void)
{
    fixture f;
    build(&f);
    limen_frame_stats st;
    unsigned char *plain = render(f.s, (limen_renderer_desc){ 0 }, NULL);
    unsigned char *ms = render(f.s, (limen_renderer_desc){ .msaa = 4 }, &st);
    /* only edges may change, and some must (the sphere's silhouette is antialiased) */
    double share = differ(plain, ms);
    int changed = 0;
    for (int i = 0; i < W * H * 3; i++)
        changed += plain[i] != ms[i];
    CHECK_MSG(share < 0.05, "msaa changed %.4f of the pixels", share);
    CHECK(changed > 0);
    CHECK(st.samples >= (uint64_t)W * H);   /* samples count per sample: about 4 per pixel */
    free(plain);
    free(ms);
    limen_scene_destroy(f.s);
}

static void test_moving_node_changes_frame(void)
{
    fixture f;
    build(&f);
    unsigned char *a = render(f.s, (limen_renderer_desc){ 0 }, NULL);
    CHECK_OK(limen_node_set_position(f.s, f.ball, (float[3]){ -1, 1, 0 }));
    unsigned char *b = render(f.s, (limen_renderer_desc){ 0 }, NULL);
    CHECK(differ(a, b) > 0.01);
    CHECK_OK(limen_node_set_visible(f.s, f.ball, 0));
    unsigned char *c = render(f.s, (limen_renderer_desc){ 0 }, NULL);
    int cx = W / 2, cy = H / 2;
    CHECK(memcmp(a + (cy * W + cx) * 3, c + (cy * W + cx) * 3, 3) != 0);
    free(a);
    free(b);
    free(c);
    limen_scene_destroy(f.s);
}

static void test_errors(void)
{
    limen_renderer *r = NULL;
    CHECK(limen_renderer_create(&(limen_renderer_desc){ .width = -5 }, &r) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_renderer_error(r), "size") != NULL);
    limen_renderer_destroy(r);
    CHECK(limen_renderer_create(&(limen_renderer_desc){ .backend = 7 }, &r) == LIMEN_ERR_ARG);
    limen_renderer_destroy(r);
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = 8, .height = 8 }, &r));
    unsigned char px[8 * 8 * 3];
    CHECK(limen_renderer_read_rgb(r, px) != LIMEN_OK);   /* nothing rendered yet */
    limen_scene *s;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK(limen_render_frame(r, s, NULL, NULL) != LIMEN_OK);   /* no camera */
    CHECK(strstr(limen_renderer_error(r), "camera") != NULL);
    CHECK(limen_render_frame(r, NULL, NULL, NULL) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
    limen_renderer_destroy(r);
    limen_renderer_destroy(NULL);
}

/* A mesh or a texture that cannot be uploaded (memory out) fails the frame with a message
 * that says so, instead of a frame that silently lacks it; once memory is back, the same
 * renderer draws it. */
static void test_upload_failure(void)
{
    static const char *what[2] = { "mesh", "texture" };
    for (int k = 0; k < 2; k++) {
        limen_scene *s = NULL;
        limen_renderer *r = NULL;
        limen_node cam, thing;
        CHECK_OK(limen_scene_create(NULL, &s));
        CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
        if (!s || !r) {
            limen_scene_destroy(s);
            limen_renderer_destroy(r);
            return;
        }
        CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "eye", &cam));
        CHECK_OK(limen_scene_set_camera(s, cam));
        CHECK_OK(limen_node_set_position(s, cam, (float[3]){ 0, 0.5f, 3 }));
        CHECK_OK(limen_node_create(s, k ? LIMEN_NODE_QUAD : LIMEN_NODE_MESH, "thing", &thing));
        if (k)
            CHECK_OK(limen_node_set_texture(s, thing, "scenes/data/tiles.png"));
        else
            CHECK_OK(limen_mesh_load(s, thing, "scenes/data/bunny.obj"));
        CHECK_OK(limen_node_set_scale(s, thing, (float[3]){ 0.1f, 0.1f, 0.1f }));
        limen__renderer_set_faults(r, 1);
        CHECK(limen_render_frame(r, s, NULL, NULL) == LIMEN_ERR_NOMEM);
        const char *msg = limen_renderer_error(r);
        CHECK_MSG(strstr(msg, "out of memory uploading") && strstr(msg, what[k]), "%s: %s",
                  what[k], msg);
        limen__renderer_set_faults(r, 0);
        CHECK_OK(limen_render_frame(r, s, NULL, NULL));
        limen_renderer_destroy(r);
        limen_scene_destroy(s);
    }
}

/* A grid of G x G squares (2 G^2 triangles) over [-0.5, 0.5]^2 in z = 0. */
#define G 16
static limen_status grid_mesh(limen_scene *s, limen_node n)
{
    static float pos[(G + 1) * (G + 1) * 3];
    static uint32_t idx[G * G * 6];
    for (int y = 0; y <= G; y++)
        for (int x = 0; x <= G; x++) {
            float *p = &pos[(y * (G + 1) + x) * 3];
            p[0] = (float)x / G - 0.5f, p[1] = (float)y / G - 0.5f, p[2] = 0;
        }
    int k = 0;
    for (int y = 0; y < G; y++)
        for (int x = 0; x < G; x++) {
            uint32_t a = (uint32_t)(y * (G + 1) + x), b = a + 1, c = a + G + 1, d = c + 1;
            uint32_t t[6] = { a, b, d, a, d, c };
            for (int j = 0; j < 6; j++)
                idx[k++] = t[j];
        }
    return limen_mesh_set_triangles(s, n, &(limen_mesh_data){ .positions = pos,
                                                              .vertex_count = (G + 1) * (G + 1),
                                                              .indices = idx,
                                                              .triangle_count = G * G * 2 });
}

/* The frame budget's triangles: eight grids of 512 triangles before a mirror that shows
 * them all again. Room for both views draws both; room for one and a half drops the
 * mirror's view (truncated, LIMEN_BUDGET_TRIANGLES); room for half the camera's own view
 * keeps that view (always drawn) but draws only half its meshes; a negative budget is
 * refused. */
static void test_triangle_budget(void)
{
    enum { N = 8, T = G * G * 2 };
    limen_scene *s = NULL;
    limen_renderer *r = NULL;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    if (!s || !r) {
        limen_scene_destroy(s);
        limen_renderer_destroy(r);
        return;
    }
    limen_node cam, light, mirror, m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "eye", &cam));
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0, 0, 4 }, (float[3]){ 0, 0, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "lamp", &light));
    CHECK_OK(limen_node_set_position(s, light, (float[3]){ 0, 2, 4 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, "mirror", &mirror));
    CHECK_OK(limen_node_set_position(s, mirror, (float[3]){ 0, 0, -2 }));
    CHECK_OK(limen_node_set_dims(s, mirror, (float[3]){ 8, 8, 0 }));
    for (int i = 0; i < N; i++) {
        CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, NULL, &m));
        CHECK_OK(grid_mesh(s, m));
        CHECK_OK(limen_node_set_position(s, m, (float[3]){ (float)(i % 4) - 1.5f,
                                                          i < 4 ? 0.6f : -0.6f, 0 }));
        CHECK_OK(limen_node_set_scale(s, m, (float[3]){ 0.5f, 0.5f, 0.5f }));
    }
    static const int64_t budgets[3] = { 4 * N * T, 3 * N * T / 2, N * T / 2 };
    for (int k = 0; k < 3; k++) {
        limen_render_opts o = { .limits = { .lod_pixels = LIMEN_LOD_FULL } };
        o.limits.budget.triangles = budgets[k];
        limen_frame_stats st = { 0 };
        CHECK_OK(limen_render_frame(r, s, &o, &st));
        limen_plan_work w;
        limen_plan_get_work(limen_renderer_plan(r), &w);
        /* the mirror's quad is the frame's one other drawing: 2 triangles a view at most */
        uint64_t mesh_tris = st.triangles - (st.triangles % T);
        if (k == 0) {
            CHECK(st.views == 2 && st.truncated == 0 && w.budgets_hit == 0);
            CHECK_MSG(w.triangles == 2 * N * T, "plan counted %lld", (long long)w.triangles);
            CHECK_MSG(mesh_tris == 2 * N * T, "drew %llu", (unsigned long long)st.triangles);
        } else if (k == 1) {
            CHECK_MSG(st.views == 1 && st.truncated == 1, "views %d truncated %d", st.views,
                      st.truncated);
            CHECK(w.budgets_hit == LIMEN_BUDGET_TRIANGLES);
            CHECK(w.triangles == N * T);
            CHECK_MSG(mesh_tris == N * T, "drew %llu", (unsigned long long)st.triangles);
        } else {
            CHECK_MSG(st.views == 1 && st.truncated == 2, "views %d truncated %d", st.views,
                      st.truncated);
            CHECK(w.budgets_hit == LIMEN_BUDGET_TRIANGLES);
            CHECK_MSG(mesh_tris == N * T / 2, "drew %llu", (unsigned long long)st.triangles);
        }
    }
    limen_render_opts bad = { 0 };
    bad.limits.budget.triangles = -1;
    CHECK(limen_render_frame(r, s, &bad, NULL) == LIMEN_ERR_ARG);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* A flat mesh drawn indexed (gl/assets.c) takes each triangle's face normal from its last
 * corner: a pyramid whose four sides all end at the apex (one vertex) shows each side with
 * its own normal, as the formula has it, not the first side's at all four. */
static void test_flat_shared_corners(void)
{
    static const float pos[5 * 3] = { -0.8f, 0, 0.8f, 0.8f, 0, 0.8f, 0.8f, 0, -0.8f,
                                      -0.8f, 0, -0.8f, 0, 1, 0 };
    static const uint32_t idx[4 * 3] = { 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4 };
    const float albedo[3] = { 0.9f, 0.8f, 0.7f };
    limen_scene *s = NULL;
    limen_node cam, light, m;
    CHECK_OK(limen_scene_create(NULL, &s));
    if (!s)
        return;
    CHECK_OK(limen_scene_set_ambient(s, AMBIENT));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 1.6f, 2.2f, 3.2f }, (float[3]){ 0, 0.4f, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "light", &light));
    CHECK_OK(limen_node_set_position(s, light, LIGHT));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "pyramid", &m));
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){ .positions = pos,
                                                                .vertex_count = 5,
                                                                .indices = idx,
                                                                .triangle_count = 4 }));
    CHECK_OK(limen_node_set_color(s, m, albedo));
    unsigned char *img = render(s, (limen_renderer_desc){ 0 }, NULL);
    int checked[4] = { 0 }, bad = 0;
    for (int y = 0; y < H; y += 2)
        for (int x = 0; x < W; x += 2) {
            double o[3], d[3], best = INFINITY, n[3] = { 0 };
            int face = -1;
            pixel_ray(s, x, y, o, d);
            for (int f = 0; f < 4; f++) {
                /* tests/ray.h; pixels near an edge are not called */
                const float *a = &pos[idx[f * 3] * 3], *b = &pos[idx[f * 3 + 1] * 3],
                            *c = &pos[idx[f * 3 + 2] * 3];
                double t, u, v, e1[3], e2[3];
                if (!ray_triangle(a, b, c, o, d, &t, &u, &v) || t >= best)
                    continue;
                for (int i = 0; i < 3; i++) {
                    e1[i] = (double)b[i] - a[i];
                    e2[i] = (double)c[i] - a[i];
                }
                best = t;
                face = u < 0.05 || v < 0.05 || u + v > 0.95 ? -1 : f;
                double cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0] };
                double len = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
                for (int i = 0; i < 3; i++)
                    n[i] = cr[i] / len;
            }
            if (face < 0)
                continue;
            double p[3] = { o[0] + best * d[0], o[1] + best * d[1], o[2] + best * d[2] };
            int want[3];
            shade(p, n, albedo, want);
            checked[face]++;
            if (px_diff(img, x, y, want) > 2 && bad++ < 3)
                CHECK_MSG(0, "face %d at (%d, %d): (%d %d %d), predicted (%d %d %d)", face, x, y,
                          img[(y * W + x) * 3], img[(y * W + x) * 3 + 1],
                          img[(y * W + x) * 3 + 2], want[0], want[1], want[2]);
        }
    /* the camera sees two sides, lit differently */
    CHECK_MSG(checked[0] > 50 && checked[1] > 50, "pixels called: %d %d", checked[0], checked[1]);
    CHECK(bad == 0);
    free(img);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "sphere_and_background", test_sphere_and_background },
    { "floor_checker", test_floor_checker },
    { "backends_agree", test_backends_agree },
    { "depth_conventions", test_depth_conventions },
    { "msaa", test_msaa },
    { "moving_node_changes_frame", test_moving_node_changes_frame },
    { "errors", test_errors },
    { "upload_failure", test_upload_failure },
    { "triangle_budget", test_triangle_budget },
    { "flat_shared_corners", test_flat_shared_corners },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
