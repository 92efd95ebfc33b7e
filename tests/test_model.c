/* test_model.c - scenes from files (limen_model_load): a glTF written here (JSON and a
 * base64 buffer from this code) with a hierarchy, a mirror and a portal pair authored in its
 * extras, a "-mirror" by name, a camera and a light; the nodes it makes, their names,
 * transforms, bounds and triangles; the frame against the ray-traced truth in both methods;
 * and the surfaces it refuses, each naming the node and leaving the scene as it was. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "limen.h"
#include "core/json.h"

#define BOUND 0.005

static char dir[64];

/* ------------------------------------------------------------------ writing glTF */

typedef struct gltf {
    unsigned char bin[16384];
    size_t nbin;
    char meshes[8192], views[8192], accessors[8192];
    int nmeshes, nviews;
} gltf;

static void append(char *dst, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void append(char *dst, size_t size, const char *fmt, ...)
{
    size_t n = strlen(dst);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(dst + n, size - n, fmt, ap);
    va_end(ap);
}

/* A buffer view (and its accessor) of len bytes; returns the accessor's index. */
static int add_view(gltf *g, const void *data, size_t len, const char *accessor)
{
    memcpy(g->bin + g->nbin, data, len);
    append(g->views, sizeof g->views, "%s{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}",
           g->nviews ? ", " : "", g->nbin, len);
    append(g->accessors, sizeof g->accessors, "%s{\"bufferView\": %d, %s}", g->nviews ? ", " : "",
           g->nviews, accessor);
    g->nbin += (len + 3) & ~(size_t)3;
    return g->nviews++;
}

/* A mesh of nv points and nt triangles in material mat, with texture coordinates uv (or
 * NULL); returns its index. */
static int add_mesh_uv(gltf *g, const float *pos, const float *uv, int mat, int nv,
                       const uint16_t *idx, int nt)
{
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (int i = 0; i < nv * 3; i++) {
        lo[i % 3] = fminf(lo[i % 3], pos[i]);
        hi[i % 3] = fmaxf(hi[i % 3], pos[i]);
    }
    char acc[256];
    snprintf(acc, sizeof acc, "\"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", "
             "\"min\": [%g, %g, %g], \"max\": [%g, %g, %g]", nv, lo[0], lo[1], lo[2], hi[0],
             hi[1], hi[2]);
    int p = add_view(g, pos, sizeof(float) * 3 * (size_t)nv, acc);
    snprintf(acc, sizeof acc, "\"componentType\": 5123, \"count\": %d, \"type\": \"SCALAR\"",
             nt * 3);
    int i = add_view(g, idx, sizeof(uint16_t) * 3 * (size_t)nt, acc);
    char tex[64] = "";
    if (uv) {
        snprintf(acc, sizeof acc, "\"componentType\": 5126, \"count\": %d, \"type\": \"VEC2\"",
                 nv);
        snprintf(tex, sizeof tex, ", \"TEXCOORD_0\": %d",
                 add_view(g, uv, sizeof(float) * 2 * (size_t)nv, acc));
    }
    append(g->meshes, sizeof g->meshes, "%s{\"primitives\": [{\"attributes\": {\"POSITION\": "
           "%d%s}, \"indices\": %d, \"material\": %d}]}", g->nmeshes ? ", " : "", p, tex, i,
           mat);
    return g->nmeshes++;
}

static int add_mesh(gltf *g, const float *pos, int nv, const uint16_t *idx, int nt)
{
    return add_mesh_uv(g, pos, NULL, 0, nv, idx, nt);
}

/* A w x h rectangle on z = 0 facing +Z (counter-clockwise seen from +Z). */
static int add_quad(gltf *g, float w, float h)
{
    const float pos[12] = { -w / 2, -h / 2, 0, w / 2, -h / 2, 0, w / 2, h / 2, 0, -w / 2, h / 2, 0 };
    static const uint16_t idx[6] = { 0, 1, 2, 0, 2, 3 };
    return add_mesh(g, pos, 4, idx, 2);
}

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? (unsigned)in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        out[o++] = tab[v >> 18 & 63];
        out[o++] = tab[v >> 12 & 63];
        out[o++] = i + 1 < n ? tab[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? tab[v & 63] : '=';
    }
    out[o] = '\0';
}

