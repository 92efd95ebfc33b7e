/* test_kinds.c - the table of node kinds (limen_kind_get, limen_kind_bounds): a row per
 * kind, named as Lua's constructors name them, giving the dims limen_node_create gives and
 * the boxes limen_node_get_bounds and the drawables' spheres are made of. The expected
 * shapes are written out here, independently of the table. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "limen.h"
#include "scratch.h"

static const char *const kind_names[LIMEN_NODE_KIND_COUNT] = {
    "group", "box", "sphere", "cylinder", "plane", "mirror", "portal", "light", "camera", "mesh"
};

/* This test's name of kind k ("?" for one it does not list: test_rows fails then). */
static const char *name_of(int k)
{
    return kind_names[k] ? kind_names[k] : "?";
}

static limen_scene *new_scene(void)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(&(limen_scene_desc){ 0 }, &s));
    return s;
}

/* One triangle, so that a mesh shows something. */
static void give_triangle(limen_scene *s, limen_node n)
{
    static const float pos[] = { -0.3f, 0.1f, 0.2f, 0.9f, -0.4f, 0.7f, 0.2f, 1.1f, -0.5f };
    static const uint32_t idx[] = { 0, 1, 2 };
    CHECK_OK(limen_mesh_set_triangles(s, n, &(limen_mesh_data){ .positions = pos,
                                                                .vertex_count = 3,
                                                                .indices = idx,
                                                                .triangle_count = 1 }));
}

/* ------------------------------------------------------------------ the table */

static void test_rows(void)
{
    CHECK(limen_kind_get(LIMEN_NODE_KIND_COUNT) == NULL);
    CHECK(limen_kind_get((limen_node_kind)-1) == NULL);
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        const limen_kind_info *ki = limen_kind_get((limen_node_kind)k);
        CHECK_MSG(ki != NULL, "kind %d has no row", k);
        if (!ki)
            continue;
        CHECK_MSG(ki->name && strcmp(ki->name, name_of(k)) == 0, "kind %d is named %s, not %s", k,
                  ki->name ? ki->name : "(null)", name_of(k));
        for (int j = 0; j < k; j++)
            CHECK(strcmp(ki->name, limen_kind_get((limen_node_kind)j)->name) != 0);
        CHECK(ki->size >= 0 && ki->size <= 3);
        CHECK((unsigned)ki->uv < LIMEN_UV_COUNT);
        CHECK((unsigned)ki->unit < LIMEN_UNIT_COUNT);
        CHECK(ki->shape + ki->surface + ki->light <= 1);
        CHECK(!ki->unit || ki->shape || ki->surface);
        CHECK(!ki->closed || (ki->shape && !ki->flat));
        CHECK(ki->round >= 0 && ki->round <= 2 && ki->axis >= 0 && ki->axis < 3);
        for (int a = 0; a < 3; a++) {
            CHECK(ki->scale[a] < ki->size);
            CHECK(!ki->unit || ki->lo[a] <= ki->hi[a]);
        }
    }
    /* what the layers ask, for the kinds limen has */
    const limen_kind_info *box = limen_kind_get(LIMEN_NODE_BOX);
    const limen_kind_info *quad = limen_kind_get(LIMEN_NODE_QUAD);
    const limen_kind_info *mesh = limen_kind_get(LIMEN_NODE_MESH);
    CHECK(box->closed && box->uv == LIMEN_UV_BOX && box->size == 3);
    CHECK(quad->flat && !quad->closed && quad->uv == LIMEN_UV_PLANE && quad->size == 2);
    CHECK(mesh->shape && !mesh->unit && !mesh->closed && mesh->uv == LIMEN_UV_MESH);
    CHECK(limen_kind_get(LIMEN_NODE_MIRROR)->surface && limen_kind_get(LIMEN_NODE_PORTAL)->flat);
    CHECK(limen_kind_get(LIMEN_NODE_SPHERE)->uv == LIMEN_UV_NONE);
    static const limen_unit_shape units[LIMEN_NODE_KIND_COUNT] = {
        [LIMEN_NODE_BOX] = LIMEN_UNIT_BOX, [LIMEN_NODE_SPHERE] = LIMEN_UNIT_BALL,
        [LIMEN_NODE_CYLINDER] = LIMEN_UNIT_CYLINDER, [LIMEN_NODE_QUAD] = LIMEN_UNIT_SQUARE,
        [LIMEN_NODE_MIRROR] = LIMEN_UNIT_SQUARE, [LIMEN_NODE_PORTAL] = LIMEN_UNIT_SQUARE,
    };
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++)
        CHECK_MSG(limen_kind_get((limen_node_kind)k)->unit == units[k], "%s: unit %d", name_of(k),
                  (int)limen_kind_get((limen_node_kind)k)->unit);
    CHECK(limen_kind_get(LIMEN_NODE_LIGHT)->light && !limen_kind_get(LIMEN_NODE_CAMERA)->light);
}

