/* test_mesh.c - mesh nodes: triangles from arrays and from files (OBJ, PLY, glTF written
 * here, and the bunny in scenes/data), sharing, bad input, and the ray caster on them.
 * No GL. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

#include "bumpy.h"
#include "check.h"
#include "ray.h"
#include "core/mesh.h"
#include "core/texture.h"
#include "limen.h"

static char dir[64];

static limen_scene *new_scene(void)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    return s;
}

/* Writes text into dir/name; returns the path (static buffer, one at a time). */
static const char *write_file(const char *name, const char *text, size_t len)
{
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (f) {
        fwrite(text, 1, len, f);
        fclose(f);
    }
    return path;
}

static const char *write_text(const char *name, const char *text)
{
    return write_file(name, text, strlen(text));
}

/* A 2x2 image: top row red, green; bottom row blue, white. */
static const char *write_tex(const char *name)
{
    static const unsigned char px[12] = { 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255 };
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    CHECK_OK(limen_write_png(path, 2, 2, px));
    return path;
}

static limen_node new_mesh(limen_scene *s, const char *name)
{
    limen_node m = { 0 };
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, name, &m));
    return m;
}

/* A unit square on z = 0 from (0,0) to (1,1), two triangles, facing +Z. */
static const float square_pos[] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
static const uint32_t square_idx[] = { 0, 1, 2, 0, 2, 3 };

static void test_arrays(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "sq");
    limen_mesh_info info;
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK(info.triangle_count == 0);
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = square_pos, .vertex_count = 4, .indices = square_idx,
        .triangle_count = 2 }));
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK(info.triangle_count == 2 && info.vertex_count == 4);
    CHECK(!info.has_normals && !info.has_uvs && !info.smooth);
    CHECK(info.lo[0] == 0 && info.hi[0] == 1 && info.hi[1] == 1 && info.hi[2] == 0);
    CHECK(info.bytes > 0 && info.shared_by == 1);
    CHECK_OK(limen_mesh_set_smooth(s, m, 1));
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK(info.smooth == 1);
    /* a box is not a mesh */
    limen_node b;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "b", &b));
    CHECK(limen_mesh_set_smooth(s, b, 1) == LIMEN_ERR_HANDLE);
    CHECK(strstr(limen_scene_error(s), "not a mesh") != NULL);
    limen_scene_destroy(s);
}

static void test_array_errors(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "bad");
    float nan_pos[12];
    memcpy(nan_pos, square_pos, sizeof nan_pos);
    nan_pos[7] = NAN;
    CHECK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = nan_pos, .vertex_count = 4, .indices = square_idx,
        .triangle_count = 2 }) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "vertex 2 has a position that is not finite") != NULL);
    const uint32_t far_idx[] = { 0, 1, 2, 0, 2, 4 };
    CHECK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = square_pos, .vertex_count = 4, .indices = far_idx,
        .triangle_count = 2 }) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "triangle 1 uses vertex 4, out of range") != NULL);
    CHECK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = square_pos, .vertex_count = 4, .indices = square_idx,
        .triangle_count = 0 }) == LIMEN_ERR_ARG);
    CHECK(limen_mesh_set_triangles(s, m, NULL) == LIMEN_ERR_ARG);
    limen_mesh_info info;
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK(info.triangle_count == 0);   /* nothing half-set */
    limen_scene_destroy(s);
}

static const char *obj_square =
    "# a square\n"
    "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3 4/4\n";

static const char *ply_tetra =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

/* One triangle with normals, its buffer inline (base64 of 3 positions, 3 normals, 3 u16). */
static const char *gltf_tri =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
    "\"nodes\":[{\"mesh\":0,\"translation\":[0,0,5]}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},"
    "\"indices\":2}]}],"
    "\"accessors\":["
    "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
    "\"min\":[0,0,0],\"max\":[1,1,0]},"
    "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
    "{\"bufferView\":2,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
    "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36},"
    "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":6}],"
    "\"buffers\":[{\"byteLength\":78,\"uri\":\"data:application/octet-stream;base64,"
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/"
    "AAAAAAAAAAAAAIA/AAABAAIA\"}]}";

static void test_files(void)
{
    limen_scene *s = new_scene();
    limen_mesh_info info;
    limen_node a = new_mesh(s, "obj");
    CHECK_OK(limen_mesh_load(s, a, write_text("square.obj", obj_square)));
    CHECK_OK(limen_mesh_get(s, a, &info));
    CHECK(info.triangle_count == 2 && info.has_uvs && !info.has_normals);
    CHECK(info.hi[0] == 2 && info.hi[1] == 2);
    limen_node b = new_mesh(s, "ply");
    CHECK_OK(limen_mesh_load(s, b, write_text("tetra.ply", ply_tetra)));
    CHECK_OK(limen_mesh_get(s, b, &info));
    CHECK(info.triangle_count == 4 && info.vertex_count == 4);
    limen_node c = new_mesh(s, "gltf");
    CHECK_OK(limen_mesh_load(s, c, write_text("tri.gltf", gltf_tri)));
    CHECK_OK(limen_mesh_get(s, c, &info));
    CHECK(info.triangle_count == 1 && info.has_normals);
    CHECK(info.lo[2] == 5 && info.hi[2] == 5);    /* the file's node transform applied */
    CHECK(info.hi[0] == 1 && info.hi[1] == 1);
    limen_scene_destroy(s);
}

/* A plain PLY (positions and faces) is read by limen's own reader, as the file has it: a
 * quad becomes two triangles (a fan), and a vertex at another's position stays its own
 * (assimp, which read it before, joined the two: 4 vertices). */
static void test_plain_ply(void)
{
    static const char *text =
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n4 0 1 2 3\n3 4 3 2\n";
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "plain");
    limen_mesh_info info;
    CHECK_OK(limen_mesh_load(s, m, write_text("plain.ply", text)));
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK_MSG(info.triangle_count == 3 && info.vertex_count == 5,
              "%d triangles, %d vertices", info.triangle_count, info.vertex_count);
    CHECK(!info.has_normals && !info.has_uvs);
    CHECK(info.lo[0] == 0 && info.hi[0] == 1 && info.hi[1] == 1 && info.hi[2] == 0);
    limen_scene_destroy(s);
}