/* Writes dir/name: the meshes of g, and nodes (a JSON array's insides) whose top nodes are
 * listed in roots; returns the path. */
static const char *write_gltf(const char *name, const gltf *g, const char *roots,
                              const char *nodes)
{
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    char *b64 = malloc(g->nbin * 2 + 8);
    base64(g->bin, g->nbin, b64);
    /* the checks image again, held in the file as a data URI */
    unsigned char png[4096];
    char png64[6000] = "", pngpath[128];
    snprintf(pngpath, sizeof pngpath, "%s/checks.png", dir);
    FILE *pf = fopen(pngpath, "rb");
    size_t npng = pf ? fread(png, 1, sizeof png, pf) : 0;
    if (pf)
        fclose(pf);
    base64(png, npng, png64);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        /* pi to 80 places in the asset's extras: a number longer than 63 characters left
         * the whole JSON unread, and the light's range and the camera's yfov with it */
        fprintf(f, "{\"asset\": {\"version\": \"2.0\", \"extras\": {\"pi\": 3.14159265358979"
                "323846264338327950288419716939937510582097494459230781640628620899}}, "
                "\"scene\": 0, \"scenes\": [{\"nodes\": "
                "[%s]}],\n \"nodes\": [%s],\n \"meshes\": [%s],\n \"materials\": "
                "[{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.8, 0.7, 0.6, 1]}},\n"
                "  {\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}},\n"
                "  {\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 1}}},\n"
                "  {\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 2}}}],\n"
                " \"textures\": [{\"source\": 0}, {\"source\": 1}, {\"source\": 2}],\n"
                " \"images\": [{\"uri\": \"../elsewhere/checks.png\"}, {\"uri\": \"gone.png\"},\n"
                "  {\"uri\": \"data:image/png;base64,%s\"}],\n"
                " \"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.9, "
                "\"aspectRatio\": 1.3333, \"znear\": 0.05, \"zfar\": 100}}],\n"
                " \"extensionsUsed\": [\"KHR_lights_punctual\"],\n \"extensions\": "
                "{\"KHR_lights_punctual\": {\"lights\": [{\"type\": \"point\", \"color\": [1, 1, "
                "1], \"intensity\": 0.9, \"range\": 7.5}]}},\n \"bufferViews\": [%s],\n \"accessors\": [%s],\n"
                " \"buffers\": [{\"byteLength\": %zu, \"uri\": "
                "\"data:application/octet-stream;base64,%s\"}]}\n",
                roots, nodes, g->meshes, png64, g->views, g->accessors, g->nbin, b64);
        fclose(f);
    }
    free(b64);
    return path;
}

/* The level: a floor, a room group holding a crate, a mirror by extras and one by name, a
 * portal pair by extras, a camera and a lamp. Meshes: 0 floor, 1 crate, 2 a 2 x 1.5 quad,
 * 3 a 1 x 2 quad, 4 a bent quad, 5 a 1.2 x 1 quad, 6 a sign whose image is missing, 7 a
 * poster whose image the file holds (a data URI). The floor's image (material 1) is named
 * "../elsewhere/checks.png" and lies beside the file. */