/* The dims limen_node_create gives are the row's, and limen_node_set_dims takes as many as
 * the row's size says. */
static void test_defaults(void)
{
    static const float want[LIMEN_NODE_KIND_COUNT][3] = {
        [LIMEN_NODE_BOX] = { 1, 1, 1 }, [LIMEN_NODE_SPHERE] = { 0.5f, 0, 0 },
        [LIMEN_NODE_CYLINDER] = { 0.5f, 1, 0 }, [LIMEN_NODE_QUAD] = { 1, 1, 0 },
        [LIMEN_NODE_MIRROR] = { 1, 1, 0 }, [LIMEN_NODE_PORTAL] = { 1, 1, 0 },
    };
    limen_scene *s = new_scene();
    if (!s)
        return;
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        const limen_kind_info *ki = limen_kind_get((limen_node_kind)k);
        limen_node n;
        float d[3] = { -1, -1, -1 };
        CHECK_OK(limen_node_create(s, (limen_node_kind)k, NULL, &n));
        CHECK(limen_node_get_kind(s, n) == (limen_node_kind)k);
        CHECK_OK(limen_node_get_dims(s, n, d));
        for (int a = 0; a < 3; a++) {
            CHECK_MSG(d[a] == want[k][a], "%s: dims[%d] = %g, expected %g", name_of(k), a, d[a],
                      want[k][a]);
            CHECK(d[a] == ki->dims[a]);
        }
        limen_status st = limen_node_set_dims(s, n, (float[3]){ 2, 3, 4 });
        CHECK_MSG((st == LIMEN_OK) == (ki->size > 0), "%s: set_dims gave %d", name_of(k), st);
        if (st == LIMEN_OK) {
            limen_node_get_dims(s, n, d);
            for (int a = 0; a < 3; a++)
                CHECK(d[a] == (a < ki->size ? 2.0f + a : 0.0f));
        } else {
            CHECK(strstr(limen_scene_error(s), "has no size") != NULL);
        }
    }
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ bounds */

/* The local box of a kind at dims d, written out: false where it is no unit shape. */
static int local_box(limen_node_kind k, const float d[3], float lo[3], float hi[3])
{
    switch (k) {
    case LIMEN_NODE_BOX:
        for (int a = 0; a < 3; a++)
            hi[a] = -(lo[a] = -0.5f * d[a]);
        return 1;
    case LIMEN_NODE_SPHERE:
        for (int a = 0; a < 3; a++)
            hi[a] = -(lo[a] = -d[0]);
        return 1;
    case LIMEN_NODE_CYLINDER:
        lo[0] = lo[2] = -d[0];
        hi[0] = hi[2] = d[0];
        lo[1] = 0;
        hi[1] = d[1];
        return 1;
    case LIMEN_NODE_QUAD:
    case LIMEN_NODE_MIRROR:
    case LIMEN_NODE_PORTAL:
        hi[0] = -(lo[0] = -0.5f * d[0]);
        hi[1] = -(lo[1] = -0.5f * d[1]);
        lo[2] = hi[2] = 0;
        return 1;
    case LIMEN_NODE_GROUP:
    case LIMEN_NODE_LIGHT:
    case LIMEN_NODE_CAMERA:
    case LIMEN_NODE_MESH:
    case LIMEN_NODE_KIND_COUNT: return 0;
    }
    return 0;
}

/* The world box of local box [lo, hi] through column-major m. */
static void world_box(const float m[16], const float lo[3], const float hi[3], float wlo[3],
                      float whi[3])
{
    for (int a = 0; a < 3; a++) {
        wlo[a] = 1e30f;
        whi[a] = -1e30f;
    }
    for (int c = 0; c < 8; c++) {
        float p[3] = { c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2] };
        for (int a = 0; a < 3; a++) {
            float v = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
            wlo[a] = fminf(wlo[a], v);
            whi[a] = fmaxf(whi[a], v);
        }
    }
}

/* Every kind at odd dims, turned, scaled and moved: limen_kind_bounds is the box written out
 * above, and limen_node_get_bounds is that box (or the mesh's triangles') in the world. */