static void test_bunny(void)
{
    limen_scene *s = new_scene();
    limen_mesh_info a, b;
    limen_node obj = new_mesh(s, "obj"), glb = new_mesh(s, "glb");
    CHECK_OK(limen_mesh_load(s, obj, "scenes/data/bunny.obj"));
    CHECK_OK(limen_mesh_load(s, glb, "scenes/data/bunny.glb"));
    CHECK_OK(limen_mesh_get(s, obj, &a));
    CHECK_OK(limen_mesh_get(s, glb, &b));
    CHECK(a.triangle_count == 3674 && b.triangle_count == 3674);
    CHECK(a.hi[0] - a.lo[0] > 8 && a.hi[0] - a.lo[0] < 12);
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(a.lo[k], b.lo[k], 1e-3);
        CHECK_NEAR(a.hi[k], b.hi[k], 1e-3);
    }
    /* shared: a hundred nodes hold one copy */
    for (int i = 0; i < 100; i++) {
        limen_node m = new_mesh(s, NULL);
        CHECK_OK(limen_mesh_load(s, m, "scenes/data/bunny.obj"));
    }
    CHECK_OK(limen_mesh_get(s, obj, &a));
    CHECK(a.shared_by == 101);
    CHECK_OK(limen_node_destroy(s, obj));
    CHECK_OK(limen_mesh_get(s, glb, &b));
    CHECK(b.shared_by == 1);
    limen_scene_destroy(s);
}

/* Each bad file: refused, the message names the file, the node keeps what it had. */
static void expect_refused(limen_scene *s, limen_node m, const char *path, const char *why)
{
    limen_status st = limen_mesh_load(s, m, path);
    CHECK_MSG(st != LIMEN_OK, "%s: loaded", path);
    const char *msg = limen_scene_error(s);
    CHECK_MSG(strncmp(msg, path, strlen(path)) == 0 && strstr(msg, why) && !strchr(msg, '\n'),
              "%s: message '%s' (wanted '%s')", path, msg, why);
}

static void test_bad_files(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "m");
    char missing[96];
    snprintf(missing, sizeof missing, "%s/missing.obj", dir);
    expect_refused(s, m, missing, "cannot open");
    expect_refused(s, m, write_text("empty.obj", ""), "empty file");
    expect_refused(s, m, dir, "not a regular file");
    expect_refused(s, m, write_text("junk.glb", "glTF\x02\0\0\0 this is not a glb"),
                   "cannot read it as a mesh");
    expect_refused(s, m, write_text("junk.ply", "ply\nformat ascii 1.0\nelement vertex 9\n"),
                   "no end_header");
    expect_refused(s, m, write_text("lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n"),
                   "no triangles in it (points and lines are skipped)");
    /* a model with triangles keeps them; its lines are skipped with a warning */
    int before = limen_scene_warning_count(s);
    CHECK_OK(limen_mesh_load(s, new_mesh(s, "mixed"), write_text("mixed.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                              "f 1 2 3\nl 1 3\n")));
    const char *w = limen_scene_warning(s, limen_scene_warning_count(s) - 1);
    CHECK_MSG(limen_scene_warning_count(s) == before + 1 && w && strstr(w, "mixed.obj") &&
                  strstr(w, "skipped"), "warning '%s'", w ? w : "(none)");
    expect_refused(s, m, write_text("far.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n"),
                   "vertex index out of range");
    expect_refused(s, m, write_text("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 1 1 0\nf 1 2 3\n"),
                   "vertex 1 has a position that is not finite");
    expect_refused(s, m, write_text("nan.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"), "vertex 1 has a position that is not finite");
    /* a header that promises ten million triangles and holds none */
    expect_refused(s, m, write_text("huge.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 30000000\nproperty float x\n"
        "property float y\nproperty float z\nelement face 10000000\n"
        "property list uchar int vertex_indices\nend_header\n"),
                   "declares more elements than the file has bytes");
    limen_mesh_info info;
    CHECK_OK(limen_mesh_get(s, m, &info));
    CHECK(info.triangle_count == 0);
    limen_scene_destroy(s);
}


/* A box of 12 triangles, [-0.5, 0.5]^3, counter-clockwise from outside. */
static void box_mesh(limen_scene *s, limen_node m)
{
    static const float p[] = { -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f,
                               -0.5f, 0.5f, -0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f, 0.5f,
                               0.5f, 0.5f, 0.5f, -0.5f, 0.5f, 0.5f };
    static const uint32_t ix[] = { 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                   3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5 };
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = p, .vertex_count = 8, .indices = ix, .triangle_count = 12 }));
}

