/* fuzz_api.c - libFuzzer target for the C API beyond the loader (make fuzz). The input is a
 * little program of byte-coded calls that builds a scene (nodes of every kind, transforms,
 * sizes, parents, portal links, lenses, local matrices, destroys); the scene is then planned
 * for a small image with a small budget, the plan written as JSON (and checked to hold no
 * inf or nan), the scene traced at 8x6, rays cast, nodes moved, swept and slid. Numbers come from one
 * byte each: small steps most of the time, and now and then an extreme (0, 1e-9, 1e9, 1e38,
 * inf, nan, ...), which the setters must refuse or the rest must survive. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "limen.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_NODES 24

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static unsigned byte(reader *r)
{
    if (!r->n)
        return 0;
    r->n--;
    return *r->p++;
}

static float number(reader *r)
{
    static const float extremes[16] = { 0.0f, -0.0f, 1e-9f, 1e9f, -1e9f, 1e38f, -1e38f, INFINITY,
                                        NAN, 1e-12f, 2e9f, 1e-30f, 0.001f, 1000.0f, 1e6f, -1.0f };
    unsigned b = byte(r);
    return b < 240 ? ((float)b - 120.0f) / 8.0f : extremes[b - 240];
}

static void vec(reader *r, float v[3])
{
    for (int i = 0; i < 3; i++)
        v[i] = number(r);
}

static limen_node pick(reader *r, const limen_node *nodes, int count)
{
    return count ? nodes[byte(r) % count] : (limen_node){ 0 };
}

static void check_json(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf - 1, f)) > 0) {
        buf[n] = 0;
        if (strstr(buf, "inf") || strstr(buf, "nan"))
            abort();    /* JSON never holds them */
    }
    fclose(f);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = { data, size };
    limen_scene *s = NULL;
    if (limen_scene_create(&(limen_scene_desc){ .max_nodes = MAX_NODES }, &s))
        return 0;
    limen_node nodes[MAX_NODES];
    int count = 0;
    float v[3], w[3];
    for (int step = 0; step < 200 && r.n; step++) {
        limen_node n = pick(&r, nodes, count);
        switch (byte(&r) % 16) {
        case 0:
        case 1: {
            limen_node made;
            if (count < MAX_NODES &&
                !limen_node_create(s, (limen_node_kind)(byte(&r) % LIMEN_NODE_KIND_COUNT), NULL,
                                   &made)) {
                nodes[count++] = made;
                if (limen_node_get_kind(s, made) == LIMEN_NODE_CAMERA)
                    limen_scene_set_camera(s, made);
            }
            break;
        }
        case 2: vec(&r, v); limen_node_set_position(s, n, v); break;
        case 3: vec(&r, v); limen_node_set_rotation(s, n, v); break;
        case 4: vec(&r, v); limen_node_set_scale(s, n, v); break;
        case 5: vec(&r, v); limen_node_set_dims(s, n, v); break;
        case 6: vec(&r, v); vec(&r, w); limen_node_set_facing(s, n, v, byte(&r) & 1 ? w : NULL); break;
        case 7: limen_node_set_parent(s, n, pick(&r, nodes, count)); break;
        case 8: limen_portal_link(s, n, pick(&r, nodes, count)); break;
        case 9: limen_camera_set_lens(s, n, number(&r), number(&r), number(&r)); break;
        case 10: {
            float m[16];
            for (int i = 0; i < 16; i++)
                m[i] = i % 5 == 0 ? 1.0f + number(&r) / 16 : number(&r) / 16;
            limen_node_set_local_matrix(s, n, m);
            break;
        }
        case 11: vec(&r, v); vec(&r, w); limen_node_look_at(s, n, v, w, NULL); break;
        case 12: vec(&r, v); limen_node_set_color(s, n, v); break;
        case 13: limen_surface_set_max_depth(s, n, (int)(byte(&r) % 12)); break;
        case 14: vec(&r, v); limen_node_move(s, n, v, NULL); break;
        case 15:
            if (!limen_node_destroy(s, n))
                limen_node_valid(s, n);
            break;
        }
    }

    limen_plan *p = NULL;
    if (!limen_plan_create(&p)) {
        limen_plan_desc d = { .width = 32, .height = 24,
                              .range = (limen_depth_range)(size / 3 % 3),
                              .limits = { .max_views = 64, .clip = (limen_clip_method)(size % 3),
                                          .budget = { .view_pixels = 32 * 24 * 16,
                                                      .surface_tests = 4096 } } };
        if (!limen_plan_build(p, s, &d)) {
            for (int i = 0; i < limen_plan_count(p); i++) {
                const limen_view_surface *vs;
                int k = limen_plan_view_surfaces(p, i, &vs);
                for (int j = 0; j < k; j++)
                    if (vs[j].child >= limen_plan_count(p))
                        abort();
            }
            char path[64];
            snprintf(path, sizeof path, "/tmp/limen-fuzz-%ld.json", (long)getpid());
            if (!limen_plan_write_json(p, s, path))
                check_json(path);
            remove(path);
        }
        limen_plan_destroy(p);
    }
    unsigned char rgb[8 * 6 * 3];
    limen_trace_image(s, &(limen_trace_desc){ .width = 8, .height = 6, .threads = 1,
                                              .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP,
                                                          .depth = 6 } },
                      rgb);
    for (int i = 0; i < 4 && r.n; i++) {
        limen_hit h;
        vec(&r, v);
        vec(&r, w);
        int depth = (int)(byte(&r) % 10) - 1;     /* -1: the surfaces' own limits */
        limen_limits lim = { .depth_rule = depth < 0 ? LIMEN_DEPTH_RULE_OWN : LIMEN_DEPTH_RULE_CAP,
                             .depth = depth < 0 ? 0 : depth };
        limen_ray_cast(s, v, w, &lim, &h);
    }
    for (int i = 0; i < count && r.n; i++) {
        limen_move_result mr;
        vec(&r, v);
        limen_node_move(s, nodes[i], v, &mr);
    }
    /* collisions: sweeps (spheres, capsules) and slides with fuzzed numbers */
    for (int i = 0; i < count && r.n; i++) {
        limen_sweep_result sr;
        limen_slide_result lr;
        float u[3];
        vec(&r, v);
        vec(&r, w);
        vec(&r, u);
        float rad = number(&r);
        limen_sweep_opts o = { .ignore = byte(&r) & 1 ? nodes[i] : (limen_node){ 0 } };
        limen_sweep_sphere(s, v, w, rad, &o, &sr);
        limen_sweep_capsule(s, v, u, rad, w, NULL, &sr);
        if (byte(&r) & 1)
            limen_node_slide(s, nodes[i], w, rad, &lr);
        else
            limen_node_slide_capsule(s, nodes[i], w, rad, u, &lr);
    }
    limen_scene_destroy(s);
    return 0;
}
