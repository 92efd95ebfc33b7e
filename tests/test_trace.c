/* test_trace.c - the reference ray tracer against analytic answers: exact hits on the true
 * shapes, paths through portals and mirrors, the drift of a long corridor of reflections,
 * the shading of an image, bounce limits and errors. No OpenGL. */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cache_dir.h"
#include "charted.h"
#include "check.h"
#include "limen.h"
#include "load.h"

/* ------------------------------------------------------------------ helpers */

static limen_scene *new_scene(void)
{
    limen_scene *s = NULL;
    limen_scene_create(&(limen_scene_desc){ 0 }, &s);
    return s;
}

static limen_node add(limen_scene *s, limen_node_kind kind, const char *name, float x, float y,
                      float z)
{
    limen_node n = { 0 };
    limen_node_create(s, kind, name, &n);
    limen_node_set_position(s, n, (float[3]){ x, y, z });
    return n;
}

static void set_dims(limen_scene *s, limen_node n, float a, float b, float c)
{
    limen_node_set_dims(s, n, (float[3]){ a, b, c });
}

static limen_hit cast(limen_scene *s, float ox, float oy, float oz, float dx, float dy, float dz,
                      int max_bounces)
{
    limen_hit h;
    memset(&h, 0xAB, sizeof h);
    limen_limits lim = { 0 };   /* max_bounces < 0: the surfaces' own limits */
    if (max_bounces >= 0)
        lim = (limen_limits){ .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = max_bounces };
    CHECK_OK(limen_ray_cast(s, (float[3]){ ox, oy, oz }, (float[3]){ dx, dy, dz }, &lim, &h));
    return h;
}

#define CHECK_VEC(v, x, y, z, tol)                                                       \
    do {                                                                                 \
        CHECK_NEAR((v)[0], (x), (tol));                                                  \
        CHECK_NEAR((v)[1], (y), (tol));                                                  \
        CHECK_NEAR((v)[2], (z), (tol));                                                  \
    } while (0)

static unsigned char byte(double c)
{
    return (unsigned char)lround(fmin(1.0, fmax(0.0, c)) * 255.0);
}

/* ------------------------------------------------------------------ shapes */

static void test_sphere_analytic(void)
{
    limen_scene *s = new_scene();
    limen_node ball = add(s, LIMEN_NODE_SPHERE, "ball", 1, 2, 3);
    set_dims(s, ball, 2, 0, 0);
    limen_hit h = cast(s, 1, 2, 10, 0, 0, -3, -1);     /* any length of dir */
    CHECK(h.hit == 1);
    CHECK(h.node.id == ball.id);
    CHECK_VEC(h.point, 1, 2, 5, 1e-6);
    CHECK_VEC(h.normal, 0, 0, 1, 1e-6);
    CHECK_NEAR(h.distance, 5, 1e-6);
    CHECK(h.surface_count == 0);
    CHECK_VEC(h.seg_origin, 1, 2, 10, 0);
    CHECK_VEC(h.seg_dir, 0, 0, -1, 1e-7);

    /* an oblique ray: |o + t d - c| = r solved by hand */
    double o[3] = { -4, 0.5, 1 }, d[3] = { 1, 0.3, 0.4 }, c[3] = { 1, 2, 3 }, r = 2;
    double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; i++)
        d[i] /= dl;
    double oc[3] = { o[0] - c[0], o[1] - c[1], o[2] - c[2] };
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
    double t = -b - sqrt(b * b - cc);
    h = cast(s, (float)o[0], (float)o[1], (float)o[2], (float)d[0], (float)d[1], (float)d[2], -1);
    CHECK(h.hit == 1);
    CHECK_NEAR(h.distance, t, 1e-5);
    for (int i = 0; i < 3; i++) {
        double p = o[i] + t * d[i];
        CHECK_NEAR(h.point[i], p, 1e-5);
        CHECK_NEAR(h.normal[i], (p - c[i]) / r, 1e-5);
    }

    /* a ray that starts inside: the back faces are culled, as in the renderer */
    h = cast(s, 1, 2, 3, 1, 0, 0, -1);
    CHECK(h.hit == 0);
    CHECK(isinf(h.distance));
    limen_scene_destroy(s);
}