static void test_bounds(void)
{
    static const float dims[3] = { 0.37f, 1.93f, 2.71f };
    limen_scene *s = new_scene();
    if (!s)
        return;
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        const limen_kind_info *ki = limen_kind_get((limen_node_kind)k);
        limen_node n;
        CHECK_OK(limen_node_create(s, (limen_node_kind)k, name_of(k), &n));
        if (ki->size)
            CHECK_OK(limen_node_set_dims(s, n, dims));
        limen_node_set_position(s, n, (float[3]){ 1.5f, -2.0f, 0.25f });
        limen_node_set_rotation(s, n, (float[3]){ 0.3f, 0.7f, -0.2f });
        limen_node_set_scale(s, n, (float[3]){ 1.3f, 0.8f, 2.1f });
        if (k == LIMEN_NODE_MESH)
            give_triangle(s, n);
        float d[3], want_lo[3], want_hi[3], lo[3], hi[3];
        limen_node_get_dims(s, n, d);
        int unit = local_box((limen_node_kind)k, d, want_lo, want_hi);
        limen_status st = limen_kind_bounds((limen_node_kind)k, d, lo, hi);
        CHECK_MSG((st == LIMEN_OK) == unit, "%s: kind_bounds gave %d", name_of(k), st);
        for (int a = 0; unit && a < 3; a++)
            CHECK_MSG(lo[a] == want_lo[a] && hi[a] == want_hi[a],
                      "%s axis %d: [%g, %g], expected [%g, %g]", name_of(k), a, lo[a], hi[a],
                      want_lo[a], want_hi[a]);
        if (k == LIMEN_NODE_MESH) {
            limen_mesh_info mi;
            CHECK_OK(limen_mesh_get(s, n, &mi));
            memcpy(want_lo, mi.lo, sizeof want_lo);
            memcpy(want_hi, mi.hi, sizeof want_hi);
            unit = 1;
        }
        st = limen_node_get_bounds(s, n, lo, hi);
        CHECK_MSG((st == LIMEN_OK) == unit, "%s: get_bounds gave %d", name_of(k), st);
        if (!unit)
            continue;
        float m[16], wlo[3], whi[3];
        CHECK_OK(limen_node_world_matrix(s, n, m));
        world_box(m, want_lo, want_hi, wlo, whi);
        for (int a = 0; a < 3; a++) {
            CHECK_NEAR(lo[a], wlo[a], 1e-5);
            CHECK_NEAR(hi[a], whi[a], 1e-5);
        }
    }
    /* NULL arguments and a kind out of range */
    float lo[3], hi[3];
    CHECK(limen_kind_bounds(LIMEN_NODE_BOX, NULL, lo, hi) == LIMEN_ERR_ARG);
    CHECK(limen_kind_bounds(LIMEN_NODE_BOX, dims, NULL, hi) == LIMEN_ERR_ARG);
    CHECK(limen_kind_bounds(LIMEN_NODE_KIND_COUNT, dims, lo, hi) == LIMEN_ERR_ARG);
    limen_scene_destroy(s);
}

/* The drawables' bounding spheres: about the box's centre, through its corners, but as tight
 * as a ball's or a cylinder's roundness allows. */
static void test_spheres(void)
{
    limen_scene *s = new_scene();
    limen_drawables *dl = NULL;
    CHECK_OK(limen_drawables_create(&dl));
    if (!s || !dl)
        return;
    struct { limen_node_kind k; float d[3]; float c[3]; float r; } cases[] = {
        { LIMEN_NODE_BOX, { 0.6f, 1.2f, 4.0f }, { 0, 0, 0 }, 0 },
        { LIMEN_NODE_SPHERE, { 0.7f, 0, 0 }, { 0, 0, 0 }, 0 },
        { LIMEN_NODE_CYLINDER, { 0.4f, 1.8f, 0 }, { 0, 0.9f, 0 }, 0 },
        { LIMEN_NODE_QUAD, { 3.0f, 4.0f, 0 }, { 0, 0, 0 }, 0 },
    };
    cases[0].r = 0.5f * sqrtf(0.36f + 1.44f + 16.0f);
    cases[1].r = 0.7f;
    cases[2].r = sqrtf(0.16f + 0.81f);
    cases[3].r = 2.5f;
    int ncase = (int)(sizeof cases / sizeof cases[0]);
    limen_node nodes[4];
    for (int i = 0; i < ncase; i++) {
        CHECK_OK(limen_node_create(s, cases[i].k, NULL, &nodes[i]));
        limen_node_set_dims(s, nodes[i], cases[i].d);
        limen_node_set_position(s, nodes[i], (float[3]){ (float)i, 0, 0 });
        limen_node_set_scale(s, nodes[i], (float[3]){ 2, 2, 2 });
    }
    CHECK_OK(limen_drawables_build(dl, s));
    const limen_drawable *items;
    int count = limen_drawables_items(dl, &items);
    CHECK(count == ncase);
    for (int i = 0; i < ncase && i < count; i++) {
        int j = limen_drawables_find(dl, nodes[i]);
        CHECK(j >= 0);
        if (j < 0)
            continue;
        CHECK_NEAR(items[j].radius, 2 * cases[i].r, 1e-5);
        CHECK_NEAR(items[j].centre[0], (float)i + 2 * cases[i].c[0], 1e-5);
        CHECK_NEAR(items[j].centre[1], 2 * cases[i].c[1], 1e-5);
        CHECK_NEAR(items[j].centre[2], 2 * cases[i].c[2], 1e-5);
    }
    limen_drawables_destroy(dl);
    limen_scene_destroy(s);
}