static void level_meshes(gltf *g)
{
    memset(g, 0, sizeof *g);
    unsigned char px[8 * 8 * 3];
    for (int i = 0; i < 64; i++)
        for (int c = 0; c < 3; c++)
            px[i * 3 + c] = (unsigned char)(((i % 8) / 2 + (i / 16)) % 2 ? 230 : 60 + 40 * c);
    char path[128];
    snprintf(path, sizeof path, "%s/checks.png", dir);
    CHECK_OK(limen_write_png(path, 8, 8, px));
    static const float floor_pos[12] = { -5, 0, 5, 5, 0, 5, 5, 0, -5, -5, 0, -5 };
    static const float floor_uv[8] = { 0, 0, 5, 0, 5, 5, 0, 5 };
    static const uint16_t quad_idx[6] = { 0, 1, 2, 0, 2, 3 };
    add_mesh_uv(g, floor_pos, floor_uv, 1, 4, quad_idx, 2);
    static const float cube_pos[24] = { -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f,
                                        -0.5f, 0.5f, -0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f, 0.5f,
                                        0.5f, 0.5f, 0.5f, -0.5f, 0.5f, 0.5f };
    static const uint16_t cube_idx[36] = { 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                           3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5 };
    add_mesh(g, cube_pos, 8, cube_idx, 12);
    add_quad(g, 2, 1.5f);
    add_quad(g, 1, 2);
    static const float bent_pos[12] = { -0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0.02f,
                                        -0.5f, 0.5f, 0 };
    add_mesh(g, bent_pos, 4, quad_idx, 2);
    add_quad(g, 1.2f, 1);
    static const float sign_pos[12] = { -0.5f, 0, 0, 0.5f, 0, 0, 0.5f, 1, 0, -0.5f, 1, 0 };
    static const float sign_uv[8] = { 0, 0, 1, 0, 1, 1, 0, 1 };
    add_mesh_uv(g, sign_pos, sign_uv, 2, 4, quad_idx, 2);
    add_mesh_uv(g, sign_pos, sign_uv, 3, 4, quad_idx, 2);
}

#define Q_PLUS_X "\"rotation\": [0, 0.70710678, 0, 0.70710678]"
#define Q_MINUS_X "\"rotation\": [0, -0.70710678, 0, 0.70710678]"

static const char *level_nodes =
    "{\"name\": \"level\", \"children\": [1, 2, 4, 5, 6, 7, 8, 9, 10, 11]},\n"
    "{\"name\": \"floor\", \"mesh\": 0},\n"
    "{\"name\": \"room\", \"translation\": [1.5, 0, -1], \"children\": [3]},\n"
    "{\"name\": \"crate\", \"mesh\": 1, \"translation\": [0, 0.5, 0], \"scale\": [1, 1, 1]},\n"
    "{\"name\": \"glass\", \"mesh\": 2, \"translation\": [0, 1.2, -3.5], \"extras\": "
    "{\"limen\": {\"mirror\": {\"max_depth\": 3, \"tint\": [0.9, 0.95, 1]}}}},\n"
    "{\"name\": \"side-mirror\", \"mesh\": 5, \"translation\": [-4.5, 1, -1], " Q_PLUS_X "},\n"
    "{\"name\": \"blue\", \"mesh\": 3, \"translation\": [-2.5, 1, -1.2], " Q_PLUS_X ", \"extras\": "
    "{\"limen\": {\"portal\": {\"partner\": \"orange\", \"max_depth\": 4}}}},\n"
    "{\"name\": \"orange\", \"mesh\": 3, \"translation\": [3.2, 1, -1.2], " Q_MINUS_X ", \"extras\": "
    "{\"limen\": {\"portal\": {\"partner\": \"blue\"}}}},\n"
    "{\"name\": \"eye\", \"camera\": 0, \"translation\": [0.3, 1.6, 4.5]},\n"
    "{\"name\": \"lamp\", \"translation\": [0, 3, 2], \"extensions\": {\"KHR_lights_punctual\": "
    "{\"light\": 0}}},\n"
    "{\"name\": \"sign\", \"mesh\": 6, \"translation\": [-1.5, 0, -2]},\n"
    "{\"name\": \"poster\", \"mesh\": 7, \"translation\": [0.6, 0, -2.5]}";

static limen_scene *new_scene(void)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    return s;
}

static limen_node find_below(limen_scene *s, limen_node root, const char *name)
{
    limen_node n = { 0 };
    CHECK_MSG(limen_node_find_below(s, root, name, &n) == LIMEN_OK, "no node '%s'", name);
    return n;
}

/* ------------------------------------------------------------------ tests */

/* The hierarchy arrives as written: names, kinds, parents, world places, surfaces fitted to
 * their rectangles, portals paired, the camera and the lamp, bounds and triangle counts. */