static void test_shapes_scaled(void)
{
    limen_scene *s = new_scene();
    /* an ellipsoid: unit sphere scaled (2, 1, 1); the normal comes from the normal matrix */
    limen_node egg = add(s, LIMEN_NODE_SPHERE, "egg", 0, 0, 0);
    set_dims(s, egg, 1, 0, 0);
    limen_node_set_scale(s, egg, (float[3]){ 2, 1, 1 });
    limen_hit h = cast(s, 5, 0, 0, -1, 0, 0, -1);
    CHECK_VEC(h.point, 2, 0, 0, 1e-6);
    CHECK_VEC(h.normal, 1, 0, 0, 1e-6);
    h = cast(s, 1, 5, 0, 0, -1, 0, -1);
    double y = sqrt(1 - 0.25);     /* x = 1 on x^2/4 + y^2 = 1 */
    CHECK_VEC(h.point, 1, y, 0, 1e-6);
    double n[3] = { 1 / 4.0, y, 0 }, len = sqrt(n[0] * n[0] + n[1] * n[1]);
    CHECK_VEC(h.normal, n[0] / len, n[1] / len, 0, 1e-6);
    limen_node_set_visible(s, egg, 0);

    /* cylinder: radius 0.5, height 2; a cap from above, the side from +x */
    limen_node cyl = add(s, LIMEN_NODE_CYLINDER, "cyl", 10, 0, 0);
    set_dims(s, cyl, 0.5f, 2, 0);
    h = cast(s, 10.1f, 5, 0.2f, 0, -1, 0, -1);
    CHECK(h.node.id == cyl.id);
    CHECK_VEC(h.point, 10.1, 2, 0.2, 1e-6);
    CHECK_VEC(h.normal, 0, 1, 0, 1e-6);
    h = cast(s, 13, 1, 0.3f, -1, 0, 0, -1);
    double x = sqrt(0.25 - 0.09);
    CHECK_VEC(h.point, 10 + x, 1, 0.3, 1e-6);
    CHECK_VEC(h.normal, x / 0.5, 0, 0.3 / 0.5, 1e-6);
    h = cast(s, 10, -3, 0, 0, 1, 0, -1);           /* the bottom cap, from below */
    CHECK_VEC(h.point, 10, 0, 0, 1e-6);
    CHECK_VEC(h.normal, 0, -1, 0, 1e-6);

    /* box turned 90 degrees about Y: dims (2, 4, 6) -> 6 wide along x */
    limen_node box = add(s, LIMEN_NODE_BOX, "box", 0, 0, 20);
    set_dims(s, box, 2, 4, 6);
    limen_node_set_rotation(s, box, (float[3]){ 0, (float)M_PI_2, 0 });
    h = cast(s, -10, 0.5f, 20.2f, 1, 0, 0, -1);
    CHECK(h.node.id == box.id);
    CHECK_VEC(h.point, -3, 0.5, 20.2, 1e-5);
    CHECK_VEC(h.normal, -1, 0, 0, 1e-6);

    /* a quad is hit from both sides, its normal turned to the ray */
    limen_node q = add(s, LIMEN_NODE_QUAD, "q", 0, 0, -20);
    set_dims(s, q, 2, 2, 0);
    h = cast(s, 0.5f, 0.5f, -30, 0, 0, 1, -1);
    CHECK(h.node.id == q.id);
    CHECK_VEC(h.normal, 0, 0, -1, 1e-7);
    h = cast(s, 3.5f, 0.5f, -30, 0, 0, 1, -1);      /* outside the rectangle */
    CHECK(h.hit == 0);

    /* lights, cameras, groups and hidden nodes are never hit */
    add(s, LIMEN_NODE_LIGHT, "l", 0, 0, 40);
    add(s, LIMEN_NODE_CAMERA, "c", 0, 0, 41);
    add(s, LIMEN_NODE_GROUP, "g", 0, 0, 42);
    h = cast(s, 0, 0, 50, 0, 0, -1, -1);
    CHECK(h.hit == 1 && h.node.id == box.id);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ portals and mirrors */

static void test_portal_pair(void)
{
    limen_scene *s = new_scene();
    limen_node a = add(s, LIMEN_NODE_PORTAL, "a", 0, 0, 0);     /* faces +z */
    limen_node b = add(s, LIMEN_NODE_PORTAL, "b", 10, 0, 0);
    set_dims(s, a, 2, 2, 0);
    set_dims(s, b, 2, 2, 0);
    limen_node_set_facing(s, b, (float[3]){ 1, 0, 0 }, NULL);
    CHECK_OK(limen_portal_link(s, a, b));
    limen_node target = add(s, LIMEN_NODE_SPHERE, "target", 15, 0, 0);
    set_dims(s, target, 1, 0, 0);

    limen_hit h = cast(s, 0, 0, 5, 0, 0, -1, -1);
    CHECK(h.hit == 1 && h.node.id == target.id);
    CHECK(h.surface_count == 1 && h.surfaces[0].id == a.id);
    CHECK_VEC(h.point, 14, 0, 0, 1e-5);
    CHECK_VEC(h.seg_origin, 10, 0, 0, 1e-5);
    CHECK_VEC(h.seg_dir, 1, 0, 0, 1e-6);
    CHECK_NEAR(h.distance, 9, 1e-5);

    /* an oblique ray: origin and direction mapped by the surface matrix */
    float x[16];
    CHECK_OK(limen_surface_matrix(s, a, x));
    double o[3] = { 0.3, 0.2, 5 }, d[3] = { 0.05, -0.02, -1 };
    double p[3] = { o[0] + 5 * d[0], o[1] + 5 * d[1], 0 }, po[3], pd[3];
    for (int i = 0; i < 3; i++) {
        po[i] = x[i] * p[0] + x[4 + i] * p[1] + x[8 + i] * p[2] + x[12 + i];
        pd[i] = x[i] * d[0] + x[4 + i] * d[1] + x[8 + i] * d[2];
    }
    double pl = sqrt(pd[0] * pd[0] + pd[1] * pd[1] + pd[2] * pd[2]);
    h = cast(s, 0.3f, 0.2f, 5, 0.05f, -0.02f, -1, -1);
    CHECK(h.surface_count == 1 && h.surfaces[0].id == a.id);
    CHECK_VEC(h.seg_origin, po[0], po[1], po[2], 1e-5);
    CHECK_VEC(h.seg_dir, pd[0] / pl, pd[1] / pl, pd[2] / pl, 1e-6);

    /* from behind, portal a is air: the ray goes on to what lies beyond */
    limen_node wall = add(s, LIMEN_NODE_QUAD, "wall", 0, 0, 3);
    set_dims(s, wall, 4, 4, 0);
    h = cast(s, 0, 0, -5, 0, 0, 1, -1);
    CHECK(h.hit == 1 && h.node.id == wall.id);
    CHECK(h.surface_count == 0);
    CHECK_NEAR(h.distance, 8, 1e-5);

    limen_node_set_visible(s, wall, 0);
    /* a larger exit scales the path: out of b (2x) the segment starts at X p */
    set_dims(s, b, 4, 4, 0);
    CHECK_OK(limen_surface_matrix(s, a, x));
    for (int i = 0; i < 3; i++)
        po[i] = x[i] * p[0] + x[4 + i] * p[1] + x[8 + i] * p[2] + x[12 + i];
    h = cast(s, 0.3f, 0.2f, 5, 0.05f, -0.02f, -1, -1);
    CHECK_VEC(h.seg_origin, po[0], po[1], po[2], 1e-5);
    CHECK_NEAR(po[1], 2 * p[1], 1e-5);

    /* unpaired, or paired with a hidden end: the fill colour, from the front only */
    limen_surface_set_fill(s, a, (float[3]){ 0.1f, 0.2f, 0.3f });
    limen_node_set_visible(s, b, 0);
    h = cast(s, 0, 0, 2, 0, 0, -1, -1);
    CHECK(h.hit == 1 && h.node.id == a.id && h.surface_count == 0);
    CHECK_VEC(h.color, 0.1, 0.2, 0.3, 1e-6);
    limen_scene_destroy(s);
}

static void test_mirror_front_back(void)
{
    limen_scene *s = new_scene();
    limen_scene_set_background(s, (float[3]){ 0.2f, 0.4f, 0.8f });
    limen_scene_set_ambient(s, 1.0f);      /* colour = albedo */
    limen_node m = add(s, LIMEN_NODE_MIRROR, "m", 0, 0, 0);
    set_dims(s, m, 2, 2, 0);
    limen_surface_set_back(s, m, (float[3]){ 0.3f, 0.5f, 0.7f });
    limen_surface_set_tint(s, m, (float[3]){ 0.5f, 0.5f, 0.25f });

    limen_hit h = cast(s, 0.2f, 0.1f, -5, 0, 0, 1, -1);  /* from behind: matte back */
    CHECK(h.hit == 1 && h.node.id == m.id && h.surface_count == 0);
    CHECK_VEC(h.color, 0.3, 0.5, 0.7, 1e-6);
    CHECK_VEC(h.normal, 0, 0, -1, 1e-7);

    h = cast(s, 0, 0, 5, 0.1f, 0, -1, -1);               /* from the front: reflected */
    CHECK(h.hit == 0 && h.surface_count == 1 && h.surfaces[0].id == m.id);
    double l = sqrt(1.01);
    CHECK_VEC(h.seg_dir, 0.1 / l, 0, 1 / l, 1e-6);
    CHECK_VEC(h.seg_origin, 0.5, 0, 0, 1e-6);
    CHECK_VEC(h.color, 0.1, 0.2, 0.2, 1e-6);             /* background * tint */

    /* the mirror never sees itself, and sees only what is in front of it */
    limen_node ball = add(s, LIMEN_NODE_SPHERE, "ball", 0, 0, 3);
    set_dims(s, ball, 0.5f, 0, 0);
    limen_node behind = add(s, LIMEN_NODE_SPHERE, "behind", 0, 0, -3);
    set_dims(s, behind, 0.5f, 0, 0);
    h = cast(s, 0.9f, 0, 3, -0.15f, 0, -1, -1);
    CHECK(h.surface_count == 1 && h.hit == 1 && h.node.id == ball.id);
    limen_scene_destroy(s);
}

/* Two facing mirrors: after n reflections the path is the straight line of the unfolded
 * corridor. */
static void drift_case(int bounces)
{
    limen_scene *s = new_scene();
    limen_node north = add(s, LIMEN_NODE_MIRROR, "north", 0, 0, -3);
    limen_node south = add(s, LIMEN_NODE_MIRROR, "south", 0, 0, 3);
    limen_node_set_facing(s, south, (float[3]){ 0, 0, -1 }, NULL);
    for (int i = 0; i < 2; i++) {
        limen_node m = i ? south : north;
        set_dims(s, m, 100, 100, 0);
        CHECK_OK(limen_surface_set_max_depth(s, m, bounces));
    }
    const double o[3] = { 0.1, -0.2, 0.5 }, d[3] = { 0.03, 0.02, 1 };
    limen_hit h = cast(s, (float)o[0], (float)o[1], (float)o[2], (float)d[0], (float)d[1],
                       (float)d[2], -1);
    /* the ray reaches z = 3 after 2.5, then every 6 in z; the (bounces + 1)-th surface
     * stops it (at the limit, its fill) */
    double zu = 2.5 + 6.0 * bounces, zl = zu - 6.0;
    double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double tol = 1e-4 * 6.0;
    limen_node last = bounces % 2 ? north : south;
    CHECK(h.hit == 1 && h.node.id == last.id);
    /* an override takes the ray one surface further than the surfaces' own limit */
    limen_hit h2;
    CHECK_OK(limen_ray_cast(s, (float[3]){ (float)o[0], (float)o[1], (float)o[2] },
                            (float[3]){ (float)d[0], (float)d[1], (float)d[2] },
                            &(limen_limits){ .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                             .depth = bounces + 1 },
                            &h2));
    CHECK(h2.surface_count == bounces + 1 && h2.node.id == (bounces % 2 ? south : north).id);
    CHECK(h.surface_count == bounces);
    CHECK_VEC(h.point, o[0] + d[0] * zu, o[1] + d[1] * zu, bounces % 2 ? -3 : 3, tol);
    CHECK_NEAR(h.distance, zu * dl, tol);
    CHECK_VEC(h.seg_origin, o[0] + d[0] * zl, o[1] + d[1] * zl, bounces % 2 ? 3 : -3, tol);
    double sz = bounces % 2 ? -1 : 1;
    CHECK_VEC(h.seg_dir, d[0] / dl, d[1] / dl, sz * d[2] / dl, 1e-6);
    int n = bounces < LIMEN_HIT_MAX_SURFACES ? bounces : LIMEN_HIT_MAX_SURFACES;
    for (int i = 0; i < n; i++)
        CHECK_MSG(h.surfaces[i].id == (i % 2 ? north.id : south.id), "chain[%d]", i);
    limen_scene_destroy(s);
}

static void test_drift_corridor(void)
{
    drift_case(64);
    drift_case(200);    /* the chain keeps its first 64 entries and counts on */
    drift_case(7);
}

/* ------------------------------------------------------------------ images */

/* Camera at (0, 0, 5) looking down -z, a red sphere at the origin, one light. */
static limen_scene *sphere_scene(limen_node *mirror)
{
    limen_scene *s = new_scene();
    limen_scene_set_background(s, (float[3]){ 0.1f, 0.2f, 0.3f });
    limen_scene_set_ambient(s, 0.2f);
    limen_node cam = add(s, LIMEN_NODE_CAMERA, "cam", 0, 0, 5);
    limen_scene_set_camera(s, cam);
    limen_node ball = add(s, LIMEN_NODE_SPHERE, "ball", 0, 0, 0);
    set_dims(s, ball, 1, 0, 0);
    limen_node_set_color(s, ball, (float[3]){ 0.8f, 0.5f, 0.2f });
    add(s, LIMEN_NODE_LIGHT, "light", 2, 3, 4);
    /* a mirror off to the side, turned towards the camera and the ball */
    *mirror = add(s, LIMEN_NODE_MIRROR, "mirror", -2.5f, 0, -1);
    set_dims(s, *mirror, 2, 3, 0);
    limen_node_set_facing(s, *mirror, (float[3]){ 1, 0, 0.6f }, NULL);
    return s;
}

static void test_image_shading(void)
{
    limen_node mirror;
    limen_scene *s = sphere_scene(&mirror);
    enum { W = 65, H = 49 };
    unsigned char *a = malloc(W * H * 3), *b = malloc(W * H * 3), *c = malloc(W * H * 3);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, a));
    /* centre pixel: the point (0, 0, 1), normal +z */
    double l[3] = { 2, 3, 3 }, ll = sqrt(22.0);
    double k = 0.2 + 0.8 * fmax(0.0, l[2] / ll);
    const unsigned char *px = a + ((H / 2) * W + W / 2) * 3;
    CHECK(px[0] == byte(0.8 * k) && px[1] == byte(0.5 * k) && px[2] == byte(0.2 * k));
    /* a corner: the background */
    px = a + ((H - 1) * W + W - 1) * 3;
    CHECK(px[0] == byte(0.1) && px[1] == byte(0.2) && px[2] == byte(0.3));

    /* threads do not change a pixel */
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H, .threads = 3 },
                               b));
    CHECK(memcmp(a, b, W * H * 3) == 0);

    /* the mirror shows something: without it the picture differs */
    limen_node_set_visible(s, mirror, 0);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, c));
    int differ = 0;
    for (int i = 0; i < W * H * 3; i++)
        differ += a[i] != c[i];
    CHECK(differ > 50);
    free(a);
    free(b);
    free(c);
    limen_scene_destroy(s);
}

