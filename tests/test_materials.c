/* test_materials.c - meshes of parts, one material each: glTF files written here (several
 * materials, vertex colours, alpha mask and blend, a texture transform, embedded, external,
 * misplaced and missing images), the 5-material spider and the vertex-coloured cube; every
 * render held to the ray tracer, both methods. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "limen.h"

#define BOUND 0.005     /* share of pixels that may differ by more than 8/255 */

static char dir[64];

static const char *in_dir(const char *name)
{
    static char path[8][256];
    static int k;
    char *p = path[k++ % 8];
    snprintf(p, 256, "%s/%s", dir, name);
    return p;
}

static void write_bytes(const char *name, const void *data, size_t n)
{
    FILE *f = fopen(in_dir(name), "wb");
    CHECK(f != NULL);
    if (!f)
        return;
    fwrite(data, 1, n, f);
    fclose(f);
}

static unsigned char *read_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)len);
    *n = fread(buf, 1, (size_t)len, f);
    fclose(f);
    return buf;
}

static char *base64(const unsigned char *in, size_t n)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = malloc(4 * ((n + 2) / 3) + 1), *o = out;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? (unsigned)in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        *o++ = abc[v >> 18 & 63];
        *o++ = abc[v >> 12 & 63];
        *o++ = i + 1 < n ? abc[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? abc[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

/* An uncompressed 32-bit TGA (bottom row first): w x h RGBA. */
static void write_tga(const char *name, int w, int h, const unsigned char *rgba_top_first)
{
    size_t n = 18 + (size_t)w * h * 4;
    unsigned char *b = calloc(1, n);
    b[2] = 2;
    b[12] = (unsigned char)w;
    b[13] = (unsigned char)(w >> 8);
    b[14] = (unsigned char)h;
    b[15] = (unsigned char)(h >> 8);
    b[16] = 32;
    b[17] = 8;          /* 8 alpha bits, rows bottom first */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char *s = rgba_top_first + ((size_t)(h - 1 - y) * w + x) * 4;
            unsigned char *d = b + 18 + ((size_t)y * w + x) * 4;
            d[0] = s[2];
            d[1] = s[1];
            d[2] = s[0];
            d[3] = s[3];
        }
    write_bytes(name, b, n);
    free(b);
}

/* ------------------------------------------------------------------ a glTF of quads */

/* The quad (1 x 1, facing +Z) every mesh shows: positions, normals, uvs (glTF's v down),
 * colours (white on the left, 0.2 on the right) and indices, in one buffer. */
static char *quad_buffer(size_t *len)
{
    static const float pos[12] = { -0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0 };
    static const float nrm[12] = { 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 };
    static const float uv[8] = { 0, 1, 1, 1, 1, 0, 0, 0 };
    static const float col[16] = { 1, 1, 1, 1, 0.2f, 0.2f, 0.2f, 1, 0.2f, 0.2f, 0.2f, 1,
                                   1, 1, 1, 1 };
    static const unsigned short idx[6] = { 0, 1, 2, 0, 2, 3 };
    unsigned char buf[48 + 48 + 32 + 64 + 12];
    memcpy(buf, pos, 48);
    memcpy(buf + 48, nrm, 48);
    memcpy(buf + 96, uv, 32);
    memcpy(buf + 128, col, 64);
    memcpy(buf + 192, idx, 12);
    *len = sizeof buf;
    return base64(buf, sizeof buf);
}

/* The grid: which material each quad shows, and where. */
typedef struct quad { float x, y, z, scale; int material; int colours; } quad;

static const quad grid[] = {
    { -1.65f, 0.6f, 0, 1, 0, 1 },       /* A: a factor times vertex colours */
    { -0.55f, 0.6f, 0, 1, 1, 0 },       /* B: an embedded PNG, its coordinates scaled by 2 */
    { 0.55f, 0.6f, 0, 1, 2, 0 },        /* C: masked by a TGA's alpha */
    { 1.65f, 0.6f, 0, 1, 3, 0 },        /* D: an absolute path, found beside the file */
    { -1.65f, -0.6f, 0, 1, 4, 0 },      /* E: a path outside the folder, found beside */
    { -0.55f, -0.6f, 0, 1, 5, 0 },      /* F: a missing image: its own colour */
    { 0.55f, -0.6f, 0.3f, 1, 6, 0 },    /* G: blended (alpha 0.5) over H */
    { 0.85f, -0.6f, 0, 1, 7, 0 },       /* H: opaque, emissive */
};
enum { NQUADS = sizeof grid / sizeof grid[0] };

static const char *const materials_json =
    "{\"name\": \"factor\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.9, 0.5, 0.25, 1]}},"
    "{\"name\": \"embedded\", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0,"
    " \"extensions\": {\"KHR_texture_transform\": {\"scale\": [2, 2]}}}}},"
    "{\"name\": \"mask\", \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.5,"
    " \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 1}}},"
    "{\"name\": \"absolute\", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 2}}},"
    "{\"name\": \"uptree\", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 3},"
    " \"baseColorFactor\": [1, 0.8, 0.8, 1]}},"
    "{\"name\": \"missing\", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 4},"
    " \"baseColorFactor\": [0.3, 0.6, 0.9, 1]}},"
    "{\"name\": \"glass\", \"alphaMode\": \"BLEND\","
    " \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 1, 0.5]}},"
    "{\"name\": \"glow\", \"emissiveFactor\": [0.3, 0, 0],"
    " \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.1, 0.8, 0.1, 1]}}";

/* Writes the glTF and its images; returns its path. */
static const char *write_gltf(void)
{
    /* images: a 2x2 PNG to embed, a 4x4 TGA (left half clear), a 2x2 PNG beside the file */
    const unsigned char px[12] = { 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255 };
    CHECK_OK(limen_write_png(in_dir("embed.png"), 2, 2, px));
    size_t plen = 0;
    unsigned char *png = read_bytes(in_dir("embed.png"), &plen);
    char *png64 = base64(png, plen);
    free(png);
    unsigned char rgba[4 * 4 * 4];
    for (int i = 0; i < 16; i++) {
        rgba[i * 4] = (unsigned char)(60 * (i / 4));
        rgba[i * 4 + 1] = 200;
        rgba[i * 4 + 2] = (unsigned char)(255 - 60 * (i / 4));
        rgba[i * 4 + 3] = i % 4 < 2 ? 0 : 255;
    }
    write_tga("cutout.tga", 4, 4, rgba);
    const unsigned char side[12] = { 250, 200, 40, 40, 90, 220, 30, 160, 60, 240, 240, 240 };
    CHECK_OK(limen_write_png(in_dir("beside.png"), 2, 2, side));
    size_t blen;
    char *buf64 = quad_buffer(&blen);
    size_t cap = 16384 + strlen(png64) + strlen(buf64);
    char *j = malloc(cap);
    int n = snprintf(j, cap, "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0,"
                     " \"extensionsUsed\": [\"KHR_texture_transform\"], \"scenes\": [{\"nodes\": [");
    for (int q = 0; q < NQUADS; q++)
        n += snprintf(j + n, cap - n, "%s%d", q ? ", " : "", q);
    n += snprintf(j + n, cap - n, "]}], \"nodes\": [");
    for (int q = 0; q < NQUADS; q++)
        n += snprintf(j + n, cap - n, "%s{\"name\": \"q%d\", \"mesh\": %d, \"translation\": [%g, %g, %g]}",
                      q ? ", " : "", q, q, grid[q].x, grid[q].y, grid[q].z);
    n += snprintf(j + n, cap - n, "], \"meshes\": [");
    for (int q = 0; q < NQUADS; q++)
        n += snprintf(j + n, cap - n, "%s{\"primitives\": [{\"attributes\": {\"POSITION\": 0,"
                      " \"NORMAL\": 1, \"TEXCOORD_0\": 2%s}, \"indices\": 4, \"material\": %d}]}",
                      q ? ", " : "", grid[q].colours ? ", \"COLOR_0\": 3" : "", grid[q].material);
    n += snprintf(j + n, cap - n, "], \"materials\": [%s],", materials_json);
    n += snprintf(j + n, cap - n,
                  " \"textures\": [{\"source\": 0}, {\"source\": 1}, {\"source\": 2},"
                  " {\"source\": 3}, {\"source\": 4}],"
                  " \"images\": [{\"uri\": \"data:image/png;base64,%s\"}, {\"uri\": \"cutout.tga\"},"
                  " {\"uri\": \"D:/projects/textures/BESIDE.PNG\"}, {\"uri\": \"../../../3DS/beside.png\"},"
                  " {\"uri\": \"nothere.png\"}],", png64);
    n += snprintf(j + n, cap - n,
                  " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,%s\"}],"
                  " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},"
                  " {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48},"
                  " {\"buffer\": 0, \"byteOffset\": 96, \"byteLength\": 32},"
                  " {\"buffer\": 0, \"byteOffset\": 128, \"byteLength\": 64},"
                  " {\"buffer\": 0, \"byteOffset\": 192, \"byteLength\": 12}],"
                  " \"accessors\": ["
                  "{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\","
                  " \"min\": [-0.5, -0.5, 0], \"max\": [0.5, 0.5, 0]},"
                  "{\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},"
                  "{\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
                  "{\"bufferView\": 3, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC4\"},"
                  "{\"bufferView\": 4, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}]}",
                  blen, buf64);
    write_bytes("quads.gltf", j, (size_t)n);
    free(j);
    free(png64);
    free(buf64);
    return in_dir("quads.gltf");
}

/* ------------------------------------------------------------------ scenes */

typedef struct stage {
    limen_scene *s;
    limen_node cam, lamp, mesh;
} stage;

static bool stage_make(stage *st, const char *file, const float eye[3], const float at[3])
{
    memset(st, 0, sizeof *st);
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &st->s));
    if (!st->s)
        return false;
    CHECK_OK(limen_node_create(st->s, LIMEN_NODE_CAMERA, "eye", &st->cam));
    CHECK_OK(limen_node_create(st->s, LIMEN_NODE_LIGHT, "lamp", &st->lamp));
    CHECK_OK(limen_node_create(st->s, LIMEN_NODE_MESH, "model", &st->mesh));
    CHECK_OK(limen_scene_set_camera(st->s, st->cam));
    CHECK_OK(limen_node_look_at(st->s, st->cam, eye, at, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_camera_set_lens(st->s, st->cam, 0.9f, 0.1f, 1000));
    CHECK_OK(limen_node_set_position(st->s, st->lamp, (float[3]){ eye[0] + 1, eye[1] + 2, eye[2] }));
    CHECK_OK(limen_scene_set_ambient(st->s, 0.3f));
    limen_status rc = limen_mesh_load(st->s, st->mesh, file);
    CHECK_MSG(rc == LIMEN_OK, "%s", limen_scene_error(st->s));
    return rc == LIMEN_OK;
}