static void test_hierarchy(void)
{
    gltf g;
    level_meshes(&g);
    const char *path = write_gltf("level.gltf", &g, "0", level_nodes);
    limen_scene *s = new_scene();
    limen_node group;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "model", &group));
    CHECK_OK(limen_node_set_position(s, group, (float[3]){ 0, 0.5f, 0 }));
    limen_status st = limen_model_load(s, group, path,
                                       &(limen_model_desc){ .cameras = 1, .lights = 1 });
    CHECK_MSG(st == LIMEN_OK, "%s", limen_scene_error(s));
    if (st) {
        limen_scene_destroy(s);
        return;
    }
    limen_node level = find_below(s, group, "level"), room = find_below(s, group, "room");
    limen_node crate = find_below(s, group, "crate"), glass = find_below(s, group, "glass");
    limen_node side = find_below(s, group, "side-mirror"), blue = find_below(s, group, "blue");
    limen_node orange = find_below(s, group, "orange");
    CHECK(limen_node_get_kind(s, level) == LIMEN_NODE_GROUP);
    CHECK(limen_node_get_parent(s, level).id == group.id);
    CHECK(limen_node_get_parent(s, crate).id == room.id);
    CHECK(limen_node_get_kind(s, crate) == LIMEN_NODE_MESH);
    CHECK(limen_node_get_kind(s, glass) == LIMEN_NODE_MIRROR);
    CHECK(limen_node_get_kind(s, side) == LIMEN_NODE_MIRROR);
    CHECK(limen_node_get_kind(s, blue) == LIMEN_NODE_PORTAL);
    CHECK(limen_portal_get_partner(s, blue).id == orange.id);
    limen_node none;
    CHECK(limen_node_find_below(s, room, "glass", &none) == LIMEN_ERR_HANDLE && !none.id);
    /* the mirror: its rectangle, centre and facing (+Z), depth and tint from the extras */
    float dims[3], w[16], tint[3];
    int depth = 0;
    CHECK_OK(limen_node_get_dims(s, glass, dims));
    CHECK_NEAR(dims[0], 2, 1e-5);
    CHECK_NEAR(dims[1], 1.5, 1e-5);
    CHECK_OK(limen_node_world_matrix(s, glass, w));
    CHECK_NEAR(w[12], 0, 1e-5);
    CHECK_NEAR(w[13], 1.7, 1e-5);
    CHECK_NEAR(w[14], -3.5, 1e-5);
    CHECK_NEAR(w[10], 1, 1e-5);     /* its +Z is the world's */
    CHECK_OK(limen_surface_get(s, glass, tint, NULL, NULL, &depth));
    CHECK(depth == 3);
    CHECK_NEAR(tint[1], 0.95, 1e-6);
    /* the named mirror faces +X, its height up */
    CHECK_OK(limen_node_world_matrix(s, side, w));
    CHECK_NEAR(w[8], 1, 1e-5);
    CHECK_NEAR(w[5], 1, 1e-5);
    CHECK_OK(limen_node_get_dims(s, side, dims));
    CHECK_NEAR(dims[0], 1.2, 1e-5);
    CHECK_OK(limen_node_get_dims(s, blue, dims));
    CHECK_NEAR(dims[1], 2, 1e-5);
    /* the crate's world box and triangles; the floor's colour from its material */
    float lo[3], hi[3], c[3];
    CHECK_OK(limen_node_get_bounds(s, crate, lo, hi));
    CHECK_NEAR(lo[0], 1.0, 1e-5);
    CHECK_NEAR(hi[1], 1.5, 1e-5);
    CHECK_NEAR(lo[2], -1.5, 1e-5);
    CHECK_OK(limen_node_get_bounds(s, group, lo, hi));
    CHECK_NEAR(lo[0], -5, 1e-5);
    CHECK_NEAR(hi[2], 5, 1e-5);
    CHECK(limen_node_get_bounds(s, find_below(s, group, "lamp"), lo, hi) == LIMEN_ERR_ARG);
    limen_mesh_info mi;
    CHECK_OK(limen_mesh_get(s, crate, &mi));
    CHECK(mi.triangle_count == 12);
    /* the floor's image found beside the file by its base name; the sign's missing one
     * leaves it untextured */
    limen_drawables *d = NULL;
    CHECK_OK(limen_drawables_create(&d));
    CHECK_OK(limen_drawables_build(d, s));
    const limen_drawable *items;
    limen_drawables_items(d, &items);
    const limen_mesh_geometry *fl = items[limen_drawables_find(d, find_below(s, group,
                                                                             "floor"))].mesh;
    const limen_mesh_geometry *si = items[limen_drawables_find(d, find_below(s, group,
                                                                             "sign"))].mesh;
    const limen_mesh_geometry *po = items[limen_drawables_find(d, find_below(s, group,
                                                                             "poster"))].mesh;
    const limen_mesh_geometry *cr = items[limen_drawables_find(d, crate)].mesh;
    CHECK(fl && fl->material_count == 1 && fl->materials[0].base_texture &&
          fl->materials[0].base_texture->width == 8);
    CHECK(si && si->material_count == 1 && !si->materials[0].base_texture);
    bool warned = false;    /* the missing image is a warning of the scene's */
    for (int i = 0; i < limen_scene_warning_count(s); i++)
        warned |= strstr(limen_scene_warning(s, i), "gone.png") != NULL;
    CHECK(warned);
    CHECK(po && po->material_count == 1 && po->materials[0].base_texture &&
          po->materials[0].base_texture->width == 8);
    /* the crate's colour is its part's material's */
    CHECK(cr && cr->material_count == 1);
    if (cr && cr->material_count == 1)
        CHECK_NEAR(cr->materials[0].base_color[1], 0.7, 1e-6);
    limen_drawables_destroy(d);
    /* the model is among the files the scene read (limen view watches them) */
    char file[4096];
    bool listed = false;
    for (int i = 0; limen_scene_get_file(s, i, file, sizeof file) == LIMEN_OK; i++)
        listed |= strlen(file) > 11 && strcmp(file + strlen(file) - 11, "/level.gltf") == 0;
    CHECK(listed);
    /* camera and lamp: the scene's camera now, at the file's place and lens */
    limen_node eye = limen_scene_get_camera(s);
    CHECK(eye.id && strcmp(limen_node_get_name(s, eye), "eye") == 0);
    CHECK_OK(limen_node_world_matrix(s, eye, w));
    CHECK_NEAR(w[13], 2.1, 1e-5);
    CHECK_NEAR(w[10], 1, 1e-5);     /* looking down -Z */
    float fovy, zn, zf;
    CHECK_OK(limen_camera_get_lens(s, eye, &fovy, &zn, &zf));
    CHECK_NEAR(fovy, 0.9, 1e-4);
    limen_node lamp = find_below(s, group, "lamp");
    CHECK(limen_node_get_kind(s, lamp) == LIMEN_NODE_LIGHT);
    CHECK_OK(limen_node_get_color(s, lamp, c));
    CHECK_NEAR(c[0], 0.9, 1e-6);
    CHECK_NEAR(limen_light_get_range(s, lamp), 7.5, 1e-6);  /* from the JSON: assimp drops it */
    /* the same as a .glb: the JSON its first chunk (the buffer's data URI cut out), the
     * buffer its binary chunk; the range and the lens are read from the JSON chunk alone */
    FILE *tf = fopen(path, "rb");
    char *json = calloc(1, 1 << 20);
    size_t jn = tf ? fread(json, 1, (1 << 20) - 4, tf) : 0;
    if (tf)
        fclose(tf);
    char *uri = strstr(json, ", \"uri\": \"data:application/octet-stream");
    char *end = uri ? strchr(uri + 10, '"') : NULL;     /* the URI's closing quote */
    CHECK(uri && end);
    if (uri && end) {
        memmove(uri, end + 1, strlen(end + 1) + 1);
        jn = strlen(json);
    }
    while (jn % 4)
        json[jn++] = ' ';
    size_t nb = (g.nbin + 3) / 4 * 4;
    uint32_t hdr[5] = { 0x46546C67u, 2, (uint32_t)(20 + jn + 8 + nb), (uint32_t)jn,
                        0x4E4F534Au };
    uint32_t bin[2] = { (uint32_t)nb, 0x004E4942u };
    char glb[128];
    snprintf(glb, sizeof glb, "%s/level.glb", dir);
    FILE *gf = fopen(glb, "wb");
    CHECK(gf != NULL);
    if (gf) {
        fwrite(hdr, sizeof hdr, 1, gf);
        fwrite(json, 1, jn, gf);
        fwrite(bin, sizeof bin, 1, gf);
        fwrite(g.bin, 1, g.nbin, gf);
        fwrite("\0\0\0", 1, nb - g.nbin, gf);
        fclose(gf);
    }
    free(json);
    limen_scene *sb = new_scene();
    limen_node gb;
    CHECK_OK(limen_node_create(sb, LIMEN_NODE_GROUP, NULL, &gb));
    CHECK_OK(limen_model_load(sb, gb, glb, &(limen_model_desc){ .cameras = 1, .lights = 1 }));
    CHECK_MSG(fabs(limen_light_get_range(sb, find_below(sb, gb, "lamp")) - 7.5) < 1e-6,
              ".glb: range %g: %s", limen_light_get_range(sb, find_below(sb, gb, "lamp")),
              limen_scene_error(sb));
    CHECK_OK(limen_camera_get_lens(sb, limen_scene_get_camera(sb), &fovy, &zn, &zf));
    CHECK_NEAR(fovy, 0.9, 1e-4);
    limen_scene_destroy(sb);
    /* asked for neither: no camera, no light */
    limen_scene *s2 = new_scene();
    limen_node g2;
    CHECK_OK(limen_node_create(s2, LIMEN_NODE_GROUP, NULL, &g2));
    CHECK_OK(limen_model_load(s2, g2, path, NULL));
    CHECK(!limen_scene_get_camera(s2).id);
    CHECK(limen_node_get_kind(s2, find_below(s2, g2, "lamp")) == LIMEN_NODE_GROUP);
    CHECK(limen_node_get_kind(s2, find_below(s2, g2, "eye")) == LIMEN_NODE_GROUP);
    limen_scene_destroy(s2);
    limen_scene_destroy(s);
}