static void test_checker(void)
{
    limen_scene *s = new_scene();
    limen_scene_set_ambient(s, 1.0f);
    limen_node q = add(s, LIMEN_NODE_QUAD, "floor", 0, 0, 0);
    set_dims(s, q, 8, 8, 0);
    limen_node_set_checker(s, q, (float[3]){ 1, 1, 1 }, (float[3]){ 0, 0, 0 }, 1.0f);
    /* local (x, y) = world (x, y): k = floor(x) + floor(y) */
    limen_hit h = cast(s, 0.5f, 0.5f, 3, 0, 0, -1, -1);    /* k = 0: colour a */
    CHECK_VEC(h.color, 1, 1, 1, 0);
    h = cast(s, -0.5f, 0.5f, 3, 0, 0, -1, -1);             /* k = -1: odd, colour b */
    CHECK_VEC(h.color, 0, 0, 0, 0);
    h = cast(s, -1.5f, 2.5f, 3, 0, 0, -1, -1);             /* k = 0 */
    CHECK_VEC(h.color, 1, 1, 1, 0);
    limen_scene_destroy(s);
}

/* Traces s at w x h under a depth rule. */
static void trace_limited(limen_scene *s, limen_depth_rule rule, int depth, int w, int h,
                          unsigned char *img)
{
    limen_trace_desc d = { .width = w, .height = h,
                           .limits = { .depth_rule = rule, .depth = depth } };
    CHECK_OK(limen_trace_image(s, &d, img));
}

static void test_bounce_limit(void)
{
    limen_node mirror;
    limen_scene *s = sphere_scene(&mirror);
    /* face the camera squarely, in front of everything */
    limen_node_set_position(s, mirror, (float[3]){ 0, 0, 2 });
    limen_node_set_facing(s, mirror, (float[3]){ 0, 0, 1 }, NULL);
    limen_surface_set_fill(s, mirror, (float[3]){ 0.2f, 0.4f, 0.8f });
    limen_surface_set_tint(s, mirror, (float[3]){ 0.5f, 0.5f, 0.5f });
    enum { W = 33, H = 25 };
    unsigned char img[W * H * 3];
    const unsigned char *px = img + ((H / 2) * W + W / 2) * 3;
    trace_limited(s, LIMEN_DEPTH_RULE_CAP, 0, W, H, img);
    CHECK(px[0] == 51 && px[1] == 102 && px[2] == 204);
    /* one level allowed: the mirror shows the camera's side of the world (background) */
    trace_limited(s, LIMEN_DEPTH_RULE_CAP, 1, W, H, img);
    CHECK(px[0] == byte(0.05) && px[1] == byte(0.1) && px[2] == byte(0.15));
    /* the surface's own limit does the same */
    limen_surface_set_max_depth(s, mirror, 0);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, img));
    CHECK(px[0] == 51 && px[1] == 102 && px[2] == 204);
    /* a cap does not raise it; an override does */
    trace_limited(s, LIMEN_DEPTH_RULE_CAP, 1, W, H, img);
    CHECK(px[0] == 51 && px[1] == 102 && px[2] == 204);
    trace_limited(s, LIMEN_DEPTH_RULE_OVERRIDE, 1, W, H, img);
    CHECK(px[0] == byte(0.05) && px[1] == byte(0.1) && px[2] == byte(0.15));
    limen_scene_destroy(s);

    /* nested: the second mirror's fill, times the first mirror's tint */
    s = new_scene();
    limen_node m1 = add(s, LIMEN_NODE_MIRROR, "m1", 0, 0, -3);
    limen_node m2 = add(s, LIMEN_NODE_MIRROR, "m2", 0, 0, 3);
    limen_node_set_facing(s, m2, (float[3]){ 0, 0, -1 }, NULL);
    set_dims(s, m1, 4, 4, 0);
    set_dims(s, m2, 4, 4, 0);
    limen_surface_set_tint(s, m1, (float[3]){ 0.5f, 0.25f, 1 });
    limen_surface_set_fill(s, m2, (float[3]){ 0.8f, 0.8f, 0.8f });
    limen_hit h = cast(s, 0, 0, 0, 0, 0, -1, 1);
    CHECK(h.hit == 1 && h.node.id == m2.id && h.surface_count == 1);
    CHECK_VEC(h.color, 0.4, 0.2, 0.8, 1e-6);
    h = cast(s, 0, 0, 0, 0, 0, -1, 0);
    CHECK(h.hit == 1 && h.node.id == m1.id && h.surface_count == 0);
    CHECK_VEC(h.color, 0, 0, 0, 0);                 /* default fill black */
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ errors */

static void test_errors(void)
{
    limen_scene *s = new_scene();
    limen_hit h;
    float o[3] = { 0, 0, 0 };
    CHECK(limen_ray_cast(s, o, (float[3]){ NAN, 0, 1 }, NULL, &h) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "direction") != NULL);
    CHECK(limen_ray_cast(s, o, (float[3]){ 0, 0, 0 }, NULL, &h) == LIMEN_ERR_ARG);
    CHECK(limen_ray_cast(s, (float[3]){ INFINITY, 0, 0 }, (float[3]){ 0, 0, 1 }, NULL, &h) ==
          LIMEN_ERR_ARG);
    CHECK(limen_ray_cast(s, o, (float[3]){ 0, 0, 1 }, NULL, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_ray_cast(NULL, o, (float[3]){ 0, 0, 1 }, NULL, &h) == LIMEN_ERR_ARG);

    unsigned char img[4 * 4 * 3];
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = 4, .height = 4 }, img) ==
          LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "camera") != NULL);
    limen_node cam = add(s, LIMEN_NODE_CAMERA, "cam", 0, 0, 5);
    limen_scene_set_camera(s, cam);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = -4, .height = 4 }, img) ==
          LIMEN_ERR_ARG);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = 4, .height = 4,
                                                    .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                                .depth = 300 } },
                            img) == LIMEN_ERR_ARG);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = 4, .height = 4, .threads = -1 },
                            img) == LIMEN_ERR_ARG);
    CHECK(limen_trace_image(s, NULL, NULL) == LIMEN_ERR_ARG);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = 4, .height = 4 }, img));
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ files */

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* Files in dir other than the good one: temporaries left behind. */
static int temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && strcmp(e->d_name, "good.png");
    if (d)
        closedir(d);
    return d ? n : -1;
}

/* A PNG is written whole or not at all: a full device, a missing folder and a write cut
 * short by a file size limit fail, and the good file already there stays as it was
 * (stb's writer ignored write errors: /dev/full "succeeded"). */