/* The share of pixels off the truth by more than 8/255, for method m; writes the frame. */
static double off_truth(limen_scene *s, int w, int h, int m, const unsigned char *truth,
                        const char *png)
{
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r));
    if (!r)
        return 1;
    unsigned char *rgb = malloc((size_t)w * h * 3);
    limen_diff d = { 1, 0, 0, 0 };
    limen_status rc = limen_render_frame(r, s, &(limen_render_opts){ .method = m }, NULL);
    CHECK_MSG(rc == LIMEN_OK, "render: %s", limen_renderer_error(r));
    if (!rc && !limen_renderer_read_rgb(r, rgb)) {
        limen_image_diff(rgb, truth, w, h, 8, &d, NULL);
        if (png)
            limen_write_png(png, w, h, rgb);
    }
    free(rgb);
    limen_renderer_destroy(r);
    return d.bad_share;
}

/* Both methods within the bound of the trace. */
static void held_to_truth(limen_scene *s, const char *what)
{
    const int w = 320, h = 240;
    unsigned char *truth = malloc((size_t)w * h * 3);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = w, .height = h }, truth));
    char png[300];
    snprintf(png, sizeof png, "%s/%s_truth.png", dir, what);
    limen_write_png(png, w, h, truth);
    for (int m = 0; m < 2; m++) {
        snprintf(png, sizeof png, "%s/%s_%s.png", dir, what, m ? "texture" : "stencil");
        double d = off_truth(s, w, h, m, truth, png);
        printf("     %s, %s: %.3f%% of pixels off\n", what, m ? "texture" : "stencil", 100 * d);
        CHECK_MSG(d <= BOUND, "%s: %.3f%% of pixels off", what, 100 * d);
    }
    free(truth);
}