static void test_ray_cast(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "sq");
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = square_pos, .vertex_count = 4, .indices = square_idx,
        .triangle_count = 2 }));
    CHECK_OK(limen_node_set_position(s, m, (float[3]){ 0, 0, -3 }));
    CHECK_OK(limen_node_set_scale(s, m, (float[3]){ 2, 2, 2 }));
    limen_hit h;
    CHECK_OK(limen_ray_cast(s, (float[3]){ 1, 1, 0 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(h.hit && h.node.id == m.id);
    CHECK_NEAR(h.distance, 3, 1e-5);
    CHECK_NEAR(h.normal[2], 1, 1e-6);
    /* from behind: both sides are there, the normal turned toward the ray */
    CHECK_OK(limen_ray_cast(s, (float[3]){ 1, 1, -5 }, (float[3]){ 0, 0, 1 }, NULL, &h));
    CHECK(h.hit && h.node.id == m.id);
    CHECK_NEAR(h.point[2], -3, 1e-5);
    CHECK_NEAR(h.normal[2], -1, 1e-6);
    /* beside it (the square spans 0..2 after scaling) */
    CHECK_OK(limen_ray_cast(s, (float[3]){ 2.1f, 1, 0 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(!h.hit);
    /* hidden: not there */
    CHECK_OK(limen_node_set_visible(s, m, 0));
    CHECK_OK(limen_ray_cast(s, (float[3]){ 1, 1, 0 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(!h.hit);
    limen_scene_destroy(s);
}

/* Normals from the file are interpolated; smooth = 1 interpolates computed ones. */
static void test_normals(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "tent");
    /* two triangles folded along x = 0 like a roof, seen from above */
    static const float p[] = { -1, 0, -1, 0, 1, -1, 0, 1, 1, -1, 0, 1, 1, 0, -1, 1, 0, 1 };
    static const uint32_t ix[] = { 0, 3, 2, 0, 2, 1, 4, 1, 2, 4, 2, 5 };
    CHECK_OK(limen_mesh_set_triangles(s, m, &(limen_mesh_data){
        .positions = p, .vertex_count = 6, .indices = ix, .triangle_count = 4 }));
    limen_hit h;
    /* flat: the left slope's normal (-1, 1, 0)/sqrt 2 just left of the ridge */
    CHECK_OK(limen_ray_cast(s, (float[3]){ -0.01f, 5, 0.2f }, (float[3]){ 0, -1, 0 }, NULL, &h));
    CHECK(h.hit);
    CHECK_NEAR(h.normal[0], -sqrt(0.5), 1e-5);
    CHECK_NEAR(h.normal[1], sqrt(0.5), 1e-5);
    /* smooth: at the ridge the vertex normal is straight up, and near it almost so */
    CHECK_OK(limen_mesh_set_smooth(s, m, 1));
    CHECK_OK(limen_ray_cast(s, (float[3]){ -0.01f, 5, 0.2f }, (float[3]){ 0, -1, 0 }, NULL, &h));
    CHECK(h.hit && h.normal[1] > 0.999f);
    limen_scene_destroy(s);
}

/* The tracer's picture of a box made of triangles is the picture of the box shape. */
static void test_trace_box(void)
{
    unsigned char *img[2];
    for (int k = 0; k < 2; k++) {
        limen_scene *s = new_scene();
        limen_node b, cam, light;
        CHECK_OK(limen_node_create(s, k ? LIMEN_NODE_MESH : LIMEN_NODE_BOX, "b", &b));
        if (k)
            box_mesh(s, b);
        CHECK_OK(limen_node_set_rotation(s, b, (float[3]){ 0.4f, 0.7f, 0.1f }));
        CHECK_OK(limen_node_set_scale(s, b, (float[3]){ 1.5f, 1, 2 }));
        CHECK_OK(limen_node_set_color(s, b, (float[3]){ 0.9f, 0.5f, 0.2f }));
        CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "l", &light));
        CHECK_OK(limen_node_set_position(s, light, (float[3]){ 2, 3, 4 }));
        CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "c", &cam));
        CHECK_OK(limen_node_look_at(s, cam, (float[3]){ 1, 1.5f, 4 }, (float[3]){ 0, 0, 0 },
                                    NULL));
        CHECK_OK(limen_scene_set_camera(s, cam));
        img[k] = malloc(160 * 120 * 3);
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = 160, .height = 120 },
                                   img[k]));
        limen_scene_destroy(s);
    }
    limen_diff d;
    CHECK_OK(limen_image_diff(img[0], img[1], 160, 120, 8, &d, NULL));
    CHECK_MSG(d.bad_pixels <= 2, "%ld pixels differ", d.bad_pixels);
    long lit = 0;
    for (int i = 0; i < 160 * 120 * 3; i++)
        lit += img[1][i] > 0;
    CHECK(lit > 160 * 120 / 10);
    free(img[0]);
    free(img[1]);
}