static void test_png_write_whole_or_not(void)
{
    enum { W = 256, H = 256 };
    unsigned char *img = malloc(W * H * 3), *back = NULL;
    for (int i = 0; i < W * H * 3; i++)
        img[i] = (unsigned char)((i * 7919u) >> 3);   /* noisy: does not compress */
    char dir[] = "/tmp/limen_png_XXXXXX", path[128];
    CHECK(mkdtemp(dir) != NULL);
    snprintf(path, sizeof path, "%s/good.png", dir);
    CHECK(limen_write_png(path, 8, 8, img) == LIMEN_OK);
    long good = file_size(path);
    CHECK(good > 0);

    CHECK(limen_write_png("/dev/full", W, H, img) == LIMEN_ERR_IO);
    CHECK(limen_write_png("/nonexistent-dir/x.png", W, H, img) == LIMEN_ERR_IO);

    /* a file size limit of 4 KB: the big image cannot be written */
    struct rlimit old, small = { 4096, 4096 };
    getrlimit(RLIMIT_FSIZE, &old);
    small.rlim_max = old.rlim_max;
    void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
    setrlimit(RLIMIT_FSIZE, &small);
    limen_status st = limen_write_png(path, W, H, img);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, was);
    CHECK(st == LIMEN_ERR_IO);
    CHECK_MSG(file_size(path) == good, "the good file was replaced (%ld bytes, was %ld)",
              file_size(path), good);
    int w = 0, h = 0;
    CHECK(limen_read_png(path, &w, &h, &back) == LIMEN_OK && w == 8 && h == 8);
    limen_free(back);
    CHECK(temporaries(dir) == 0);

    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK(system(cmd) == 0);
    free(img);
}

/* A PNG in memory, chunk by chunk (stb_image does not check CRCs: they are left 0). */
typedef struct pngbuf { unsigned char b[4096]; size_t n; } pngbuf;

static void png_u32(pngbuf *p, unsigned v)
{
    for (int i = 3; i >= 0; i--)
        p->b[p->n++] = (unsigned char)(v >> (8 * i));
}

static void png_chunk(pngbuf *p, const char *type, const unsigned char *data, unsigned len)
{
    png_u32(p, len);
    memcpy(p->b + p->n, type, 4);
    p->n += 4;
    if (len)
        memcpy(p->b + p->n, data, len);
    p->n += len;
    png_u32(p, 0);
}

static void png_start(pngbuf *p, unsigned w, unsigned h)
{
    static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    memcpy(p->b, sig, 8);
    p->n = 8;
    unsigned char ihdr[13] = { (unsigned char)(w >> 24), (unsigned char)(w >> 16),
                               (unsigned char)(w >> 8), (unsigned char)w,
                               (unsigned char)(h >> 24), (unsigned char)(h >> 16),
                               (unsigned char)(h >> 8), (unsigned char)h, 8, 2, 0, 0, 0 };
    png_chunk(p, "IHDR", ihdr, 13);
}

static limen_status read_bytes(const pngbuf *p, int *w, int *h, unsigned char **rgb)
{
    char path[] = "/tmp/limen-png-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0 && write(fd, p->b, p->n) == (ssize_t)p->n);
    close(fd);
    limen_status st = limen_read_png(path, w, h, rgb);
    remove(path);
    return st;
}

/* Reading: an image declaring more than LIMEN_IMAGE_MAX_PIXELS is refused from its header
 * (it took seconds and gigabytes to fail), and an empty IDAT chunk is read as nothing
 * (stb_image copied zero bytes to NULL for it: undefined behaviour). */
static void test_png_read_limits(void)
{
    pngbuf p;
    int w = -1, h = -1;
    unsigned char *rgb = NULL;
    png_start(&p, 16384, 16384);
    static const unsigned char junk[64] = { 0x78, 0x01 };
    png_chunk(&p, "IDAT", junk, sizeof junk);
    png_chunk(&p, "IEND", NULL, 0);
    CHECK(read_bytes(&p, &w, &h, &rgb) == LIMEN_ERR_ARG);
    CHECK(rgb == NULL);

    /* 1x1 red: an empty IDAT, then a stored zlib block with the scanline 0, 255, 0, 0 */
    png_start(&p, 1, 1);
    png_chunk(&p, "IDAT", NULL, 0);
    unsigned a = 1 + 255, b = 1 + a + a + a;    /* adler-32 of 0, 255, 0, 0 */
    const unsigned char z[] = { 0x78, 0x01, 0x01, 4, 0, 0xfb, 0xff, 0, 255, 0, 0,
                                (unsigned char)(b >> 8), (unsigned char)b,
                                (unsigned char)(a >> 8), (unsigned char)a };
    png_chunk(&p, "IDAT", z, sizeof z);
    png_chunk(&p, "IEND", NULL, 0);
    CHECK(read_bytes(&p, &w, &h, &rgb) == LIMEN_OK);
    CHECK(w == 1 && h == 1 && rgb && rgb[0] == 255 && rgb[1] == 0 && rgb[2] == 0);
    limen_free(rgb);
}

/* A lens from 0.01 to 1e6: the tracer built its rays by unprojecting through the float
 * projection, whose far point was off by half, and saw only background. */
static void test_wide_depth_range(void)
{
    limen_scene *s = new_scene();
    limen_node cam = add(s, LIMEN_NODE_CAMERA, "cam", 0, 0, 5);
    CHECK_OK(limen_camera_set_lens(s, cam, 1.0f, 0.01f, 1e6f));
    CHECK_OK(limen_scene_set_camera(s, cam));
    limen_node ball = add(s, LIMEN_NODE_SPHERE, "ball", 0, 0, 0);
    set_dims(s, ball, 1, 0, 0);
    CHECK_OK(limen_node_set_color(s, ball, (float[3]){ 1, 0, 0 }));
    CHECK_OK(limen_scene_set_ambient(s, 1));
    enum { TW = 31, TH = 21 };
    unsigned char rgb[TW * TH * 3];
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = TW, .height = TH }, rgb));
    const unsigned char *c = rgb + ((TH / 2) * TW + TW / 2) * 3;
    CHECK_MSG(c[0] == 255 && c[1] == 0 && c[2] == 0, "centre %d %d %d, expected the red ball",
              c[0], c[1], c[2]);
    /* the ball covers what its angular size says: tan(half fov) = 0.546 over 10 columns */
    int red = 0;
    for (int x = 0; x < TW; x++)
        red += rgb[((TH / 2) * TW + x) * 3] == 255;
    double half = atan(1.0 / sqrt(24.0));   /* tangent cone half-angle from 5 units */
    int expect = 2 * (int)floor(tan(half) / (tan(0.5) * TW / TH) * (TW / 2.0) + 0.5) + 1;
    CHECK_MSG(abs(red - expect) <= 2, "%d red pixels on the middle row, expected ~%d", red,
              expect);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ samples per pixel */

/* A white quad (ambient 1, no light) on black covering x >= X and y >= Y in front of a
 * camera at z = 2 with a 90-degree lens over an 8 x 8 image: pixel (column c, GL row g) spans
 * x in [c, c + 1) pixels, and a pixel edge at c + f is the world x (2 (c + f) / 8 - 1) * 2. */
static limen_scene *corner_scene(double fx, double fy)
{
    limen_scene *s = new_scene();
    limen_scene_set_ambient(s, 1.0f);
    limen_scene_set_background(s, (float[3]){ 0, 0, 0 });
    limen_node cam = add(s, LIMEN_NODE_CAMERA, "eye", 0, 0, 2);
    limen_scene_set_camera(s, cam);
    limen_camera_set_lens(s, cam, (float)(M_PI / 2), 0.05f, 100.0f);
    double x = (2.0 * (4 + fx) / 8 - 1) * 2, y = (2.0 * (4 + fy) / 8 - 1) * 2;
    limen_node q = add(s, LIMEN_NODE_QUAD, "quad", (float)(x + 10), (float)(y + 10), 0);
    set_dims(s, q, 20, 20, 0);
    return s;
}

/* What pixel (column 4, GL row 4) holds when the quad's corner lies at (4 + fx, 4 + fy) in
 * it, traced with n samples. */
static int corner_pixel(double fx, double fy, int n)
{
    limen_scene *s = corner_scene(fx, fy);
    unsigned char rgb[8 * 8 * 3];
    int v = -1;
    if (limen_trace_image(s, &(limen_trace_desc){ .width = 8, .height = 8, .samples = n }, rgb))
        CHECK_MSG(0, "trace: %s", limen_scene_error(s));
    else
        v = rgb[((8 - 1 - 4) * 8 + 4) * 3];    /* PNG row 3 is GL row 4 */
    limen_scene_destroy(s);
    return v;
}

/* limen_trace_desc.samples: the 4x MSAA positions (0.375, 0.125), (0.875, 0.375),
 * (0.125, 0.625), (0.625, 0.875), each pixel the mean of its samples. A corner at (0.3, 0.3)
 * of the pixel covers two of them (a 2 x 2 grid would cover one); at (0.3, 0.55) one (the
 * pattern upside down would cover two); a k x k grid covers the cell centres past the
 * corner; the centre alone sees all or nothing. Other counts are refused, and threads do
 * not change a pixel. */