/* The level through its own camera, both methods, against the truth; and it is not empty
 * (mirrors and portals show something other than the background). */
static void test_render(void)
{
    const int w = 320, h = 240;
    gltf g;
    level_meshes(&g);
    const char *path = write_gltf("level.gltf", &g, "0", level_nodes);
    limen_scene *s = new_scene();
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = w, .height = h }, &r));
    limen_node group;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "model", &group));
    limen_status st = limen_model_load(s, group, path,
                                       &(limen_model_desc){ .cameras = 1, .lights = 1 });
    CHECK_MSG(st == LIMEN_OK, "%s", limen_scene_error(s));
    unsigned char *truth = malloc((size_t)w * h * 3), *rgb = malloc((size_t)w * h * 3);
    if (!st && r) {
        CHECK_OK(limen_trace_image(s, &(limen_trace_desc){ .width = w, .height = h }, truth));
        /* the mirror's middle shows the room (not its fill, not the background) */
        limen_hit hit;
        CHECK_OK(limen_ray_cast(s, (float[3]){ 0, 1.7f, 0 }, (float[3]){ 0, -0.2f, -1 }, NULL,
                                &hit));
        CHECK(hit.surface_count == 1 && hit.surfaces[0].id == find_below(s, group, "glass").id);
        CHECK(hit.hit && hit.node.id == find_below(s, group, "floor").id);
        for (int m = 0; m < 2; m++) {
            CHECK_OK(limen_render_frame(r, s, &(limen_render_opts){ .method = m }, NULL));
            CHECK_OK(limen_renderer_read_rgb(r, rgb));
            limen_diff d = { 1, 0, 0, 0 };
            CHECK_OK(limen_image_diff(rgb, truth, w, h, 8, &d, NULL));
            printf("     level from a glTF, %s: %.3f%% of pixels off\n",
                   m ? "texture" : "stencil", 100 * d.bad_share);
            CHECK_MSG(d.bad_share <= BOUND, "%.3f%% of pixels off", 100 * d.bad_share);
        }
    }
    free(truth);
    free(rgb);
    limen_renderer_destroy(r);
    limen_scene_destroy(s);
}