/* The bunny, traced through its hierarchy, and hit where it stands. */
static void test_bunny_cast(void)
{
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "bunny");
    CHECK_OK(limen_mesh_load(s, m, "scenes/data/bunny.glb"));
    limen_mesh_info info;
    CHECK_OK(limen_mesh_get(s, m, &info));
    float c[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5f * (info.lo[k] + info.hi[k]);
    CHECK_OK(limen_node_set_position(s, m, (float[3]){ 10, 0, 0 }));
    limen_hit h;
    CHECK_OK(limen_ray_cast(s, (float[3]){ 10 + c[0], c[1], 50 }, (float[3]){ 0, 0, -1 }, NULL,
                            &h));
    CHECK(h.hit && h.node.id == m.id);
    CHECK(h.point[2] < info.hi[2] + 1e-4f && h.point[2] > c[2]);
    CHECK_OK(limen_ray_cast(s, (float[3]){ c[0], c[1], 50 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(!h.hit);
    limen_scene_destroy(s);
}


/* Writes a script into dir and loads it; returns the status, the message in msg. */
static limen_status run_script(const char *name, const char *text, int trusted, int64_t cap,
                               char *msg, size_t size, int *nodes)
{
    char path[128];
    snprintf(path, sizeof path, "%s", write_text(name, text));
    limen_script *sc = NULL;
    limen_status st = limen_script_load(path, &(limen_script_desc){ .trusted = trusted,
                                                                     .memory_cap = cap }, &sc);
    snprintf(msg, size, "%s", sc ? limen_script_error(sc) : "");
    if (nodes)
        *nodes = st ? 0 : limen_scene_node_count(limen_script_scene(sc));
    limen_script_destroy(sc);
    return st;
}

static void test_script(void)
{
    char msg[512], want[256];
    int nodes;
    write_text("square.obj", obj_square);
    CHECK_OK(run_script("ok.lua",
        "local limen = require 'limen' local s = limen.scene{}\n"
        "local a = s:mesh{ file = 'square.obj', pos = {1, 0, 0}, color = {1, 0, 0} }\n"
        "local b = s:mesh{ file = 'square.obj', smooth = true }\n"
        "assert(a.kind == 'mesh' and b.smooth == true and a.smooth == false)\n"
        "b.smooth = false\n"
        "assert(not b.smooth)\n"
        "return s\n", 0, 0, msg, sizeof msg, &nodes));
    CHECK_MSG(nodes == 2, "%d nodes: %s", nodes, msg);
    /* errors name the script line and the mesh file */
    CHECK(run_script("missing.lua", "local limen = require 'limen' local s = limen.scene{}\n\ns:mesh{ file = 'nope.obj' }\n"
                     "return s\n", 0, 0, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    snprintf(want, sizeof want, "%s/missing.lua:3: mesh: %s/nope.obj: cannot open", dir, dir);
    CHECK_MSG(strncmp(msg, want, strlen(want)) == 0, "%s", msg);
    CHECK(run_script("nofile.lua", "local limen = require 'limen' local s = limen.scene{}\ns:mesh{ pos = {0, 0, 0} }\n",
                     0, 0, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "nofile.lua:2: mesh: field 'file' is required"), "%s", msg);
    CHECK(run_script("typo.lua", "local limen = require 'limen' local s = limen.scene{}\ns:mesh{ file = 'square.obj', "
                     "smoth = true }\n", 0, 0, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "typo.lua:2: mesh: unknown field 'smoth'"), "%s", msg);
    write_tex("t.png");
    CHECK_OK(run_script("tex.lua", "local limen = require 'limen' local s = limen.scene{}\n"
                        "s:plane{ texture = 't.png' } s:box{ texture = 't.png' }\n"
                        "s:mesh{ file = 'square.obj', texture = 't.png' }\nreturn s\n",
                        0, 0, msg, sizeof msg, &nodes));
    CHECK_MSG(nodes == 3, "%s", msg);
    CHECK(run_script("notex.lua", "local limen = require 'limen' local s = limen.scene{}\n"
                     "s:plane{ texture = 'none.png' }\n", 0, 0, msg, sizeof msg, NULL) ==
          LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "notex.lua:2: plane: ") && strstr(msg, "/none.png: cannot open"),
              "%s", msg);
    CHECK(run_script("sphtex.lua", "local limen = require 'limen' local s = limen.scene{}\n"
                     "s:sphere{ texture = 't.png' }\n", 0, 0, msg, sizeof msg, NULL) ==
          LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "sphtex.lua:2: sphere: field 'texture' does not apply to a sphere"),
              "%s", msg);
    CHECK(run_script("bad.lua", "local limen = require 'limen' local s = limen.scene{}\ns:mesh{ file = 'junk.ply' }\n",
                     0, 0, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "bad.lua:2: mesh: ") && strstr(msg, "/junk.ply: "), "%s", msg);
}

static void test_script_safety(void)
{
    char msg[512];
    write_text("square.obj", obj_square);
    char link[160], target[160], up[96];
    snprintf(link, sizeof link, "%s/out.obj", dir);
    snprintf(target, sizeof target, "%s.obj", dir);     /* beside the folder */
    snprintf(up, sizeof up, "..%s", strrchr(target, '/'));
    const char *escapes[] = { "/etc/passwd", up, "sub/../../x.obj", "out.obj" };
    FILE *f = fopen(target, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(obj_square, f);
        fclose(f);
    }
    CHECK(symlink(target, link) == 0);
    for (int i = 0; i < 4; i++) {
        char text[256];
        snprintf(text, sizeof text, "local limen = require 'limen' local s = limen.scene{}\ns:mesh{ file = '%s' }\nreturn s\n",
                 escapes[i]);
        CHECK(run_script("escape.lua", text, 0, 0, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
        CHECK_MSG(strstr(msg, "escape.lua:2: mesh: ") &&
                  strstr(msg, "a safe script reads files only under its own folder"),
                  "%s: %s", escapes[i], msg);
        /* a trusted script may */
        limen_status st = run_script("escape.lua", text, 1, 0, msg, sizeof msg, NULL);
        CHECK_MSG(i == 0 || i == 2 ? st != LIMEN_OK && !strstr(msg, "safe script")
                                   : st == LIMEN_OK, "%s: %s", escapes[i], msg);
    }
    remove(target);
}

/* Mesh memory counts against the script's cap: a mesh too big for it is refused before it
 * is read, and the same file loaded twice counts once. */
static void test_script_memory(void)
{
    /* a binary PLY of 200,000 triangles: 2.4 MB of vertices, 2.6 MB of faces */
    int nt = 200000, nv = nt + 2;
    char path[128];
    snprintf(path, sizeof path, "%s/big.ply", dir);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f)
        return;
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n", nv, nt);
    for (int i = 0; i < nv; i++) {
        float v[3] = { (float)(i / 2), (float)(i % 2), 0 };
        fwrite(v, sizeof v, 1, f);
    }
    for (int i = 0; i < nt; i++) {
        unsigned char three = 3;
        int ix[3] = { i, i + 1, i + 2 };
        fwrite(&three, 1, 1, f);
        fwrite(ix, sizeof ix, 1, f);
    }
    fclose(f);
    char msg[512];
    const char *text = "local limen = require 'limen' local s = limen.scene{}\nfor i = 1, 3 do s:mesh{ file = 'big.ply' } end\n"
                       "return s\n";
    CHECK(run_script("big.lua", text, 0, 12 << 20, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "big.lua:2: mesh: ") && strstr(msg, "big.ply: 200000 triangles need"),
              "%s", msg);
    /* a small cap refuses the file before it is read */
    CHECK(run_script("big.lua", text, 0, 3 << 20, msg, sizeof msg, NULL) == LIMEN_ERR_SCRIPT);
    CHECK_MSG(strstr(msg, "big.ply: a file of 4.8 MiB"), "%s", msg);
    int nodes;
    CHECK_OK(run_script("big.lua", text, 0, 64 << 20, msg, sizeof msg, &nodes));
    CHECK_MSG(nodes == 3, "%s", msg);
}


/* A light's range: full at its source, (1 - (d/R)^4)^2 between, nothing from R on; the
 * same in the tracer and (test_truth's mesh scenes) the renderer. */
static void test_light_range(void)
{
    limen_scene *s = new_scene();
    CHECK_OK(limen_scene_set_ambient(s, 0));
    limen_node q, l;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "floor", &q));
    CHECK_OK(limen_node_set_dims(s, q, (float[3]){ 100, 100, 0 }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "lamp", &l));
    CHECK_OK(limen_node_set_position(s, l, (float[3]){ 0, 0, 1 }));
    CHECK(limen_light_set_range(s, q, 3) == LIMEN_ERR_HANDLE);
    CHECK(limen_light_set_range(s, l, -1) == LIMEN_ERR_ARG);
    CHECK(limen_light_set_range(s, l, NAN) == LIMEN_ERR_ARG);
    CHECK_OK(limen_light_set_range(s, l, 2));
    CHECK(limen_light_get_range(s, l) == 2);
    for (int i = 0; i < 4; i++) {
        float x = (float[]){ 0, 1, 1.5f, 2 }[i];   /* d = sqrt(1 + x^2) */
        limen_hit h;
        CHECK_OK(limen_ray_cast(s, (float[3]){ x, 0, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
        double d2 = 1.0 + x * x, q4 = d2 * d2 / 16.0, w = q4 < 1 ? (1 - q4) * (1 - q4) : 0;
        double want = w / sqrt(d2);     /* times n.l */
        CHECK_NEAR(h.color[0], want, 1e-5);
    }
    limen_scene_destroy(s);
}


/* Colour seen straight down -Z at (x, y) with ambient 1: the albedo itself. */
static void albedo_at(limen_scene *s, float x, float y, float out[3])
{
    limen_hit h;
    CHECK_OK(limen_ray_cast(s, (float[3]){ x, y, 5 }, (float[3]){ 0, 0, -1 }, NULL, &h));
    CHECK(h.hit);
    memcpy(out, h.color, sizeof h.color);
}

/* Bilinear, repeating, texel centres at (i + 0.5) / w, v up from the bottom row. */
static void test_texture_sampling(void)
{
    limen_scene *s = new_scene();
    CHECK_OK(limen_scene_set_ambient(s, 1));
    limen_node q;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "q", &q));
    CHECK_OK(limen_node_set_dims(s, q, (float[3]){ 2, 2, 0 }));   /* u = x/2 + 0.5 */
    CHECK_OK(limen_node_set_color(s, q, (float[3]){ 1, 1, 0.5f }));
    CHECK_OK(limen_node_set_texture(s, q, write_tex("t.png")));
    float c[3];
    albedo_at(s, -0.5f, -0.5f, c);      /* (0.25, 0.25): the bottom-left texel's centre */
    CHECK_NEAR(c[0], 0, 1e-6);
    CHECK_NEAR(c[2], 0.5, 1e-6);        /* blue times the colour's 0.5 */
    albedo_at(s, 0.0f, 0.5f, c);        /* (0.5, 0.75): half red, half green */
    CHECK_NEAR(c[0], 0.5, 1e-6);
    CHECK_NEAR(c[1], 0.5, 1e-6);
    CHECK_NEAR(c[2], 0, 1e-6);
    albedo_at(s, -0.999f, 0.5f, c);     /* u near 0 wraps: mostly green, some red */
    CHECK(c[1] > 0.45f && c[1] < 0.55f && c[0] > 0.45f);
    albedo_at(s, 0.5f, 0.0f, c);        /* (0.75, 0.5): between green and white */
    CHECK_NEAR(c[0], 0.5, 1e-6);
    CHECK_NEAR(c[1], 1, 1e-6);
    CHECK_NEAR(c[2], 0.25, 1e-6);
    /* a mirror takes no texture; a missing file is named */
    limen_node m;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, "m", &m));
    CHECK(limen_node_set_texture(s, m, write_tex("t.png")) == LIMEN_ERR_HANDLE);
    CHECK(limen_node_set_texture(s, q, "/nonexistent/x.png") == LIMEN_ERR_IO);
    CHECK(strstr(limen_scene_error(s), "/nonexistent/x.png: cannot open") != NULL);
    CHECK(limen_node_set_texture(s, q, write_text("bad.png", "not a png")) == LIMEN_ERR_IO);
    CHECK(strstr(limen_scene_error(s), "bad.png: cannot read it as an image") != NULL);
    CHECK_OK(limen_node_set_texture(s, q, NULL));
    albedo_at(s, -0.5f, -0.5f, c);
    CHECK_NEAR(c[2], 0.5, 1e-6);
    CHECK_NEAR(c[0], 1, 1e-6);
    limen_scene_destroy(s);
}

/* Tiling: the coordinates are scaled before sampling, by any positive amount. */
static void test_texture_repeat(void)
{
    limen_scene *s = new_scene();
    CHECK_OK(limen_scene_set_ambient(s, 1));
    limen_node q;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "q", &q));
    CHECK_OK(limen_node_set_dims(s, q, (float[3]){ 2, 2, 0 }));
    CHECK_OK(limen_node_set_texture(s, q, write_tex("t.png")));
    float rep[2] = { 0, 0 }, c[3];
    CHECK_OK(limen_node_get_texture_repeat(s, q, rep));
    CHECK(rep[0] == 1 && rep[1] == 1);
    CHECK_OK(limen_node_set_texture_repeat(s, q, (float[2]){ 2.5f, 1 }));
    CHECK_OK(limen_node_get_texture_repeat(s, q, rep));
    CHECK(rep[0] == 2.5f && rep[1] == 1);
    /* (0.25, 0.25) becomes (0.625, 0.25): a quarter of the blue texel, three of the white */
    albedo_at(s, -0.5f, -0.5f, c);
    CHECK_NEAR(c[0], 0.75, 1e-6);
    CHECK_NEAR(c[2], 1, 1e-6);
    /* (0.75, 0.75) becomes (1.875, 0.75), which wraps to (0.875, 0.75): a quarter red */
    albedo_at(s, 0.5f, 0.5f, c);
    CHECK_NEAR(c[0], 0.25, 1e-6);
    CHECK_NEAR(c[1], 0.75, 1e-6);
    CHECK(limen_node_set_texture_repeat(s, q, (float[2]){ 0, 1 }) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "texture repeat") != NULL);
    CHECK(limen_node_set_texture_repeat(s, q, (float[2]){ 1, NAN }) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_texture_repeat(s, q, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_node_set_texture_repeat(s, (limen_node){ 0 }, (float[2]){ 1, 1 }) ==
          LIMEN_ERR_HANDLE);
    CHECK_OK(limen_node_get_texture_repeat(s, q, rep));
    CHECK(rep[0] == 2.5f && rep[1] == 1);       /* refused values leave it as it was */
    limen_scene_destroy(s);
}