static void test_samples(void)
{
    CHECK(corner_pixel(0.3, 0.3, 0) == 255);    /* the centre (0.5, 0.5) is covered */
    CHECK(corner_pixel(0.3, 0.3, 1) == 255);
    CHECK(corner_pixel(0.6, 0.3, 1) == 0);
    CHECK_MSG(corner_pixel(0.3, 0.3, 4) == 128, "got %d", corner_pixel(0.3, 0.3, 4));
    CHECK_MSG(corner_pixel(0.3, 0.55, 4) == 64, "got %d", corner_pixel(0.3, 0.55, 4));
    CHECK_MSG(corner_pixel(0.55, 0.3, 4) == 128, "got %d", corner_pixel(0.55, 0.3, 4));
    /* 4 x 4: centres 1/8, 3/8, 5/8, 7/8 -> 3 x 3 of 16 past (0.3, 0.3) */
    CHECK_MSG(corner_pixel(0.3, 0.3, 16) == 143, "got %d", corner_pixel(0.3, 0.3, 16));
    /* 3 x 3: centres 1/6, 1/2, 5/6 -> 2 x 2 of 9 */
    CHECK_MSG(corner_pixel(0.3, 0.3, 9) == 113, "got %d", corner_pixel(0.3, 0.3, 9));
    limen_scene *s = corner_scene(0.3, 0.3);
    unsigned char a[8 * 8 * 3], b[8 * 8 * 3];
    static const int bad[] = { -1, 2, 3, 8, 15, 257, 289 };
    for (int i = 0; i < 7; i++) {
        CHECK(limen_trace_image(s, &(limen_trace_desc){ .samples = bad[i] }, a) ==
              LIMEN_ERR_ARG);
        CHECK_MSG(strstr(limen_scene_error(s), "samples"), "%s", limen_scene_error(s));
    }
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = 8, .height = 8, .samples = 16,
                                                       .threads = 1 }, a));
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = 8, .height = 8, .samples = 16,
                                                       .threads = 3 }, b));
    CHECK(memcmp(a, b, sizeof a) == 0);
    limen_scene_destroy(s);
}

/* The gallery at --msaa 4 against the 4-sample truth (the same positions, each sample
 * shaded): every scene within 0.5% (pixels off by more than 8 of 255), and nearer it than
 * the centre-sampled truth. Three things had to hold for that: each sample's attributes
 * exact (gl/shader.c's EXACT: llvmpipe divides a sample's perspective numerators by the
 * pixel centre's 1/w), a view's scissor holding every pixel its surface meets, not only
 * those whose centre it covers (limen_plan_desc.multisample), and curved silhouettes within
 * a quarter of the one-sample tolerance (core/drawlist.c). */
static void test_msaa_truth(void)
{
    static const char *const scenes[] = {
        "plain", "mirror_room", "corridor", "kaleidoscope", "periscope", "water", "portals",
        "tunnel", "portal_mirror", "portal_sizes", "moving_portal", "flythrough",
        "hall_of_mirrors", "portal_rooms", "portal_statue", "level", "materials",
    };
    enum { W = 128, H = 96, N = sizeof scenes / sizeof scenes[0] };
    /* both methods: the texture method's targets are drawn with the frame's samples and
     * read sample by sample */
    static const limen_method methods[2] = { LIMEN_METHOD_STENCIL, LIMEN_METHOD_TEXTURE };
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H,
                                                                    .msaa = 4 }, &r);
    CHECK_MSG(st == LIMEN_OK, "renderer: %s", limen_renderer_error(r));
    unsigned char *img = malloc(W * H * 3), *t4 = malloc(W * H * 3), *t1 = malloc(W * H * 3);
    for (int i = 0; i < N && !st && img && t4 && t1; i++) {
        char path[64];
        snprintf(path, sizeof path, "scenes/%s.lua", scenes[i]);
        limen_script *sc = check_load_script(path);
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H,
                                                           .samples = 4 }, t4));
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, t1));
        for (int m = 0; m < 2; m++) {
            limen_render_opts o = { .method = methods[m] };
            CHECK_OK(limen_render_frame(r, s, &o, NULL));
            CHECK_OK(limen_renderer_read_rgb(r, img));
            limen_diff d4, d1;
            CHECK_OK(limen_image_diff(img, t4, W, H, 8, &d4, NULL));
            CHECK_OK(limen_image_diff(img, t1, W, H, 8, &d1, NULL));
            const char *how = m ? "texture" : "stencil";
            CHECK_MSG(d4.bad_share <= 0.005, "%s, %s method: %.2f%% off the 4-sample truth",
                      scenes[i], how, 100 * d4.bad_share);
            CHECK_MSG(d4.bad_share < d1.bad_share, "%s, %s method: %.2f%% off the 4-sample "
                      "truth, %.2f%% off the centre-sampled one", scenes[i], how,
                      100 * d4.bad_share, 100 * d1.bad_share);
        }
        limen_script_destroy(sc);
    }
    free(img);
    free(t4);
    free(t1);
    limen_renderer_destroy(r);
}

/* ------------------------------------------------------------------ levels of detail */

/* The texture's colours in test_lod_levels: five charts and the margin around each. */
static const unsigned char lod_colour[6][3] = {
    { 230, 60, 40 }, { 60, 200, 60 }, { 50, 90, 230 }, { 230, 200, 40 }, { 40, 200, 210 },
    { 255, 0, 255 },
};

/* Which of lod_colour a pixel shows, by its hue (light and dark checks and the blends
 * between them are one chart's colour scaled): 0-5, or -1 for the black background. */
static int lod_class(const unsigned char *p)
{
    int m = p[0] > p[1] ? p[0] : p[1];
    m = p[2] > m ? p[2] : m;
    if (m < 24)
        return -1;
    int best = 0;
    double bd = 1e9;
    for (int c = 0; c < 6; c++) {
        const unsigned char *q = lod_colour[c];
        int qm = q[0] > q[1] ? q[0] : q[1];
        qm = q[2] > qm ? q[2] : qm;
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += fabs((double)p[k] / m - (double)q[k] / qm);
        if (d < bd) {
            bd = d;
            best = c;
        }
    }
    return best;
}

/* How many pixels of img show a colour (lod_class) that ref shows nowhere within r of them
 * (a square of side 2r + 1 around the pixel: each class's Chebyshev distance from it, by
 * two passes over ref). blends: a pixel whose colour lies within the box of the colours ref
 * shows within r (each channel between their least and greatest) is matched too, as a
 * blend of texels from within r is. */
static int unmatched_within(const unsigned char *img, const unsigned char *ref, int w, int h,
                            int r, bool blends)
{
    enum { CLASSES = 7 };       /* lod_class + 1: the background, then lod_colour's */
    int *dist = malloc(sizeof(int) * CLASSES * (size_t)w * h);
    if (!dist)
        return w * h;
    const int far = w + h;
    for (int c = 0; c < CLASSES; c++) {
        int *d = dist + (size_t)c * w * h;
        for (int i = 0; i < w * h; i++)
            d[i] = lod_class(&ref[i * 3]) + 1 == c ? 0 : far;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                for (int dy = -1; dy <= 0; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int yy = y + dy, xx = x + dx;
                        if ((dy < 0 || dx < 0) && yy >= 0 && xx >= 0 && xx < w &&
                            d[yy * w + xx] + 1 < d[y * w + x])
                            d[y * w + x] = d[yy * w + xx] + 1;
                    }
        for (int y = h - 1; y >= 0; y--)
            for (int x = w - 1; x >= 0; x--)
                for (int dy = 0; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int yy = y + dy, xx = x + dx;
                        if ((dy > 0 || dx > 0) && yy < h && xx >= 0 && xx < w &&
                            d[yy * w + xx] + 1 < d[y * w + x])
                            d[y * w + x] = d[yy * w + xx] + 1;
                    }
    }
    int bad = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char *p = &img[(y * w + x) * 3];
            if (dist[(size_t)(lod_class(p) + 1) * w * h + (size_t)y * w + x] <= r)
                continue;
            bool inside = false;
            if (blends) {
                int lo[3] = { 255, 255, 255 }, hi[3] = { 0, 0, 0 };
                for (int yy = y - r; yy <= y + r; yy++)
                    for (int xx = x - r; xx <= x + r; xx++)
                        if (yy >= 0 && yy < h && xx >= 0 && xx < w)
                            for (int k = 0; k < 3; k++) {
                                int v = ref[(yy * w + xx) * 3 + k];
                                lo[k] = v < lo[k] ? v : lo[k];
                                hi[k] = v > hi[k] ? v : hi[k];
                            }
                inside = true;
                for (int k = 0; k < 3; k++)
                    inside = inside && p[k] >= lo[k] && p[k] <= hi[k];
            }
            bad += !inside;
        }
    free(dist);
    return bad;
}