/* What it refuses, each naming the file and the node, the scene left as it was. */
static void test_refusals(void)
{
    gltf g;
    level_meshes(&g);
    static const struct {
        const char *nodes, *msg;
    } bad[] = {
        { "{\"name\": \"wavy-mirror\", \"mesh\": 4}", "node 'wavy-mirror': a mirror must be "
          "one flat rectangle (a polygon's bounding rectangle will do): it is not flat" },
        { "{\"name\": \"box\", \"mesh\": 1, \"extras\": {\"limen\": {\"mirror\": {}}}}",
          "node 'box': a mirror must be one flat rectangle (a polygon's bounding rectangle "
          "will do): its triangles do not make one flat polygon facing one way" },
        { "{\"name\": \"p\", \"mesh\": 3, \"extras\": {\"limen\": {\"portal\": {\"partner\": "
          "\"q\"}}}}", "portal 'p': its partner 'q' is not a node of the file" },
        { "{\"name\": \"p\", \"mesh\": 3, \"children\": [1], \"extras\": {\"limen\": {\"portal\": "
          "{\"partner\": \"q\"}}}}, {\"name\": \"q\", \"mesh\": 3}",
          "portal 'p': its partner 'q' does not name it back as a portal's partner" },
        { "{\"name\": \"m\", \"mesh\": 2, \"extras\": {\"limen\": {\"mirror\": {\"tint\": [1, 1]}}}}",
          "node 'm': tint must be [r, g, b], each from 0 to 1" },
        { "{\"name\": \"m\", \"mesh\": 2, \"extras\": {\"limen\": {\"mirror\": {\"depth\": 2}}}}",
          "node 'm': unknown mirror field \"depth\"" },
        { "{\"name\": \"m\", \"mesh\": 2, \"extras\": {\"limen\": \"mirror\"}}",
          "node 'm': its extras' \"limen\" is not an object" },
        { "{\"name\": \"e-mirror\", \"children\": [1]}, {\"name\": \"f\", \"mesh\": 0}",
          "node 'e-mirror': a mirror must be one flat rectangle (a polygon's bounding "
          "rectangle will do): it has no triangles" },
        { "{\"name\": \"m\", \"mesh\": 2, \"extras\": {\"limen\": {\"mirror\": {\"max_depth\": "
          "300}}}}", "node 'm': max_depth must be an integer from 0 to 255" },
        { "{\"name\": \"m\", \"mesh\": 2, \"extras\": {\"limen\": {\"mirror\": {\"max_depth\": "
          "2.5}}}}", "node 'm': max_depth must be an integer from 0 to 255" },
        { "{\"name\": \"p\", \"mesh\": 3, \"extras\": {\"limen\": {\"portal\": {\"partner\": "
          "7}}}}", "node 'p': partner must be a node's name" },
        { "{\"name\": \"p\", \"mesh\": 3, \"extras\": {\"limen\": {\"portal\": {}}}}",
          "node 'p': a portal needs \"partner\": the name of the other node" },
        { "{\"name\": \"p\", \"mesh\": 3, \"extras\": {\"limen\": {\"portal\": {\"partner\": "
          "\"p\"}, \"mirror\": {}}}}", "node 'p': its extras' \"limen\" must hold one object" },
        { "{\"name\": \"far\", \"mesh\": 2, \"translation\": [1e39, 0, 0]}",
          "node 'far': its matrix is not finite" },
        { "{\"name\": \"tiny-mirror\", \"mesh\": 2, \"scale\": [1e-30, 1e-30, 1]}",
          "node 'tiny-mirror': " },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char name[32];
        snprintf(name, sizeof name, "bad%zu.gltf", i);
        const char *path = write_gltf(name, &g, "0", bad[i].nodes);
        limen_scene *s = new_scene();
        limen_node group;
        CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "model", &group));
        limen_status st = limen_model_load(s, group, path, NULL);
        char want[512];
        snprintf(want, sizeof want, "%s: %s", path, bad[i].msg);
        CHECK_MSG(st != LIMEN_OK && strncmp(limen_scene_error(s), want, strlen(want)) == 0,
                  "case %zu:\n    got      '%s'\n    expected '%s...'", i, limen_scene_error(s),
                  want);
        CHECK(limen_scene_node_count(s) == 1);
        limen_scene_destroy(s);
    }
    /* no file, a file that is not a model, a node that is not a group */
    limen_scene *s = new_scene();
    limen_node group, box;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_GROUP, "model", &group));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_BOX, "box", &box));
    CHECK(limen_model_load(s, group, "/nonexistent/x.glb", NULL) == LIMEN_ERR_IO);
    CHECK(strstr(limen_scene_error(s), "/nonexistent/x.glb: cannot open") != NULL);
    char path[128];
    snprintf(path, sizeof path, "%s/junk.gltf", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 99}]", f);
        fclose(f);
    }
    CHECK(limen_model_load(s, group, path, NULL) == LIMEN_ERR_IO);
    CHECK(limen_model_load(s, box, path, NULL) == LIMEN_ERR_HANDLE);
    CHECK(limen_scene_node_count(s) == 2);
    limen_scene_destroy(s);
}