/* Mipmap levels (limen_image.levels): halved (rounded down, at least 1) to 1 x 1, each
 * texel the area-weighted average of those above it, so that at an odd size a texel of the
 * level above splits between two below; and the filter's setter, getter and refusals. */
static void test_texture_levels(void)
{
    enum { W = 5, H = 4 };
    unsigned char px[W * H * 3];
    for (int i = 0; i < W * H * 3; i++)
        px[i] = (unsigned char)((i * 37 + i / 3 * 11) % 256);
    char path[128];
    snprintf(path, sizeof path, "%s/odd.png", dir);
    CHECK_OK(limen_write_png(path, W, H, px));
    limen_scene *s = new_scene();
    limen_node q;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "q", &q));
    CHECK_OK(limen_node_set_texture(s, q, path));
    limen_texture_filter f = LIMEN_FILTER_NEAREST;
    CHECK_OK(limen_node_get_texture_filter(s, q, &f));
    CHECK(f == LIMEN_FILTER_TRILINEAR);
    CHECK_OK(limen_node_set_texture_filter(s, q, LIMEN_FILTER_NEAREST));
    CHECK(limen_node_set_texture_filter(s, q, (limen_texture_filter)7) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_scene_error(s), "texture filter: 7") != NULL);
    CHECK(limen_node_set_texture_filter(s, (limen_node){ 0 }, LIMEN_FILTER_LINEAR) ==
          LIMEN_ERR_HANDLE);
    CHECK(limen_node_get_texture_filter(s, q, NULL) == LIMEN_ERR_ARG);
    limen_drawables *d = NULL;
    CHECK_OK(limen_drawables_create(&d));
    CHECK_OK(limen_drawables_build(d, s));
    const limen_drawable *items;
    limen_drawables_items(d, &items);
    const limen_drawable *it = &items[limen_drawables_find(d, q)];
    CHECK(it->texture_filter == LIMEN_FILTER_NEAREST);  /* refused values leave it as it was */
    const limen_image *im = it->texture;
    CHECK(im && im->level_count == 3);
    if (im && im->level_count == 3) {
        CHECK(im->levels[0].rgb == im->rgb && im->levels[0].width == W);
        CHECK(im->levels[1].width == 2 && im->levels[1].height == 2);
        CHECK(im->levels[2].width == 1 && im->levels[2].height == 1);
        /* level 1's texel (1, 0) (top right): columns 2.5 to 5 of rows 0 and 1, the middle
         * column counting half */
        for (int c = 0; c < 3; c++) {
            double sum = 0;
            for (int y = 0; y < 2; y++)
                for (int x = 2; x < 5; x++)
                    sum += (x == 2 ? 0.5 : 1.0) * px[(y * W + x) * 3 + c];
            CHECK(abs(im->levels[1].rgb[3 + c] - (int)lround(sum / 5)) == 0);
        }
        /* level 2: the mean of level 1's bytes */
        for (int c = 0; c < 3; c++) {
            const unsigned char *l1 = im->levels[1].rgb;
            int mean = (int)lround((l1[c] + l1[3 + c] + l1[6 + c] + l1[9 + c]) / 4.0);
            CHECK(im->levels[2].rgb[c] == mean);
        }
    }
    limen_drawables_destroy(d);
    limen_scene_destroy(s);
}