/* A ball of tests/charted.h in charts of the texture (nv vertices, nt triangles), charts of
 * them, each chart c its own cell of cell x cell texels of the atlas, in colour[c] of
 * lod_colour; name in messages. */
typedef struct lod_asset {
    const char *name;
    int nv, nt, charts, cell;
    const float *pos, *nrm, *uv;
    const uint32_t *idx;
    const int *colour;
    bool notches;               /* the texels of a chart's cell that no triangle of it shows
                                 * (beyond a texel around them) in the margin's colour, as
                                 * an atlas packs other charts there; else the chart's own */
    bool file;                  /* loaded from an OBJ whose material has the atlas as its
                                 * texture (the mesh's own: its coarse levels baked), not
                                 * made from arrays with the atlas as the node's texture */
} lod_asset;

/* a as an OBJ (dir/ball.obj) whose material's texture is dir/atlas.png */
static bool lod_asset_obj(const lod_asset *a, const char *dir, char *obj, size_t size)
{
    char mtl[96];
    snprintf(obj, size, "%s/ball.obj", dir);
    snprintf(mtl, sizeof mtl, "%s/ball.mtl", dir);
    FILE *f = fopen(mtl, "w");
    if (!f)
        return false;
    fprintf(f, "newmtl atlas\nKd 1 1 1\nmap_Kd atlas.png\n");
    fclose(f);
    if (!(f = fopen(obj, "w")))
        return false;
    fprintf(f, "mtllib ball.mtl\nusemtl atlas\n");
    for (int v = 0; v < a->nv; v++)
        fprintf(f, "v %.9g %.9g %.9g\nvt %.9g %.9g\nvn %.9g %.9g %.9g\n", a->pos[v * 3],
                a->pos[v * 3 + 1], a->pos[v * 3 + 2], a->uv[v * 2], a->uv[v * 2 + 1],
                a->nrm[v * 3], a->nrm[v * 3 + 1], a->nrm[v * 3 + 2]);
    for (int t = 0; t < a->nt; t++) {
        fprintf(f, "f");
        for (int k = 0; k < 3; k++)
            fprintf(f, " %u/%u/%u", a->idx[t * 3 + k] + 1, a->idx[t * 3 + k] + 1,
                    a->idx[t * 3 + k] + 1);
        fprintf(f, "\n");
    }
    return fclose(f) == 0;
}

/* A textured asset with seams (a, each chart's cell checkered in its colour, with a margin
 * of a colour no chart has), unlit, at each of its levels of detail: the renderer forced to
 * the level (the bound that makes limen_view_mesh_lod choose it) draws what the tracer
 * traces at that level (limen_trace_desc.lod_level; lod_pixels chooses the same), within the
 * 0.5% the full mesh meets; and the level's picture is the full mesh's moved by at most the
 * level's bound: every pixel has its colour in the full mesh's truth within the bound's
 * pixels (plus one), so no texture smears across a seam, where the margin's or another
 * chart's colour would show. At least min_levels levels, the coarsest at most 1/fraction of
 * the triangles where fraction > 0. */
static void lod_asset_levels(const lod_asset *a, int min_levels, int fraction)
{
    enum { W = 160, H = 120 };
    int side = 1;
    while (side * side < a->charts)
        side++;
    const int CELL = a->cell, T = side * CELL, MARGIN = CELL / 32 ? CELL / 32 : 1;
    const int NT = a->nt;
    unsigned char *tex = malloc((size_t)T * T * 3), *img = malloc(W * H * 3), *full = malloc(W * H * 3),
                  *lvl = malloc(W * H * 3), *by_px = malloc(W * H * 3);
    unsigned char *shown = NULL;
    char dir[] = "/tmp/limen_lod_XXXXXX", path[64] = "";
    bool made = false;
    limen_scene *s = new_scene();
    limen_renderer *r = NULL;
    limen_drawables *dr = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    CHECK_OK(limen_drawables_create(&dr));
    if (!tex || !img || !full || !lvl || !by_px || !s || !r || !dr ||
        !(made = mkdtemp(dir) != NULL)) {
        CHECK(!"setup");
        goto done;
    }
    /* the texels the charts' triangles show (in the texture's coordinates: each axis-aligned
     * box of a square's two), a texel around them included */
    shown = a->notches ? calloc((size_t)T * T, 1) : NULL;
    for (int t = 0; shown && t < NT; t += 2) {
        float lo[2] = { 2, 2 }, hi[2] = { -1, -1 };
        for (int k = 0; k < 6; k++)
            for (int d = 0; d < 2; d++) {
                float u = a->uv[a->idx[t * 3 + k] * 2 + d];
                lo[d] = u < lo[d] ? u : lo[d];
                hi[d] = u > hi[d] ? u : hi[d];
            }
        for (int y = (int)floorf(lo[1] * T) - 1; y <= (int)ceilf(hi[1] * T); y++)
            for (int x = (int)floorf(lo[0] * T) - 1; x <= (int)ceilf(hi[0] * T); x++)
                if (x >= 0 && y >= 0 && x < T && y < T)
                    shown[(size_t)(T - 1 - y) * T + x] = 1;
    }
    /* chart c's colour checkered light and dark; margins and unused cells magenta */
    for (int y = 0; y < T; y++)
        for (int x = 0; x < T; x++) {
            int c = (T - 1 - y) / CELL * side + x / CELL, ix = x % CELL, iy = y % CELL;
            bool margin = c >= a->charts || ix < MARGIN || ix >= CELL - MARGIN ||
                          iy < MARGIN || iy >= CELL - MARGIN ||
                          (shown && !shown[(size_t)y * T + x]);
            for (int k = 0; k < 3; k++)
                tex[((size_t)y * T + x) * 3 + k] =
                    margin ? lod_colour[5][k]
                           : (unsigned char)(lod_colour[a->colour[c]][k] *
                                             ((ix / 8 + iy / 8) % 2 ? 1.0 : 0.55));
        }
    snprintf(path, sizeof path, "%s/atlas.png", dir);
    CHECK_OK(limen_write_png(path, T, T, tex));
    limen_node cam = add(s, LIMEN_NODE_CAMERA, "cam", 0, 0, 0), ball = { 0 };
    CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 0.6f, 0.9f, 2.6f }, (float[3]){ 0, 0, 0 },
                                (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_scene_set_ambient(s, 1.0f));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "ball", &ball));
    if (a->file) {
        char obj[96];
        CHECK(lod_asset_obj(a, dir, obj, sizeof obj));
        CHECK_OK(limen_mesh_load(s, ball, obj));
    } else {
        CHECK_OK(limen_mesh_set_triangles(s, ball, &(limen_mesh_data){
            .positions = a->pos, .normals = a->nrm, .uvs = a->uv, .vertex_count = a->nv,
            .indices = a->idx, .triangle_count = NT }));
        CHECK_OK(limen_node_set_texture(s, ball, path));
    }
    /* one point of the texture per pixel in both: no level of a mipmap to choose */
    CHECK_OK(limen_node_set_texture_filter(s, ball, LIMEN_FILTER_LINEAR));
    /* the camera's view and the ball as the renderer reads them */
    CHECK_OK(limen_render_frame(r, s, NULL, NULL));
    CHECK_OK(limen_drawables_build(dr, s));
    const limen_drawable *all = NULL;
    limen_drawables_items(dr, &all);
    int di = limen_drawables_find(dr, ball);
    const limen_view *root = limen_plan_view(limen_renderer_plan(r), 0);
    if (di < 0 || !root || !all[di].mesh) {
        CHECK(!"no ball");
        goto done;
    }
    const limen_drawable *d = &all[di];
    const limen_mesh_geometry *g = d->mesh;
    CHECK_MSG(g->lod_count >= min_levels, "%s: %d levels", a->name, g->lod_count);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H }, full));
    /* pixels per unit of the mesh at the ball's nearest point (limen_view_mesh_lod's) */
    const float *m = root->view;
    double depth = -(m[2] * d->centre[0] + m[6] * d->centre[1] + m[10] * d->centre[2] + m[14]);
    double to_px = root->proj[5] * 0.5 * H / (depth - d->radius);
    int reached = 0;
    for (int k = 0; k < g->lod_count; k++) {
        float px = 0;   /* the smallest bound of 2^(j/8) pixels that chooses level k */
        for (int j = -80; j <= 120 && !px; j++)
            if (limen_view_mesh_lod(root, H, d, powf(2.0f, j / 8.0f)) == k)
                px = powf(2.0f, j / 8.0f);
        if (!px)
            continue;   /* its error equals a coarser level's: never chosen */
        reached++;
        limen_render_opts o = { .limits = { .lod_pixels = k ? px : LIMEN_LOD_FULL } };
        limen_frame_stats st;
        CHECK_OK(limen_render_frame(r, s, &o, &st));
        CHECK_MSG(st.triangles == (uint64_t)g->lods[k].triangle_count, "level %d: %llu triangles "
                  "drawn, %d in the level", k, (unsigned long long)st.triangles,
                  g->lods[k].triangle_count);
        CHECK_OK(limen_renderer_read_rgb(r, img));
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H,
                                                           .lod_level = k }, lvl));
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H,
                                                           .lod_pixels = k ? px : 0 }, by_px));
        CHECK_MSG(memcmp(lvl, by_px, W * H * 3) == 0, "level %d: lod_pixels %g traces another "
                  "level", k, (double)px);
        limen_diff dl;
        CHECK_OK(limen_image_diff(img, lvl, W, H, 8, &dl, NULL));
        CHECK_MSG(dl.bad_share <= 0.005, "level %d (%d triangles): render %.3f%% off its trace", k,
                  g->lods[k].triangle_count, 100 * dl.bad_share);
        int radius = (int)ceil(g->lods[k].error * to_px) + 1;
        int moved = unmatched_within(lvl, full, W, H, radius, g->lods[k].baked != NULL);
        CHECK_MSG(moved <= W * H / 2000, "level %d (error %.2f px): %d pixels with no colour of "
                  "the full mesh's within %d px", k, g->lods[k].error * to_px, moved, radius);
        if (getenv("LIMEN_TEST_PNGS")) {
            char png[96];
            snprintf(png, sizeof png, "%s/lod_%s_%d.png", getenv("LIMEN_TEST_PNGS"), a->name, k);
            limen_write_png(png, W, H, lvl);
        }
        if (getenv("LIMEN_TEST_VERBOSE"))
            fprintf(stderr, "%s, level %d: %d triangles, error %.3f px, render %.3f%% off its trace, "
                    "%d pixels unmatched within %d px\n", a->name, k, g->lods[k].triangle_count,
                    g->lods[k].error * to_px, 100 * dl.bad_share, moved, radius);
    }
    /* every level kept is drawn and checked (each is the coarsest within some bound), and
     * five or more reach 1/16 of the triangles */
    CHECK_MSG(reached >= min_levels && reached == g->lod_count, "%d of %d levels reached",
              reached, g->lod_count);
    CHECK_MSG(fraction <= 0 || g->lods[g->lod_count - 1].triangle_count * fraction <= NT,
              "%s: the coarsest level %d triangles", a->name,
              g->lods[g->lod_count - 1].triangle_count);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H, .lod_level = -1 },
                            lvl) == LIMEN_ERR_ARG);
    CHECK(limen_trace_image(s, &(limen_trace_desc){ .width = W, .height = H,
                                                    .lod_pixels = NAN }, lvl) == LIMEN_ERR_ARG);
    CHECK_MSG(strstr(limen_scene_error(s), "lod_pixels"), "%s", limen_scene_error(s));
    if (a->file) {
        /* past the charts' floor the levels are baked: their own triangles, as many */
        const limen_mesh_lod *last = &g->lods[g->lod_count - 1];
        CHECK_MSG(last->baked && last->baked->triangle_count == last->triangle_count &&
                  last->baked->material_count == 1 && last->baked->materials[0].base_texture,
                  "%s: the coarsest level is not baked", a->name);
        /* and the plan's JSON says so, with the baked level's one part */
        char json[96], text[4096] = "";
        snprintf(json, sizeof json, "%s/plan.json", dir);
        limen_render_opts o = { .limits = { .lod_pixels = 1e6f } };
        CHECK_OK(limen_render_frame(r, s, &o, NULL));
        CHECK_OK(limen_plan_write_json(limen_renderer_plan(r), s, json));
        read_text(json, text, sizeof text);
        remove(json);
        char want[96];
        snprintf(want, sizeof want, "\"lod\": %d, \"triangles\": %d, \"baked\": true, "
                 "\"parts\": [{\"first\": 0, \"count\": %d", g->lod_count - 1,
                 last->triangle_count, last->triangle_count);
        CHECK_MSG(strstr(text, want), "%s: the plan lists no baked level (%.200s)", a->name,
                  text);
    }