static void colour_at(limen_scene *s, float x, float y, float out[3])
{
    limen_hit h;
    memset(out, 0, sizeof(float) * 3);
    CHECK_OK(limen_ray_cast(s, (float[3]){ x, y, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    memcpy(out, h.color, sizeof h.color);
}

static const limen_drawable *mesh_item(limen_drawables *d, limen_scene *s, limen_node n)
{
    CHECK_OK(limen_drawables_build(d, s));
    const limen_drawable *items;
    limen_drawables_items(d, &items);
    int i = limen_drawables_find(d, n);
    CHECK(i >= 0);
    return i >= 0 ? &items[i] : NULL;
}

/* ------------------------------------------------------------------ tests */

/* The glTF's materials as read: names, factors, alpha modes, textures found or not, and the
 * warnings for the misplaced and missing ones. */
static void test_gltf_materials(void)
{
    const char *path = write_gltf();
    stage st;
    if (!stage_make(&st, path, (float[3]){ 0, 0, 4.5f }, (float[3]){ 0, 0, 0 }))
        return;
    limen_scene *s = st.s;
    int nw = limen_scene_warning_count(s);
    CHECK_MSG(nw == 3, "%d warnings", nw);
    bool abs = false, up = false, missing = false;
    for (int i = 0; i < nw; i++) {
        const char *w = limen_scene_warning(s, i);
        CHECK_MSG(strncmp(w, path, strlen(path)) == 0 && strstr(w, ": warning: "), "%s", w);
        abs = abs || (strstr(w, "D:/projects/textures/BESIDE.PNG") && strstr(w, "absolute"));
        up = up || (strstr(w, "../../../3DS/beside.png") && strstr(w, "outside"));
        missing = missing || (strstr(w, "nothere.png") && strstr(w, "not found"));
    }
    CHECK(abs && up && missing);
    limen_drawables *d;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = mesh_item(d, s, st.mesh);
    if (it && it->mesh) {
        const limen_mesh_geometry *g = it->mesh;
        CHECK(g->part_count == 8 && g->material_count == 8 && g->has_blend && g->colors);
        const char *names[8] = { "factor", "embedded", "mask", "absolute", "uptree", "missing",
                                 "glass", "glow" };
        int tri = 0;
        for (int p = 0; p < g->part_count && g->part_count == 8; p++) {
            const limen_material *m = &g->materials[g->parts[p].material];
            CHECK_MSG(strcmp(m->name, names[p]) == 0, "part %d: %s", p, m->name);
            CHECK(g->parts[p].first_triangle == tri && g->parts[p].triangle_count == 2);
            tri += g->parts[p].triangle_count;
            bool textured = p >= 1 && p <= 4;
            CHECK_MSG(!m->base_texture == !textured, "part %d texture", p);
        }
        if (g->material_count == 8) {
            CHECK(g->materials[2].alpha_mode == LIMEN_ALPHA_MASK);
            CHECK_NEAR(g->materials[2].alpha_cutoff, 0.5, 1e-6);
            CHECK(g->materials[2].base_texture && g->materials[2].base_texture->alpha);
            CHECK(g->materials[6].alpha_mode == LIMEN_ALPHA_BLEND);
            CHECK_NEAR(g->materials[6].base_color[3], 0.5, 1e-6);
            CHECK_NEAR(g->materials[7].emissive[0], 0.3, 1e-6);
            CHECK_NEAR(g->materials[1].base_transform[0], 2, 1e-6);
            CHECK(g->materials[0].alpha_mode == LIMEN_ALPHA_OPAQUE);
            for (int l = 0; l < g->lod_count; l++) {
                int sum = 0;
                for (int p = 0; p < g->part_count; p++)
                    sum += g->lods[l].parts[p].triangle_count;
                CHECK(sum == g->lods[l].triangle_count);
            }
        }
    }
    limen_drawables_destroy(d);

    /* colours, unlit (ambient 1) */
    CHECK_OK(limen_scene_set_ambient(s, 1));
    float c[3], c2[3];
    colour_at(s, -1.65f, 0.6f, c);     /* factor x the colours' mean across (0.6) */
    CHECK_NEAR(c[0], 0.9 * 0.6, 1e-4);
    CHECK_NEAR(c[1], 0.5 * 0.6, 1e-4);
    CHECK_NEAR(c[2], 0.25 * 0.6, 1e-4);
    /* scaled by 2, the embedded image repeats every half quad */
    colour_at(s, -0.55f - 0.25f, 0.6f - 0.25f, c);
    colour_at(s, -0.55f + 0.25f, 0.6f + 0.25f, c2);
    CHECK_MSG(fabsf(c[0] - c2[0]) < 1e-3 && fabsf(c[1] - c2[1]) < 1e-3 &&
              fabsf(c[2] - c2[2]) < 1e-3, "(%g %g %g) vs (%g %g %g)", c[0], c[1], c[2],
              c2[0], c2[1], c2[2]);
    /* the mask: the clear left half lets the ray through to the background */
    limen_hit h;
    CHECK_OK(limen_ray_cast(s, (float[3]){ 0.55f - 0.35f, 0.6f, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(!h.hit);
    CHECK_OK(limen_ray_cast(s, (float[3]){ 0.55f + 0.35f, 0.6f, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(h.hit);
    /* the missing image: its own colour */
    colour_at(s, -0.55f, -0.6f, c);
    CHECK_NEAR(c[0], 0.3, 1e-4);
    CHECK_NEAR(c[1], 0.6, 1e-4);
    CHECK_NEAR(c[2], 0.9, 1e-4);
    /* the absolute path found beside: its top-right texel (blue) at the top right texel's
     * centre, (0.75, 0.75) */
    colour_at(s, 1.65f + 0.25f, 0.6f + 0.25f, c);
    CHECK_NEAR(c[0], 40 / 255.0, 1e-3);
    CHECK_NEAR(c[1], 90 / 255.0, 1e-3);
    CHECK_NEAR(c[2], 220 / 255.0, 1e-3);
    /* glass over the glowing quad: half of each; the glow adds to its albedo */
    colour_at(s, 0.75f, -0.6f, c);
    CHECK_NEAR(c[0], 0.5 * 0.2 + 0.5 * 0.4, 1e-3);
    CHECK_NEAR(c[1], 0.5 * 0.4 + 0.5 * 0.8, 1e-3);
    CHECK_NEAR(c[2], 0.5 * 1.0 + 0.5 * 0.1, 1e-3);
    colour_at(s, 1.2f, -0.6f, c);
    CHECK_NEAR(c[0], 0.4, 1e-3);
    CHECK_NEAR(c[1], 0.8, 1e-3);
    limen_scene_destroy(s);
}

/* The same file rendered, lit, both methods, against the trace. */
static void test_gltf_truth(void)
{
    const char *path = write_gltf();
    stage st;
    if (!stage_make(&st, path, (float[3]){ 0.4f, 0.3f, 4.5f }, (float[3]){ 0, 0, 0 }))
        return;
    held_to_truth(st.s, "quads");
    limen_scene_destroy(st.s);
}

/* A node's own texture replaces every part's, and the file's are not read: no warnings for
 * the missing and misplaced ones, no textures on the materials. */
static void test_node_texture_first(void)
{
    const char *path = write_gltf();
    limen_scene *s;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "m", &m));
    CHECK_OK(limen_node_set_texture(s, m, in_dir("beside.png")));
    CHECK_OK(limen_mesh_load(s, m, path));
    CHECK_MSG(limen_scene_warning_count(s) == 0, "%s", limen_scene_warning(s, 0));
    limen_drawables *d;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = mesh_item(d, s, m);
    if (it && it->mesh)
        for (int i = 0; i < it->mesh->material_count; i++)
            CHECK(!it->mesh->materials[i].base_texture);
    CHECK(it && it->texture);
    limen_drawables_destroy(d);
    limen_scene_destroy(s);
}

/* The spider: five materials, each part with its own texture (not the first one's
 * everywhere), within the bound of the trace. */
static void test_spider(void)
{
    stage st;
    if (!stage_make(&st, "scenes/data/spider/spider.obj", (float[3]){ 0, 60, 110 },
                    (float[3]){ 0, 5, 0 }))
        return;
    limen_scene *s = st.s;
    CHECK_MSG(limen_scene_warning_count(s) == 0, "%s", limen_scene_warning(s, 0));
    limen_drawables *d;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = mesh_item(d, s, st.mesh);
    if (it && it->mesh) {
        const limen_mesh_geometry *g = it->mesh;
        /* five materials, four used (the MTL's Brusttex is not) */
        CHECK_MSG(g->part_count == 4 && g->material_count == 4, "%d parts", g->part_count);
        for (int i = 0; i < g->material_count; i++)
            for (int k = 0; k < i; k++)
                CHECK(g->materials[i].base_texture && g->materials[k].base_texture &&
                      g->materials[i].base_texture->id != g->materials[k].base_texture->id);
    }
    limen_drawables_destroy(d);
    held_to_truth(s, "spider");
    /* every part in the first part's texture is a different picture */
    const int w = 160, h = 120;
    unsigned char *own = malloc((size_t)w * h * 3), *one = malloc((size_t)w * h * 3);
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = w, .height = h }, own));
    CHECK_OK(limen_node_set_texture(s, st.mesh, "scenes/data/spider/wal67ar_small.jpg"));
    CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = w, .height = h }, one));
    limen_diff df;
    CHECK_OK(limen_image_diff(own, one, w, h, 8, &df, NULL));
    CHECK_MSG(df.bad_share > 0.05, "only %.2f%% differ", 100 * df.bad_share);
    free(own);
    free(one);
    limen_scene_destroy(s);
}

/* The vertex-coloured cube is coloured, not white, and matches the trace. */
static void test_vertex_colours(void)
{
    stage st;
    if (!stage_make(&st, "scenes/data/cube_with_vertexcolors.obj", (float[3]){ 2.2f, 1.9f, 2.6f },
                    (float[3]){ 0.5f, 0.5f, 0.5f }))
        return;
    limen_scene *s = st.s;
    limen_drawables *d;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = mesh_item(d, s, st.mesh);
    CHECK(it && it->mesh && it->mesh->colors);
    limen_drawables_destroy(d);
    CHECK_OK(limen_scene_set_ambient(s, 1));
    limen_hit h;
    /* the face z = 1, at its centre: the mean of its diagonal's corners */
    CHECK_OK(limen_ray_cast(s, (float[3]){ 0.5f, 0.5f, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(h.hit && !(h.color[0] > 0.99f && h.color[1] > 0.99f && h.color[2] > 0.99f));
    CHECK_OK(limen_scene_set_ambient(s, 0.3f));
    held_to_truth(s, "vertex_cube");
    limen_scene_destroy(s);
}

/* limen_mesh_set_triangles takes colours, parts and materials; bad parts are refused. */
static void test_set_triangles(void)
{
    limen_scene *s;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    CHECK_OK(limen_scene_set_ambient(s, 1));
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "m", &m));
    const float pos[] = { -1, -1, 0, 0, -1, 0, 0, 1, 0, -1, 1, 0, 0, -1, 0, 1, -1, 0, 1, 1, 0, 0, 1, 0 };
    const float col[32] = { 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
                            0.5f, 0.5f, 0.5f, 1, 0.5f, 0.5f, 0.5f, 1, 0.5f, 0.5f, 0.5f, 1, 0.5f, 0.5f, 0.5f, 1 };
    const uint32_t idx[] = { 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7 };
    limen_material mats[2] = { { .base_color = { 1, 0, 0, 1 } }, { .base_color = { 0, 1, 0, 1 } } };
    limen_mesh_part parts[2] = { { 0, 2, 1 }, { 2, 2, 0 } };
    limen_mesh_data data = { .positions = pos, .vertex_count = 8, .indices = idx,
                             .triangle_count = 4, .colors = col, .part_count = 2,
                             .parts = parts, .material_count = 2, .materials = mats };
    CHECK_OK(limen_mesh_set_triangles(s, m, &data));
    float c[3];
    colour_at(s, -0.5f, 0, c);      /* part 0: material 1, green, white corners */
    CHECK_NEAR(c[0], 0, 1e-5);
    CHECK_NEAR(c[1], 1, 1e-5);
    colour_at(s, 0.5f, 0, c);       /* part 1: red at half */
    CHECK_NEAR(c[0], 0.5, 1e-5);
    CHECK_NEAR(c[1], 0, 1e-5);
    limen_mesh_part gap[2] = { { 0, 1, 0 }, { 2, 2, 0 } };
    data.parts = gap;
    CHECK(limen_mesh_set_triangles(s, m, &data) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "part 1"));
    limen_mesh_part bad[2] = { { 0, 2, 0 }, { 2, 2, 5 } };
    data.parts = bad;
    CHECK(limen_mesh_set_triangles(s, m, &data) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

/* A PLY stored as triangle strips loads whole (a restart, and every other triangle turned),
 * in ASCII and in binary, with its vertex colours. */
static void test_ply_strips(void)
{
    const char *ascii =
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n0 1 0 255 0 0\n1 0 0 255 0 0\n1 1 0 255 0 0\n2 0 0 0 0 255\n"
        "2 1 0 0 0 255\n3 0 0 0 0 255\n3 1 0 0 0 255\n"
        "9 0 1 2 3 -1 4 5 6 7\n";
    write_bytes("strips.ply", ascii, strlen(ascii));
    /* the same in binary, little endian */
    const char *head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
        "property uchar blue\nelement tristrips 1\nproperty list int int vertex_indices\n"
        "end_header\n";
    unsigned char bin[1024];
    size_t n = strlen(head);
    memcpy(bin, head, n);
    for (int v = 0; v < 8; v++) {
        float p[3] = { (float)(v / 2), (float)(v % 2), 0 };
        memcpy(bin + n, p, 12);
        n += 12;
        unsigned char c[3] = { v < 4 ? 255 : 0, 0, v < 4 ? 0 : 255 };
        memcpy(bin + n, c, 3);
        n += 3;
    }
    int list[10] = { 9, 0, 1, 2, 3, -1, 4, 5, 6, 7 };
    memcpy(bin + n, list, sizeof list);
    n += sizeof list;
    write_bytes("strips_bin.ply", bin, n);
    const char *files[2] = { "strips.ply", "strips_bin.ply" };
    for (int f = 0; f < 2; f++) {
        limen_scene *s;
        CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
        CHECK_OK(limen_scene_set_ambient(s, 1));
        limen_node m;
        CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "m", &m));
        limen_status st = limen_mesh_load(s, m, in_dir(files[f]));
        CHECK_MSG(st == LIMEN_OK, "%s: %s", files[f], limen_scene_error(s));
        limen_mesh_info mi;
        CHECK_OK(limen_mesh_get(s, m, &mi));
        CHECK_MSG(mi.triangle_count == 4, "%s: %d triangles", files[f], mi.triangle_count);
        /* hits along the strip's length, red then blue */
        float c[3];
        colour_at(s, 0.25f, 0.5f, c);
        CHECK(c[0] > 0.99f && c[2] < 0.01f);
        colour_at(s, 0.75f, 0.6f, c);
        CHECK(c[0] > 0.99f);
        colour_at(s, 2.75f, 0.4f, c);
        CHECK(c[2] > 0.99f && c[0] < 0.01f);
        /* the gap the restart leaves: no triangle between x = 1 and 2 */
        limen_hit h;
        CHECK_OK(limen_ray_cast(s, (float[3]){ 1.5f, 0.5f, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
        CHECK(!h.hit);
        limen_scene_destroy(s);
    }
}

/* An MTL's map_Kd -s and -o (which assimp reads and drops): uv' = uv x s + o, applied to the
 * mesh's texture coordinates and listed in the material; other options are passed over. */
static void test_mtl_options(void)
{
    const unsigned char texel[4] = { 200, 40, 40, 255 };
    write_tga("tile.tga", 1, 1, texel);
    const char *mtl = "newmtl plain\nKd 1 1 1\nmap_Kd tile.tga\n"
                      "newmtl moved\nKd 1 1 1\nmap_Kd -clamp off -s 2 3 1 -o 0.25 0.5 0 "
                      "-bm 1.5 tile.tga\n";
    write_bytes("opts.mtl", mtl, strlen(mtl));
    const char *obj = "mtllib opts.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                      "usemtl plain\nf 1/1 2/2 3/3\nusemtl moved\nf 1/1 3/3 4/4\n";
    write_bytes("opts.obj", obj, strlen(obj));
    stage st;
    if (!stage_make(&st, in_dir("opts.obj"), (float[3]){ 0.5f, 0.5f, 3 },
                    (float[3]){ 0.5f, 0.5f, 0 }))
        return;
    limen_drawables *d;
    CHECK_OK(limen_drawables_create(&d));
    const limen_drawable *it = mesh_item(d, st.s, st.mesh);
    const limen_mesh_geometry *g = it ? it->mesh : NULL;
    CHECK(g && g->material_count == 2 && g->uvs);
    for (int k = 0; g && g->uvs && k < g->material_count; k++) {
        const limen_material *m = &g->materials[k];
        bool moved = strcmp(m->name, "moved") == 0;
        const float want[6] = { moved ? 2 : 1, 0, 0, moved ? 3 : 1, moved ? 0.25f : 0,
                                moved ? 0.5f : 0 };
        CHECK_MSG(memcmp(m->base_transform, want, sizeof want) == 0,
                  "%s: %g %g %g %g %g %g", m->name, m->base_transform[0],
                  m->base_transform[1], m->base_transform[2], m->base_transform[3],
                  m->base_transform[4], m->base_transform[5]);
        /* the part's corners carry it: (1, 1) becomes (2.25, 3.5) in the moved part */
        const limen_mesh_part *pt = NULL;
        for (int q = 0; q < g->part_count; q++)
            if (g->parts[q].material == k)
                pt = &g->parts[q];
        bool seen = false;
        for (int c = 0; pt && c < 3; c++) {
            const float *uv = &g->uvs[g->indices[pt->first_triangle * 3 + c] * 2];
            const float *pos = &g->positions[g->indices[pt->first_triangle * 3 + c] * 3];
            if (pos[0] == 1 && pos[1] == 1)
                seen = uv[0] == (moved ? 2.25f : 1) && uv[1] == (moved ? 3.5f : 1);
        }
        CHECK_MSG(seen, "%s: the corner at (1, 1) has no uv as the options say", m->name);
    }
    limen_drawables_destroy(d);
    limen_scene_destroy(st.s);
}

static const check_case cases[] = {
    { "gltf_materials", test_gltf_materials },
    { "gltf_truth", test_gltf_truth },
    { "node_texture_first", test_node_texture_first },
    { "spider", test_spider },
    { "vertex_colours", test_vertex_colours },
    { "set_triangles", test_set_triangles },
    { "ply_strips", test_ply_strips },
    { "mtl_options", test_mtl_options },
    { 0 },
};

int main(int argc, char **argv)
{
    snprintf(dir, sizeof dir, "/tmp/limen_materials_XXXXXX");
    if (!mkdtemp(dir))
        return 1;
    int rc = check_run(argc, argv, cases);
    if (!getenv("LIMEN_KEEP"))
        for (const char *const *f = (const char *const[]){ "embed.png", "cutout.tga", "beside.png",
                                                           "quads.gltf", "quads_truth.png",
                                                           "quads_stencil.png", "quads_texture.png",
                                                           "spider_truth.png", "spider_stencil.png",
                                                           "spider_texture.png", "vertex_cube_truth.png",
                                                           "vertex_cube_stencil.png",
                                                           "vertex_cube_texture.png", "strips.ply",
                                                           "strips_bin.ply", NULL };
             *f; f++)
            unlink(in_dir(*f));
    if (!getenv("LIMEN_KEEP"))
        rmdir(dir);
    return rc;
}