/* An OBJ's map_Kd is used with the file's texture coordinates. */
static void test_mesh_texture(void)
{
    write_tex("t.png");
    write_text("sq.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd t.png\n");
    const char *path = write_text("tsq.obj",
        "mtllib sq.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl paint\nf 1/1 2/2 3/3 4/4\n");
    limen_scene *s = new_scene();
    CHECK_OK(limen_scene_set_ambient(s, 1));
    limen_node m = new_mesh(s, "m");
    CHECK_OK(limen_mesh_load(s, m, path));
    float c[3];
    albedo_at(s, 0.5f, 0.5f, c);        /* (0.75, 0.75): the top-right texel, green */
    CHECK_NEAR(c[0], 0, 1e-6);
    CHECK_NEAR(c[1], 1, 1e-6);
    albedo_at(s, 0.0f, -0.5f, c);       /* (0.5, 0.25): blue and white */
    CHECK_NEAR(c[0], 0.5, 1e-6);
    CHECK_NEAR(c[2], 1, 1e-6);
    /* a missing texture is named with the mesh */
    write_text("gone.mtl", "newmtl paint\nKd 0.5 0.25 1\nmap_Kd nothere.png\n");
    const char *p2 = write_text("gone.obj", "mtllib gone.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\n"
                                "vt 0 0\nvt 1 0\nvt 1 1\nusemtl paint\nf 1/1 2/2 3/3\n");
    CHECK_OK(limen_mesh_load(s, m, p2));       /* kept, untextured, with a warning */
    CHECK(limen_scene_warning_count(s) == 1);
    const char *w = limen_scene_warning(s, 0);
    CHECK_MSG(w && strncmp(w, p2, strlen(p2)) == 0 && strstr(w, ": warning: ") &&
              strstr(w, "nothere.png") && strstr(w, "not found"), "%s", w ? w : "(none)");
    albedo_at(s, 0.5f, -0.5f, c);             /* its own colour, Kd */
    CHECK_NEAR(c[0], 0.5, 1e-6);
    CHECK_NEAR(c[1], 0.25, 1e-6);
    CHECK_NEAR(c[2], 1, 1e-6);
    limen_scene_clear_warnings(s);
    CHECK(limen_scene_warning_count(s) == 0 && !limen_scene_warning(s, 0));
    limen_scene_destroy(s);
}


/* A mesh passing through a portal is cut and cloned like a box; culling and moving use its
 * bounds. */
/* Loading in two threads at once, each into its own scene: every failure names its own
 * file with the reason it has alone (the importer's error is the process's, not the
 * scene's), and every good load succeeds. */
typedef struct loader {
    char bad[128], good[128];
    char expected[512];
    int wrong, failed_good;
} loader;

static void *load_many(void *arg)
{
    loader *l = arg;
    limen_scene *s = new_scene();
    for (int k = 0; k < 1000; k++) {
        limen_node m = new_mesh(s, "m");
        if (limen_mesh_load(s, m, l->bad) == LIMEN_OK ||
            strcmp(limen_scene_error(s), l->expected) != 0)
            l->wrong++;
        /* a good load after every eighth bad one (an OBJ's read takes a 16 MiB buffer:
         * under the sanitizers each is mapped afresh, 35 ms) */
        if (k % 8 == 0 && limen_mesh_load(s, m, l->good) != LIMEN_OK)
            l->failed_good++;
        limen_node_destroy(s, m);
    }
    limen_scene_destroy(s);
    return NULL;
}

static void test_threads(void)
{
    loader l[2] = { 0 };
    snprintf(l[0].bad, sizeof l[0].bad, "%s", write_text("junk1.glb", "glTF\x02\0\0\0 not a glb"));
    snprintf(l[0].good, sizeof l[0].good, "%s", write_text("tetra1.ply", ply_tetra));
    snprintf(l[1].bad, sizeof l[1].bad, "%s",
             write_text("junk2.gltf", "{ \"asset\": { \"version\": 7 } ]"));
    snprintf(l[1].good, sizeof l[1].good, "%s", write_text("square2.obj", obj_square));
    limen_scene *s = new_scene();
    for (int i = 0; i < 2; i++) {
        limen_node m = new_mesh(s, "alone");
        CHECK(limen_mesh_load(s, m, l[i].bad) != LIMEN_OK);
        snprintf(l[i].expected, sizeof l[i].expected, "%s", limen_scene_error(s));
        CHECK_MSG(strstr(l[i].expected, "cannot read it as a mesh"), "%s", l[i].expected);
        printf("     alone: %s\n", l[i].expected);
    }
    CHECK_MSG(strcmp(strchr(l[0].expected, ':'), strchr(l[1].expected, ':')) != 0,
              "the two files should fail for different reasons: %s / %s", l[0].expected,
              l[1].expected);
    limen_scene_destroy(s);
    pthread_t t[2];
    for (int i = 0; i < 2; i++)
        CHECK(pthread_create(&t[i], NULL, load_many, &l[i]) == 0);
    for (int i = 0; i < 2; i++) {
        pthread_join(t[i], NULL);
        CHECK_MSG(!l[i].wrong && !l[i].failed_good, "%s: %d wrong messages, %d good loads failed",
                  l[i].bad, l[i].wrong, l[i].failed_good);
    }
}

/* The nearest hit of the ray o + t d on the triangles, each tested in turn (tests/ray.h:
 * in double, both sides); INFINITY where none. */