done:
    if (path[0])
        remove(path);
    if (made) {
        char f[96];
        snprintf(f, sizeof f, "%s/ball.obj", dir);
        remove(f);
        snprintf(f, sizeof f, "%s/ball.mtl", dir);
        remove(f);
        rmdir(dir);
    }
    limen_drawables_destroy(dr);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
    free(shown);
    free(tex);
    free(img);
    free(full);
    free(lvl);
    free(by_px);
}

/* The ball of charted_ball (tile x tile squares a chart), chart c's colour by its place,
 * a chart's neighbours on its face each another colour (of five). */
static void lod_levels(int tile, int min_levels, bool file)
{
    enum { N = 40, NT = 5 * N * N * 2 };
    int per = N / tile, charts = 5 * per * per, nv = charted_verts(N, tile);
    float *pos = malloc(sizeof(float) * 3 * nv), *nrm = malloc(sizeof(float) * 3 * nv),
          *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * NT);
    int *colour = malloc(sizeof(int) * charts);
    if (pos && nrm && uv && idx && colour) {
        charted_ball(N, tile, pos, nrm, uv, idx);
        for (int c = 0; c < charts; c++) {
            int f = c / (per * per), cj = c / per % per, ci = c % per;
            colour[c] = (f + ci + 2 * cj) % 5;
        }
        char name[32];
        snprintf(name, sizeof name, "charts_of_%d", tile);
        lod_asset_levels(&(lod_asset){ .name = name, .nv = nv, .nt = NT, .charts = charts,
                                       .cell = tile == N ? 64 : 32, .pos = pos, .nrm = nrm,
                                       .uv = uv, .idx = idx, .colour = colour, .file = file },
                         min_levels, min_levels >= 5 ? 16 : 0);
    } else {
        CHECK(!"out of memory");
    }
    free(pos);
    free(nrm);
    free(uv);
    free(idx);
    free(colour);
}

static void test_lod_levels(void)
{
    lod_levels(40, 5, false);
}

/* The same with 500 charts of 4 x 4 squares (a margin around each): a triangle whose
 * corners lie on two charts (clustering makes them) shows the atlas between its corners'
 * coordinates, other charts' colours and the margin, which the full mesh shows nowhere
 * near, so no distance bounds it: no level has one, and each level shows no colour farther
 * than its error from where the full mesh shows it. The coarse levels, made within the
 * charts (core/lod_charts.c), reach 1/16 of the triangles in five levels. */
static void test_lod_charts(void)
{
    lod_levels(4, 5, false);
}

/* 2,000 charts of 2 x 2 squares, loaded from a file whose material has the atlas: the
 * charts hold the levels within them above a quarter of the triangles, and the coarser ones
 * are baked (core/lod_bake.c), each with a texture of its own: five levels or more to 1/16,
 * each drawn as traced, and none showing a colour farther than its error from where the
 * full mesh shows it. */
static void test_lod_baked(void)
{
    lod_levels(2, 5, true);
}

/* Colours (of lod_colour's five) for charts (chart per vertex of nv at pos) so that charts
 * with a vertex at one position differ wherever five allow. */
static const float *lod_sort_pos;

static int lod_pos_cmp(const void *a, const void *b)
{
    return memcmp(&lod_sort_pos[*(const int *)a * 3], &lod_sort_pos[*(const int *)b * 3],
                  sizeof(float) * 3);
}

static bool lod_colours(const float *pos, const int *chart, int nv, int charts, int *colour)
{
    int *order = malloc(sizeof(int) * nv);
    unsigned char *near = calloc((size_t)charts * charts, 1);
    if (!order || !near) {
        free(order);
        free(near);
        return false;
    }
    for (int v = 0; v < nv; v++)
        order[v] = v;
    lod_sort_pos = pos;
    qsort(order, nv, sizeof *order, lod_pos_cmp);
    for (int i = 0, j; i < nv; i = j) {
        for (j = i + 1; j < nv && !lod_pos_cmp(&order[i], &order[j]); j++)
            ;
        for (int a = i; a < j; a++)
            for (int b = i; b < j; b++)
                near[(size_t)chart[order[a]] * charts + chart[order[b]]] = 1;
    }
    for (int c = 0; c < charts; c++) {
        int clash[5] = { 0 }, best = 0;
        for (int d = 0; d < c; d++)
            if (d != c && near[(size_t)c * charts + d])
                clash[colour[d]]++;
        for (int k = 1; k < 5; k++)
            if (clash[k] < clash[best])
                best = k;
        colour[c] = best;
    }
    free(order);
    free(near);
    return true;
}

/* A ball of charted_layout's (tests/charted.h) in the charts square_chart gives (n x n
 * squares a face), checked as lod_asset_levels does. */