/* What draws is listed (shapes, surfaces, lights), and a texture goes only where a kind has
 * texture coordinates. */
static void test_listed_and_textured(void)
{
    limen_scene *s = new_scene();
    limen_drawables *dl = NULL;
    CHECK_OK(limen_drawables_create(&dl));
    if (!s || !dl)
        return;
    limen_node n[LIMEN_NODE_KIND_COUNT];
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        CHECK_OK(limen_node_create(s, (limen_node_kind)k, name_of(k), &n[k]));
        limen_status st = limen_node_set_texture(s, n[k], NULL);
        int takes = k == LIMEN_NODE_BOX || k == LIMEN_NODE_QUAD || k == LIMEN_NODE_MESH;
        CHECK_MSG((st == LIMEN_OK) == takes, "%s: set_texture gave %d", name_of(k), st);
        CHECK(takes == (limen_kind_get((limen_node_kind)k)->uv != LIMEN_UV_NONE));
        if (!takes)
            CHECK(strstr(limen_scene_error(s), "takes no texture") != NULL);
    }
    CHECK_OK(limen_drawables_build(dl, s));
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        int listed = k != LIMEN_NODE_GROUP && k != LIMEN_NODE_CAMERA;
        CHECK_MSG((limen_drawables_find(dl, n[k]) >= 0) == listed, "%s: listed %d", name_of(k),
                  limen_drawables_find(dl, n[k]));
    }
    limen_drawables_destroy(dl);
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ Lua */

/* s:<name>{} for every row's name makes a node of that kind, whose node.kind is the name. */
static void test_lua_constructors(void)
{
    script("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    char text[4096];
    size_t len = (size_t)snprintf(text, sizeof text, "%s", HEAD);
    for (int k = 0; k < LIMEN_NODE_KIND_COUNT; k++) {
        const char *name = limen_kind_get((limen_node_kind)k)->name;
        len += (size_t)snprintf(text + len, sizeof text - len,
                                "assert(s:%s { name = \"k%d\"%s }.kind == \"%s\")\n", name, k,
                                k == LIMEN_NODE_MESH ? ", file = \"tri.obj\"" : "", name);
    }
    snprintf(text + len, sizeof text - len,
             "assert(#s:box { size = {1, 2, 3} }.size == 3)\n"
             "assert(#s:plane { size = {2, 3} }.size == 2)\n"
             "assert(s:cylinder { radius = 2, height = 3 }.height == 3)\n"
             "assert(not pcall(s.sphere, s, { size = {1, 1} }))\n"
             "assert(not pcall(s.plane, s, { radius = 1 }))\n"
             "assert(not pcall(s.sphere, s, { texture = \"x.png\" }))\n"
             "return s\n");
    limen_script *sc = NULL;
    CHECK_OK(limen_script_load(script("kinds.lua", text), NULL, &sc));
    CHECK_MSG(strcmp(limen_script_error(sc), "") == 0, "%s", limen_script_error(sc));
    limen_scene *s = limen_script_scene(sc);
    for (int k = 0; s && k < LIMEN_NODE_KIND_COUNT; k++) {
        char nm[16];
        snprintf(nm, sizeof nm, "k%d", k);
        limen_node n = { 0 };
        CHECK_OK(limen_node_find(s, nm, &n));
        CHECK_MSG(limen_node_get_kind(s, n) == (limen_node_kind)k, "s:%s made a kind %d",
                  name_of(k), (int)limen_node_get_kind(s, n));
    }
    limen_script_destroy(sc);
}

static const check_case cases[] = {
    { "rows", test_rows },
    { "defaults", test_defaults },
    { "bounds", test_bounds },
    { "spheres", test_spheres },
    { "listed_and_textured", test_listed_and_textured },
    { "lua_constructors", test_lua_constructors },
    { 0 },
};

int main(int argc, char **argv)
{
    return scratch_main(argc, argv, cases);
}