static double brute_hit(const float *pos, const uint32_t *idx, int nt, const double o[3],
                        const double d[3])
{
    double best = INFINITY, tt, u, v;
    for (int t = 0; t < nt; t++)
        if (ray_triangle(&pos[idx[t * 3] * 3], &pos[idx[t * 3 + 1] * 3],
                         &pos[idx[t * 3 + 2] * 3], o, d, &tt, &u, &v) && tt < best)
            best = tt;
    return best;
}

/* A mesh's hierarchy (the ray tracer's, the sweeps') is made when a ray or a sweep first
 * needs it, not when the mesh is made: with its levels read from the cache, nothing at
 * loading makes it. A ray cast then makes it, and finds what every triangle tested in turn
 * finds; a sweep makes it too (without it, the sweep went through the mesh); rays cast
 * while another thread makes its levels find the same; and levels made, here or on another
 * thread, leave the mesh without one (their measuring's own is given back). */
static void test_hierarchy_on_first_need(void)
{
    enum { U = 60, V = 40, NV = (U + 1) * (V + 1), NT = U * V * 2, RAYS = 64 };
    char cache[] = "/tmp/limen_hierarchyXXXXXX";
    static float pos[NV * 3];
    static uint32_t idx[NT * 3];
    if (!mkdtemp(cache)) {
        CHECK(!"no temporary folder");
        return;
    }
    bumpy_sphere(U, V, pos, idx);
    limen_mesh_data data = { .positions = pos, .vertex_count = NV, .indices = idx,
                             .triangle_count = NT };
    setenv("LIMEN_CACHE_DIR", cache, 1);
    unsetenv("LIMEN_CACHE");
    limen_scene *s = new_scene();
    limen_node m = new_mesh(s, "ball");
    CHECK_OK(limen_mesh_set_triangles(s, m, &data));   /* levels made here, and stored */
    /* their measuring made a hierarchy of its own, not the tracer's */
    CHECK(!limen__mesh_hierarchy_made(s, m));
    limen_scene_destroy(s);
    for (int round = 0; round < 4; round++) {
        if (round == 2) {
            /* levels made on another thread beside the rays (whichever makes the hierarchy
             * first, the other waits for it) */
            setenv("LIMEN_CACHE", "off", 1);
            limen__lod_set_async_above(1000);
        }
        s = new_scene();
        m = new_mesh(s, "ball");
        CHECK_OK(limen_mesh_set_triangles(s, m, &data));
        if (round == 2) {           /* the build begins now, as after a first frame */
            limen__meshes_framed(s);
            limen__meshes_framed(s);
        }
        if (round == 3)
            limen__meshes_settle(s, true);
        if (round != 2)
            CHECK_MSG(!limen__mesh_hierarchy_made(s, m), "round %d: made at loading", round);
        if (round == 1) {
            /* a sphere of radius 0.2 dropped onto the ball from above stops on it */
            limen_sweep_result r;
            CHECK_OK(limen_sweep_sphere(s, (float[3]){ 0, 3, 0 }, (float[3]){ 0, -3, 0 }, 0.2f,
                                        NULL, &r));
            CHECK_MSG(r.hit && r.node.id == m.id && r.centre[1] > 0.9f && r.centre[1] < 1.5f,
                      "sweep: hit %d at y = %g", r.hit, r.centre[1]);
            CHECK(limen__mesh_hierarchy_made(s, m));
        }
        int bad = 0;
        for (int i = 0; i < RAYS; i++) {
            /* from points around the ball towards points near its centre */
            double a = 2 * M_PI * i / RAYS, b = 0.3 + 2.5 * i / RAYS;
            float from[3] = { (float)(3 * cos(a) * sin(b)), (float)(3 * cos(b)),
                              (float)(3 * sin(a) * sin(b)) };
            float to[3] = { -from[0] + 0.1f * (float)sin(3.0 * i), -from[1],
                             -from[2] + 0.1f * (float)cos(5.0 * i) };
            limen_hit h;
            CHECK_OK(limen_ray_cast(s, from, to, NULL, &h));
            double len = sqrt((double)to[0] * to[0] + (double)to[1] * to[1] +
                              (double)to[2] * to[2]);
            double o[3] = { from[0], from[1], from[2] },
                   d[3] = { to[0] / len, to[1] / len, to[2] / len };
            double want = brute_hit(pos, idx, NT, o, d);
            if (!h.hit || fabs(h.distance - want) > 1e-5 * want)
                bad++;
        }
        CHECK_MSG(bad == 0, "round %d: %d of %d rays off", round, bad, RAYS);
        CHECK(limen__mesh_hierarchy_made(s, m));
        limen_scene_destroy(s);
    }
    limen__lod_set_async_above(LIMEN__LOD_ASYNC_TRIS);
    setenv("LIMEN_CACHE", "off", 1);
    unsetenv("LIMEN_CACHE_DIR");
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", cache);
    CHECK(system(cmd) == 0);
}