static void lod_layout_levels(const char *name, int n, const int *square, bool notches,
                              int min_levels, int fraction)
{
    int nt = 5 * n * n * 2, nv = charted_layout(n, square, NULL, NULL, NULL, NULL, NULL),
        charts = 0;
    for (int q = 0; q < 5 * n * n; q++)
        charts = square[q] + 1 > charts ? square[q] + 1 : charts;
    charted_arrays a;
    int *colour = malloc(sizeof(int) * charts);
    if (charted_arrays_make(&a, nv, nt) && colour &&
        charted_layout(n, square, a.pos, a.nrm, a.uv, a.idx, a.chart) == nv &&
        lod_colours(a.pos, a.chart, nv, charts, colour))
        lod_asset_levels(&(lod_asset){ .name = name, .nv = nv, .nt = nt, .charts = charts,
                                       .cell = 32, .pos = a.pos, .nrm = a.nrm, .uv = a.uv,
                                       .idx = a.idx, .colour = colour, .notches = notches },
                         min_levels, fraction);
    else
        CHECK(!"out of memory");
    charted_arrays_free(&a);
    free(colour);
}

/* Concave charts (tests/charted.h charted_ells: each 2 x 2 block of 4 x 4 squares an L of
 * three and the square of the fourth, 250 charts): where the L's inner corner moves along
 * its seams, the seam between the L and the square no longer runs where it did, and the L
 * shows, where the square was, what its cell of the atlas holds beside it: its own colour
 * (a texture's padding around a chart), or with notches the margin's (an atlas packs other
 * charts into a concave chart's notches), which the full mesh shows nowhere. Five levels
 * down to 1/16 of the triangles; no level's seams lie farther from the full mesh's than its
 * bound (the next, which would show the notches over half of each square, is not kept). */
static void test_lod_concave(void)
{
    enum { N = 40 };
    int *square = malloc(sizeof(int) * 5 * N * N);
    if (square) {
        charted_ells(N, 4, square);
        lod_layout_levels("concave", N, square, false, 5, 16);
        lod_layout_levels("notches", N, square, true, 5, 16);
    } else {
        CHECK(!"out of memory");
    }
    free(square);
}

/* The ball's charts as bricks (tests/charted.h charted_bricks: 275 charts, three meeting at
 * every corner), down to the fewest triangles the charts allow (990, 1/16): no level shows
 * a colour farther than its bound from where the full mesh shows it. */
static void test_lod_bricks(void)
{
    enum { N = 40, NT = 5 * N * N * 2 };
    int nv = charted_bricks(N, 8, 4, NULL, NULL, NULL, NULL, NULL), charts = 0;
    charted_arrays a;
    int *colour = NULL;
    if (charted_arrays_make(&a, nv, NT) &&
        charted_bricks(N, 8, 4, a.pos, a.nrm, a.uv, a.idx, a.chart) == nv) {
        for (int v = 0; v < nv; v++)
            charts = a.chart[v] + 1 > charts ? a.chart[v] + 1 : charts;
        colour = malloc(sizeof(int) * charts);
    }
    if (colour && lod_colours(a.pos, a.chart, nv, charts, colour))
        lod_asset_levels(&(lod_asset){ .name = "bricks", .nv = nv, .nt = NT, .charts = charts,
                                       .cell = 32, .pos = a.pos, .nrm = a.nrm, .uv = a.uv,
                                       .idx = a.idx, .colour = colour },
                         5, 16);
    else
        CHECK(!"out of memory");
    charted_arrays_free(&a);
    free(colour);
}

/* Whether two loads' levels are the same: their triangles, errors (to the bit), and the
 * baked ones' vertices, texture coordinates and texels. */
static bool same_baked(const limen_mesh_geometry *a, const limen_mesh_geometry *b)
{
    if (a->lod_count != b->lod_count)
        return false;
    for (int k = 0; k < a->lod_count; k++) {
        const limen_mesh_lod *x = &a->lods[k], *y = &b->lods[k];
        if (x->triangle_count != y->triangle_count ||
            memcmp(&x->error, &y->error, sizeof x->error) || !x->baked != !y->baked)
            return false;
        if (!x->baked)
            continue;
        const limen_mesh_geometry *p = x->baked, *q = y->baked;
        const limen_image *pi = p->materials[0].base_texture, *qi = q->materials[0].base_texture;
        size_t nv = (size_t)p->vertex_count;
        if (p->vertex_count != q->vertex_count ||
            memcmp(p->positions, q->positions, sizeof(float) * 3 * nv) ||
            memcmp(p->uvs, q->uvs, sizeof(float) * 2 * nv) || pi->width != qi->width ||
            pi->height != qi->height ||
            memcmp(pi->rgb, qi->rgb, (size_t)pi->width * (size_t)pi->height * 3))
            return false;
    }
    return true;
}

/* Baked levels kept between runs (core/lod_cache.c keeps their triangles and surface bound;
 * the texture is baked again when read): a second load of the same file reads the entry and
 * gets the same levels, errors, vertices and texels. */
static void test_lod_baked_cache(void)
{
    enum { N = 40, NT = 5 * N * N * 2, T = 64 };
    int nv = charted_verts(N, 2);
    char dir[] = "/tmp/limen_bakedXXXXXX", cache[64], f[96], obj[96], entry[4200] = "";
    float *pos = malloc(sizeof(float) * 3 * nv), *nrm = malloc(sizeof(float) * 3 * nv),
          *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * NT);
    unsigned char *tex = malloc(T * T * 3);
    limen_scene *sc[2] = { NULL, NULL };
    limen_drawables *dr[2] = { NULL, NULL };
    const limen_mesh_geometry *g[2] = { NULL, NULL };
    if (!pos || !nrm || !uv || !idx || !tex || !mkdtemp(dir)) {
        CHECK(!"setup");
        goto done;
    }
    charted_ball(N, 2, pos, nrm, uv, idx);
    for (int i = 0; i < T * T * 3; i++)
        tex[i] = (unsigned char)(i * 37 % 251);
    snprintf(f, sizeof f, "%s/atlas.png", dir);
    CHECK_OK(limen_write_png(f, T, T, tex));
    CHECK(lod_asset_obj(&(lod_asset){ .nv = nv, .nt = NT, .pos = pos, .nrm = nrm, .uv = uv,
                                      .idx = idx }, dir, obj, sizeof obj));
    snprintf(cache, sizeof cache, "%s/cache", dir);
    setenv("LIMEN_CACHE_DIR", cache, 1);
    unsetenv("LIMEN_CACHE");
    /* the first load makes and stores them, the second (the first still held) reads them */
    for (int run = 0; run < 2; run++) {
        sc[run] = new_scene();
        limen_node ball;
        CHECK_OK(limen_drawables_create(&dr[run]));
        CHECK_OK(limen_node_create(sc[run], LIMEN_NODE_MESH, "ball", &ball));
        CHECK_OK(limen_mesh_load(sc[run], ball, obj));
        CHECK_OK(limen_drawables_build(dr[run], sc[run]));
        const limen_drawable *all = NULL;
        limen_drawables_items(dr[run], &all);
        int di = limen_drawables_find(dr[run], ball);
        g[run] = di >= 0 ? all[di].mesh : NULL;
        CHECK(g[run] && g[run]->lod_count >= 5 && g[run]->lods[g[run]->lod_count - 1].baked);
        CHECK_MSG(entries(cache, entry, sizeof entry) == 1, "run %d: no entry", run);
    }
    CHECK_MSG(g[0] && g[1] && same_baked(g[0], g[1]),
              "the levels read back differ from those made");
done:
    setenv("LIMEN_CACHE", "off", 1);
    unsetenv("LIMEN_CACHE_DIR");
    snprintf(f, sizeof f, "%s/atlas.png", dir);
    remove(f);
    snprintf(f, sizeof f, "%s/ball.obj", dir);
    remove(f);
    snprintf(f, sizeof f, "%s/ball.mtl", dir);
    remove(f);
    if (entry[0])
        remove(entry);
    snprintf(f, sizeof f, "%s/cache", dir);
    rmdir(f);
    rmdir(dir);
    free(pos);
    free(nrm);
    free(uv);
    free(idx);
    free(tex);
    for (int run = 0; run < 2; run++) {
        limen_drawables_destroy(dr[run]);
        limen_scene_destroy(sc[run]);
    }
}

static const check_case cases[] = {
    { "sphere_analytic", test_sphere_analytic },
    { "shapes_scaled", test_shapes_scaled },
    { "portal_pair", test_portal_pair },
    { "mirror_front_back", test_mirror_front_back },
    { "drift_corridor", test_drift_corridor },
    { "image_shading", test_image_shading },
    { "checker", test_checker },
    { "bounce_limit", test_bounce_limit },
    { "errors", test_errors },
    { "png_write_whole_or_not", test_png_write_whole_or_not },
    { "png_read_limits", test_png_read_limits },
    { "wide_depth_range", test_wide_depth_range },
    { "samples", test_samples },
    { "msaa_truth", test_msaa_truth },
    { "lod_levels", test_lod_levels },
    { "lod_charts", test_lod_charts },
    { "lod_baked", test_lod_baked },
    { "lod_baked_cache", test_lod_baked_cache },
    { "lod_concave", test_lod_concave },
    { "lod_bricks", test_lod_bricks },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