/* The JSON reader behind the light ranges, on hostile text: refused, never read past. */
static void test_json(void)
{
    limen__json j;
    const char *good = " {\"a\": [1, -2.5e1, true, null, \"x\\\"y\"], \"b\": {}} ";
    CHECK(limen__json_parse(&j, good, strlen(good), 100));
    int a = limen__json_get(&j, 0, "a");
    CHECK(limen__json_at(&j, a, 1) >= 0 && j.v[limen__json_at(&j, a, 1)].number == -25);
    CHECK(j.v[limen__json_at(&j, a, 2)].number == 1 && limen__json_at(&j, a, 5) < 0);
    CHECK(limen__json_is(&j, limen__json_at(&j, a, 4), "x\\\"y"));
    CHECK(limen__json_get(&j, a, "b") < 0 && limen__json_get(&j, 0, "c") < 0);
    free(j.v);
    /* a number of more digits than a double holds is read whole (and rounded) */
    const char *pi = "[3.14159265358979323846264338327950288419716939937510582097494459230781]";
    CHECK(limen__json_parse(&j, pi, strlen(pi), 100) && fabs(j.v[1].number - M_PI) < 1e-15);
    free(j.v);
    static const char *const bad[] = { "", "{", "[1,]", "{\"a\" 1}", "\"abc", "01x", "[1] 2",
                                       "{\"a\": tru}", "[\"\\", "1e999999999999999999999999"
                                       "999999999999999999999999999999999999999999999999" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_MSG(!limen__json_parse(&j, bad[i], strlen(bad[i]), 100), "case %zu accepted", i);
        free(j.v);
    }
    char deep[400];
    memset(deep, '[', sizeof deep);
    CHECK(!limen__json_parse(&j, deep, sizeof deep, 1000));     /* deeper than 64 */
    free(j.v);
    CHECK(!limen__json_parse(&j, "[1, 2, 3]", 9, 3));            /* more values than allowed */
    free(j.v);
    CHECK(limen__json_parse(&j, "[1, 2, 3]", 5, 10) == false);   /* cut short */
    free(j.v);
}

static const check_case cases[] = {
    { "json", test_json },
    { "hierarchy", test_hierarchy },
    { "render", test_render },
    { "refusals", test_refusals },
    { 0 },
};

int main(int argc, char **argv)
{
    snprintf(dir, sizeof dir, "/tmp/limen_model_XXXXXX");
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