static void test_portal_clone(void)
{
    limen_scene *s = new_scene();
    limen_node a, b, m, cam;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "a", &a));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_PORTAL, "b", &b));
    CHECK_OK(limen_node_set_dims(s, a, (float[3]){ 2, 2, 0 }));
    CHECK_OK(limen_node_set_dims(s, b, (float[3]){ 2, 2, 0 }));
    CHECK_OK(limen_node_set_position(s, b, (float[3]){ 10, 0, 0 }));
    CHECK_OK(limen_portal_link(s, a, b));
    m = new_mesh(s, "cube");
    box_mesh(s, m);
    CHECK_OK(limen_node_set_scale(s, m, (float[3]){ 0.5f, 0.5f, 0.5f }));
    CHECK_OK(limen_node_set_position(s, m, (float[3]){ 0, 0, 0.1f }));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "c", &cam));
    CHECK_OK(limen_node_set_position(s, cam, (float[3]){ 0, 0, 5 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    CHECK_OK(limen_plan_build(p, s, &(limen_plan_desc){ .width = 64, .height = 48 }));
    const limen_clone *cl;
    CHECK(limen_plan_clones(p, &cl) == 1 && cl[0].node.id == m.id && cl[0].portal.id == a.id);
    /* moved away from the portal: no clone */
    limen_move_result mv;
    CHECK_OK(limen_node_move(s, m, (float[3]){ 0, 0, 2 }, &mv));
    CHECK(mv.crossed == 0);
    CHECK_OK(limen_plan_build(p, s, &(limen_plan_desc){ .width = 64, .height = 48 }));
    CHECK(limen_plan_clones(p, &cl) == 0);
    /* and through it: out of the partner */
    CHECK_OK(limen_node_move(s, m, (float[3]){ 0, 0, -4 }, &mv));
    CHECK(mv.crossed == 1);
    float w[16];
    CHECK_OK(limen_node_world_matrix(s, m, w));
    CHECK_NEAR(w[12], 10, 1e-4);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* The triangles a file is refused for before its import (core/mesh_look.c, asked with room
 * for nothing, or 1 MiB for a glTF's JSON to be read in) are never more than its mesh holds once imported, and are its count where
 * every face is kept: real files (OBJ with quads and materials, glTF scenes and a .glb), a
 * PLY written a triangle at a time (three vertices a face), binary and ASCII STL, and a glTF
 * of two triangles without indices, whose six vertices the importer joins into four (counted
 * from the file, they would be more than the mesh holds), and one of a triangle beside 300
 * points (which make no triangles). */
static void test_look_lower_bound(void)
{
    char soup[4096] = "ply\nformat ascii 1.0\nelement vertex 12\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 4\n"
                      "property list uchar int vertex_indices\nend_header\n";
    static const float tet[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    static const int faces[4][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 0, 3, 2 }, { 1, 2, 3 } };
    for (int f = 0; f < 4; f++)
        for (int k = 0; k < 3; k++) {
            const float *p = tet[faces[f][k]];
            snprintf(soup + strlen(soup), 64, "%g %g %g\n", p[0], p[1], p[2]);
        }
    for (int f = 0; f < 4; f++)
        snprintf(soup + strlen(soup), 64, "3 %d %d %d\n", 3 * f, 3 * f + 1, 3 * f + 2);
    unsigned char stl[84 + 2 * 50] = "binary";
    uint32_t two = 2;
    memcpy(stl + 80, &two, 4);
    for (int t = 0; t < 2; t++) {
        float tri[12] = { 0, 0, 1, 0, 0, 0, 1, 0, 0, (float)t, 1, 0 };
        memcpy(stl + 84 + 50 * t, tri, sizeof tri);
    }
    char *files[] = {
        "scenes/data/bunny.obj", "scenes/data/bunny.glb", "scenes/data/level.gltf",
        "scenes/data/spider/spider.obj", "scenes/data/cube_with_vertexcolors.obj",
        NULL, NULL, NULL, NULL, NULL, NULL, NULL,
    };
    files[5] = strdup(write_text("square.obj", obj_square));
    files[6] = strdup(write_text("tetra.ply", ply_tetra));
    files[7] = strdup(write_text("soup.ply", soup));
    files[8] = strdup(write_file("two.stl", (const char *)stl, sizeof stl));
    files[9] = strdup(write_text("one.stl", "solid t\n facet normal 0 0 1\n  outer loop\n"
                                 "   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
                                 "  endloop\n endfacet\nendsolid t\n"));
    /* two triangles without indices: six vertices in the file, four in the mesh */
    files[10] = strdup(write_text("soup.gltf", "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{"
        "\"attributes\":{\"POSITION\":0}}]}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":6,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":72}],\"buffers\":[{\"uri\":"
        "\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPwAA"
        "AAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAA\",\"byteLength\":72}]}"));
    /* a triangle and 300 points (mode 0): the points make no triangles */
    float pts[303 * 3];
    for (int i = 0; i < 303; i++) {
        pts[i * 3] = (float)(i % 17);
        pts[i * 3 + 1] = (float)(i / 17);
        pts[i * 3 + 2] = i < 3 ? 0.0f : 1.0f;
    }
    pts[3] = 1;     /* the triangle (0,0,0) (1,0,0) (0,1,0) */
    pts[4] = 0;
    pts[6] = 0;
    pts[7] = 1;
    write_file("pts.bin", (const char *)pts, sizeof pts);
    files[11] = strdup(write_text("pts.gltf", "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":["
        "{\"attributes\":{\"POSITION\":0}},{\"attributes\":{\"POSITION\":1},\"mode\":0}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,"
        "\"count\":300,\"type\":\"VEC3\",\"min\":[0,0,1],\"max\":[16,17,1]}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,"
        "\"byteLength\":3600}],\"buffers\":[{\"uri\":\"pts.bin\",\"byteLength\":3636}]}"));
    for (int i = 0; i < 12; i++) {
        limen_scene *s = new_scene();
        uint64_t counted;
        size_t wanted;
        CHECK(limen__mesh_look(s, files[i], 1, &counted, &wanted) == LIMEN_ERR_NOMEM);
        char msg[512];
        snprintf(msg, sizeof msg, "%s", limen_scene_error(s));
        if (!counted)
            CHECK_OK(limen__mesh_look(s, files[i], 1 << 20, &counted, &wanted));
        limen_node m = new_mesh(s, "m");
        limen_mesh_info mi = { 0 };
        CHECK_OK(limen_mesh_load(s, m, files[i]));
        CHECK_OK(limen_mesh_get(s, m, &mi));
        CHECK_MSG(counted > 0 && counted == (uint64_t)mi.triangle_count, "%s: %llu counted, %d "
                  "imported (%s)", files[i], (unsigned long long)counted, mi.triangle_count, msg);
        /* nor the bytes: the same measure the mesh is refused by after its import */
        size_t after = limen__mesh_bytes((uint64_t)mi.vertex_count, (uint64_t)mi.triangle_count,
                                         mi.has_uvs);
        CHECK_MSG(wanted > 0 && wanted <= after, "%s: %zu bytes wanted from the file, %zu by "
                  "its mesh", files[i], wanted, after);
        limen_scene_destroy(s);
    }
    for (int i = 5; i < 12; i++)
        free(files[i]);
}

static const check_case cases[] = {
    { "look_lower_bound", test_look_lower_bound },
    { "arrays", test_arrays },
    { "array_errors", test_array_errors },
    { "files", test_files },
    { "plain_ply", test_plain_ply },
    { "bunny", test_bunny },
    { "bad_files", test_bad_files },
    { "ray_cast", test_ray_cast },
    { "normals", test_normals },
    { "trace_box", test_trace_box },
    { "bunny_cast", test_bunny_cast },
    { "portal_clone", test_portal_clone },
    { "hierarchy_on_first_need", test_hierarchy_on_first_need },
    { "threads", test_threads },
    { "light_range", test_light_range },
    { "texture_sampling", test_texture_sampling },
    { "texture_repeat", test_texture_repeat },
    { "texture_levels", test_texture_levels },
    { "mesh_texture", test_mesh_texture },
    { "script", test_script },
    { "script_safety", test_script_safety },
    { "script_memory", test_script_memory },
    { 0 }
};

int main(int argc, char **argv)
{
    snprintf(dir, sizeof dir, "/tmp/limen_mesh_XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    int rc = check_run(argc, argv, cases);
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return rc;
}
