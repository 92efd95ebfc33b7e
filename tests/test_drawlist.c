/* test_drawlist.c - the draw list without GL: the stencil steps of a mirror box in order,
 * every command within the list's arrays, polygons clipped, batches of shared geometry, the
 * depth tests of both ranges, the triangle budget, bad input, and memory reused. */
#include <stdbool.h>
#include <stdlib.h>

#include "check.h"
#include "limen.h"

#define W 160
#define H 120

typedef struct frame {
    limen_scene *s;
    limen_plan *p;
    limen_drawables *d;
    limen_drawlist *dl;
} frame;

static limen_scene *scene_with_camera(const float eye[3], const float at[3])
{
    limen_scene *s = NULL;
    limen_node cam;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam));
    CHECK_OK(limen_node_look_at(s, cam, eye, at, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(s, cam));
    return s;
}

static limen_node surface(limen_scene *s, limen_node_kind kind, const float pos[3],
                          const float normal[3], float w, float h)
{
    limen_node n;
    CHECK_OK(limen_node_create(s, kind, NULL, &n));
    CHECK_OK(limen_node_set_position(s, n, pos));
    CHECK_OK(limen_node_set_facing(s, n, normal, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_node_set_dims(s, n, (float[3]){ w, h, 0 }));
    return n;
}

static void shape(limen_scene *s, limen_node_kind kind, const float pos[3])
{
    limen_node n;
    CHECK_OK(limen_node_create(s, kind, NULL, &n));
    CHECK_OK(limen_node_set_position(s, n, pos));
    CHECK_OK(limen_node_set_dims(s, n, (float[3]){ 0.5f, 0.5f, 0.5f }));
}

/* A room of four mirror walls around the camera, a sphere and a box inside. */
static limen_scene *mirror_box(void)
{
    limen_scene *s = scene_with_camera((float[3]){ 0.4f, 1.2f, 0.7f }, (float[3]){ -0.5f, 1, -3 });
    surface(s, LIMEN_NODE_MIRROR, (float[3]){ 0, 1, -3 }, (float[3]){ 0, 0, 1 }, 5.9f, 2);
    surface(s, LIMEN_NODE_MIRROR, (float[3]){ 0, 1, 3 }, (float[3]){ 0, 0, -1 }, 5.9f, 2);
    surface(s, LIMEN_NODE_MIRROR, (float[3]){ -3, 1, 0 }, (float[3]){ 1, 0, 0 }, 5.9f, 2);
    surface(s, LIMEN_NODE_MIRROR, (float[3]){ 3, 1, 0 }, (float[3]){ -1, 0, 0 }, 5.9f, 2);
    shape(s, LIMEN_NODE_SPHERE, (float[3]){ -1, 1, -1 });
    shape(s, LIMEN_NODE_BOX, (float[3]){ 1, 0.5f, -1.5f });
    return s;
}

static void frame_open(frame *f, limen_scene *s, limen_plan_desc pd)
{
    f->s = s;
    f->p = NULL;
    f->d = NULL;
    f->dl = NULL;
    pd.width = W, pd.height = H;
    CHECK_OK(limen_plan_create(&f->p));
    CHECK_OK(limen_drawables_create(&f->d));
    CHECK_OK(limen_drawlist_create(&f->dl));
    limen_status st = limen_plan_build(f->p, s, &pd);
    CHECK_MSG(st == LIMEN_OK, "plan: %s", limen_scene_error(s));
    CHECK_OK(limen_drawables_build(f->d, s));
}

static limen_status frame_list(frame *f, limen_drawlist_desc dd)
{
    dd.width = W, dd.height = H;
    limen_status st = limen_drawlist_build(f->dl, f->p, f->d, &dd);
    CHECK_MSG(st == LIMEN_OK, "drawlist: %s", limen_drawlist_error(f->dl));
    return st;
}

static void frame_close(frame *f)
{
    limen_drawlist_destroy(f->dl);
    limen_drawables_destroy(f->d);
    limen_plan_destroy(f->p);
    limen_scene_destroy(f->s);
}

/* Every index of every command lies within the list's arrays, every polygon within the
 * image (clipped), and each image polygon samples a target drawn before it. */
static void check_ranges(const frame *f)
{
    const limen_draw_cmd *c;
    const limen_draw_pass *p;
    const float (*v)[3];
    int n = limen_drawlist_commands(f->dl, &c), np = limen_drawlist_passes(f->dl, &p);
    const limen_draw_instance *inst;
    int nv = limen_drawlist_vertices(f->dl, &v), ni = limen_drawlist_instances(f->dl, &inst);
    const limen_drawable *items;
    int nitems = limen_drawables_items(f->d, &items);
    bool drawn[256] = { false };
    CHECK(n > 0 && np > 0);
    for (int i = 0; i < n; i++) {
        CHECK_MSG(c[i].pass >= 0 && c[i].pass < np, "command %d: pass %d of %d", i, c[i].pass, np);
        CHECK((unsigned)c[i].op < LIMEN_DRAW_OP_COUNT);
        CHECK((unsigned)c[i].state.depth_test < LIMEN_COMPARE_COUNT);
        switch (c[i].op) {
        case LIMEN_DRAW_POLYGON:
            CHECK_MSG(c[i].first >= 0 && c[i].count >= 3 && c[i].first + c[i].count <= nv,
                      "command %d: vertices %d+%d of %d", i, c[i].first, c[i].count, nv);
            for (int k = c[i].first; k < c[i].first + c[i].count && k < nv; k++)
                CHECK_MSG(fabsf(v[k][0]) <= 1.00001f && fabsf(v[k][1]) <= 1.00001f,
                          "vertex %d at %g, %g", k, v[k][0], v[k][1]);
            /* already clipped: a backend may draw it with no clip distances */
            CHECK(!c[i].state.clip_on && !c[i].state.cut_on);
            if (c[i].image == LIMEN_IMAGE_TARGET)
                CHECK(c[i].target > 0 && c[i].target < 256 && drawn[c[i].target]);
            break;
        case LIMEN_DRAW_SHAPE: {
            CHECK(c[i].item >= 0 && c[i].item < nitems);
            if (c[i].item < 0 || c[i].item >= nitems)
                break;
            /* curved shapes come tessellated, the others not */
            limen_node_kind k = items[c[i].item].kind;
            bool curved = k == LIMEN_NODE_SPHERE || k == LIMEN_NODE_CYLINDER, known = false;
            static const int segments[] = { 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256 };
            for (int j = 0; j < 11; j++)
                known |= c[i].segments == segments[j];
            CHECK_MSG(curved ? known : c[i].segments == 0, "command %d: kind %d, %d segments",
                      i, (int)k, c[i].segments);
            /* its level of the unit geometry has those segments (a ball's S (S - 2) triangles,
             * a cylinder's 4 S), and its instance is world times scale, with its albedo */
            const limen_mesh_geometry *g = limen_unit_geometry(limen_kind_get(k)->unit);
            CHECK(g && c[i].lod >= 0 && c[i].lod < g->lod_count);
            int S = c[i].segments, tris = g && c[i].lod >= 0 && c[i].lod < g->lod_count
                                              ? g->lods[c[i].lod].triangle_count : -1;
            if (curved)
                CHECK_MSG(tris == (k == LIMEN_NODE_SPHERE ? S * (S - 2) : 4 * S),
                          "command %d: %d segments, %d triangles", i, S, tris);
            CHECK(c[i].count == 1 && c[i].first >= 0 && c[i].first < ni);
            const limen_draw_instance *in = c[i].first >= 0 && c[i].first < ni ? &inst[c[i].first]
                                                                             : NULL;
            for (int e = 0; in && e < 16; e++)
                CHECK(in->world[e] == c[i].world[e] * (e < 12 ? c[i].scale[e / 4] : 1.0f));
            CHECK(in && memcmp(in->color, c[i].color, sizeof in->color) == 0);
            break;
        }
        case LIMEN_DRAW_MESHES:
            CHECK(c[i].item >= 0 && c[i].item < nitems);
            CHECK(c[i].first >= 0 && c[i].count > 0 && c[i].first + c[i].count <= ni);
            break;
        case LIMEN_DRAW_TARGET:
            CHECK(c[i].target >= 0 && c[i].target < 256);
            if (c[i].target > 0 && c[i].target < 256) {
                CHECK(c[i].target_w > 0 && c[i].target_h > 0);
                drawn[c[i].target] = true;
            }
            break;
        default:
            break;
        }
    }
}

/* The first and last command drawn with pass k (-1: none). */
static void pass_span(const limen_draw_cmd *c, int n, int k, int *first, int *last)
{
    *first = *last = -1;
    for (int i = 0; i < n; i++)
        if (c[i].pass == k) {
            if (*first < 0)
                *first = i;
            *last = i;
        }
}

/* In the stencil method each nested view's pixels are marked (INVERT, in its parent's pass)
 * before the view draws, and, when the method counts depth, sealed (DECR back to the
 * parent's value) after it has drawn. */
static void check_stencil_order(const frame *f, bool counting)
{
    const limen_draw_cmd *c;
    const limen_draw_pass *p;
    int n = limen_drawlist_commands(f->dl, &c), np = limen_drawlist_passes(f->dl, &p);
    int nested = 0, decr = 0;
    for (int i = 0; i < n; i++)
        decr += c[i].state.stencil_pass == LIMEN_STENCIL_DECR;
    CHECK_MSG(counting ? decr > 0 : decr == 0, "%d seals", decr);
    for (int k = 1; k < np; k++) {
        int first, last;
        pass_span(c, n, k, &first, &last);
        const limen_view *v = limen_plan_view(f->p, p[k].view);
        if (first < 0 || !v || v->parent < 0)
            continue;
        nested++;
        int parent = -1;    /* the parent's pass: the last one of its view before this */
        for (int j = k - 1; j >= 0 && parent < 0; j--)
            if (p[j].view == v->parent)
                parent = j;
        CHECK(parent >= 0);
        int mark = -1, seal = -1;
        for (int i = 0; i < first; i++)
            if (c[i].pass == parent && c[i].op == LIMEN_DRAW_POLYGON &&
                c[i].state.stencil_pass == LIMEN_STENCIL_INVERT)
                mark = i;
        for (int i = last + 1; i < n && seal < 0; i++)
            if (c[i].pass == parent && c[i].op == LIMEN_DRAW_POLYGON &&
                c[i].state.stencil_pass == LIMEN_STENCIL_DECR)
                seal = i;
        CHECK_MSG(mark >= 0, "view %d: no mark before it draws", p[k].view);
        if (counting)
            CHECK_MSG(seal > last && c[seal].state.stencil_ref == (unsigned char)v->stencil,
                      "view %d: no seal after it drew", p[k].view);
        /* what the view shades passes only on its own value */
        for (int i = first; i <= last; i++)
            if (c[i].pass == k && c[i].op == LIMEN_DRAW_SHAPE)
                CHECK(c[i].state.stencil_test);
    }
    CHECK(nested > 0);
}

static void test_stencil_unique(void)
{
    frame f;
    frame_open(&f, mirror_box(), (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                                                 .depth = 2 } });
    int views = limen_plan_count(f.p);
    CHECK(views > 3 && views <= 255);
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .method = LIMEN_METHOD_STENCIL }));
    check_ranges(&f);
    check_stencil_order(&f, false);
    /* the first command clears the whole frame, stencil included */
    const limen_draw_cmd *c;
    limen_drawlist_commands(f.dl, &c);
    CHECK(c[0].op == LIMEN_DRAW_CLEAR && c[0].state.stencil_write_mask == 0xFF &&
          c[0].state.scissor[2] == W && c[0].state.scissor[3] == H);
    frame_close(&f);
}

static void test_stencil_counting(void)
{
    frame f;
    frame_open(&f, mirror_box(), (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                                                 .depth = 20 } });
    int views = limen_plan_count(f.p);
    CHECK_MSG(views > 255, "%d views", views);
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .method = LIMEN_METHOD_STENCIL }));
    check_ranges(&f);
    check_stencil_order(&f, true);
    /* a flush every 8 views marked */
    const limen_draw_cmd *c;
    int n = limen_drawlist_commands(f.dl, &c), flushes = 0;
    for (int i = 0; i < n; i++)
        flushes += c[i].op == LIMEN_DRAW_FLUSH;
    CHECK(flushes > 0 && flushes <= views / 8 + 1);
    frame_close(&f);
}

static void test_texture(void)
{
    frame f;
    frame_open(&f, mirror_box(), (limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_OVERRIDE,
                                                                 .depth = 2 } });
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .method = LIMEN_METHOD_TEXTURE,
                                                   .texture_scale = 0.5f }));
    check_ranges(&f);
    const limen_draw_cmd *c;
    int n = limen_drawlist_commands(f.dl, &c), targets = 0, images = 0;
    for (int i = 0; i < n; i++) {
        targets += c[i].op == LIMEN_DRAW_TARGET && c[i].target > 0;
        images += c[i].op == LIMEN_DRAW_POLYGON && c[i].image == LIMEN_IMAGE_TARGET;
        CHECK(!c[i].state.stencil_test);
        if (c[i].op == LIMEN_DRAW_TARGET && c[i].target > 0)
            CHECK(c[i].target_w == W / 2 && c[i].target_h == H / 2);
    }
    CHECK(targets > 0 && images > 0);
    frame_close(&f);
}

/* The depth tests as the range says: GREATER where the plain range says LESS. */
static void test_reversed(void)
{
    const limen_depth_range ranges[2] = { LIMEN_DEPTH_NO, LIMEN_DEPTH_ZO_REVERSED };
    for (int m = 0; m < 2; m++)
        for (int r = 0; r < 2; r++) {
            frame f;
            frame_open(&f, mirror_box(), (limen_plan_desc){ .range = ranges[r] });
            CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .method = m ? LIMEN_METHOD_TEXTURE
                                                                      : LIMEN_METHOD_STENCIL,
                                                           .range = ranges[r] }));
            const limen_draw_cmd *c;
            int n = limen_drawlist_commands(f.dl, &c), shapes = 0;
            for (int i = 0; i < n; i++) {
                limen_compare t = c[i].state.depth_test;
                if (c[i].op == LIMEN_DRAW_SHAPE && t != LIMEN_COMPARE_ALWAYS) {
                    shapes++;
                    CHECK_MSG(t == (r ? LIMEN_COMPARE_GREATER : LIMEN_COMPARE_LESS),
                              "range %d: a shape drawn with test %d", r, (int)t);
                }
                if (c[i].state.stencil_pass == LIMEN_STENCIL_INVERT)
                    CHECK(t == (r ? LIMEN_COMPARE_GEQUAL : LIMEN_COMPARE_LEQUAL));
                CHECK(t != (r ? LIMEN_COMPARE_LESS : LIMEN_COMPARE_GREATER));
            }
            CHECK(shapes > 0);
            frame_close(&f);
        }
}

/* 1,000 nodes of one mesh in a grid before the camera, rows dz apart. */
static limen_scene *statues(float dz)
{
    limen_scene *s = scene_with_camera((float[3]){ 0, 12, 24 }, (float[3]){ 0, 0, -16 * dz });
    for (int i = 0; i < 1000; i++) {
        limen_node m;
        CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, NULL, &m));
        CHECK_OK(limen_mesh_load(s, m, "scenes/data/bunny.obj"));
        CHECK_OK(limen_node_set_position(s, m, (float[3]){ (float)(i % 32) - 16, 0,
                                                           16 - (float)(i / 32) * dz }));
        CHECK_OK(limen_node_set_scale(s, m, (float[3]){ 0.07f, 0.07f, 0.07f }));
    }
    return s;
}

static void test_batches_and_budget(void)
{
    frame f;
    limen_limits full = { .lod_pixels = LIMEN_LOD_FULL };
    frame_open(&f, statues(1), (limen_plan_desc){ .limits = full });
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .limits = full }));
    check_ranges(&f);
    const limen_draw_cmd *c;
    const limen_drawable *items;
    limen_drawables_items(f.d, &items);
    int n = limen_drawlist_commands(f.dl, &c), meshes = 0, drawn = 0, item = -1;
    for (int i = 0; i < n; i++)
        if (c[i].op == LIMEN_DRAW_MESHES) {
            meshes++;
            drawn += c[i].count;
            item = c[i].item;
        }
    /* one geometry at one level: one batch, one command, every node an instance */
    CHECK_MSG(meshes == 1 && drawn > 500, "%d commands, %d instances", meshes, drawn);
    CHECK(limen_drawlist_instances(f.dl, NULL) == drawn);
    if (item < 0) {
        frame_close(&f);
        return;
    }
    /* the budget stops the camera's meshes: ten bunnies and a half */
    int64_t per = items[item].mesh->triangle_count;
    full.budget.triangles = per * 21 / 2;
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .limits = full }));
    n = limen_drawlist_commands(f.dl, &c), drawn = 0;
    for (int i = 0; i < n; i++)
        if (c[i].op == LIMEN_DRAW_MESHES)
            drawn += c[i].count;
    CHECK_MSG(drawn == 10, "%d instances under a budget of 10.5 meshes", drawn);
    /* with levels of detail the batches differ in level, and the budget runs over all of
     * them: what they draw stays within it, and fills it to within one mesh */
    frame_close(&f);
    frame_open(&f, statues(8), (limen_plan_desc){ 0 });
    limen_drawables_items(f.d, &items);
    int64_t tris = 0;
    for (int round = 0; round < 2; round++) {
        limen_limits levels = { .budget.triangles = round ? per * 3 : 0 };
        CHECK_OK(frame_list(&f, (limen_drawlist_desc){ .limits = levels }));
        n = limen_drawlist_commands(f.dl, &c), meshes = 0, tris = 0;
        for (int i = 0; i < n; i++)
            if (c[i].op == LIMEN_DRAW_MESHES) {
                const limen_mesh_geometry *g = items[c[i].item].mesh;
                meshes++;
                tris += (int64_t)c[i].count *
                        g->lods[c[i].lod < g->lod_count ? c[i].lod : 0].triangle_count;
            }
        if (!round)
            CHECK_MSG(meshes > 2 && tris > per * 3, "%d batches, %lld triangles", meshes,
                      (long long)tris);
    }
    CHECK_MSG(tris <= per * 3 && tris > per * 2, "%lld triangles under a budget of %lld",
              (long long)tris, (long long)(per * 3));
    frame_close(&f);
}

static void test_bad_input(void)
{
    limen_drawlist *dl = NULL;
    limen_plan *p = NULL;
    limen_drawables *d = NULL;
    CHECK_OK(limen_drawlist_create(&dl));
    CHECK_OK(limen_plan_create(&p));
    CHECK_OK(limen_drawables_create(&d));
    CHECK(limen_drawlist_build(dl, NULL, d, NULL) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_drawlist_error(dl), "plan") != NULL);
    CHECK(limen_drawlist_build(dl, p, d, NULL) == LIMEN_ERR_ARG);
    CHECK(strstr(limen_drawlist_error(dl), "not built") != NULL);
    CHECK(limen_drawlist_commands(dl, NULL) == 0);
    limen_scene *s = mirror_box();
    CHECK_OK(limen_plan_build(p, s, NULL));
    CHECK_OK(limen_drawables_build(d, s));
    CHECK(limen_drawlist_build(dl, p, NULL, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_drawlist_build(dl, p, d, &(limen_drawlist_desc){ .method = 7 }) == LIMEN_ERR_ARG);
    CHECK(limen_drawlist_build(dl, p, d, &(limen_drawlist_desc){ .texture_scale = 2 }) ==
          LIMEN_ERR_ARG);
    CHECK(limen_drawlist_build(dl, p, d, &(limen_drawlist_desc){ .width = -1 }) == LIMEN_ERR_ARG);
    /* the plan is for 640x480 and the plain depth range */
    CHECK(limen_drawlist_build(dl, p, d, &(limen_drawlist_desc){ .width = 320, .height = 240 }) ==
          LIMEN_ERR_ARG);
    CHECK(strstr(limen_drawlist_error(dl), "640x480") != NULL);
    CHECK(limen_drawlist_build(dl, p, d, &(limen_drawlist_desc){ .range = LIMEN_DEPTH_ZO }) ==
          LIMEN_ERR_ARG);
    CHECK(limen_drawlist_build(NULL, p, d, NULL) == LIMEN_ERR_ARG);
    CHECK(limen_drawlist_create(NULL) == LIMEN_ERR_ARG);
    CHECK_OK(limen_drawlist_build(dl, p, d, NULL));
    CHECK(limen_drawlist_error(dl)[0] == '\0');
    CHECK(limen_drawlist_commands(dl, NULL) > 0);
    limen_drawlist_destroy(NULL);
    limen_drawlist_destroy(dl);
    limen_drawables_destroy(d);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* A second build of the same frame gives the same list in the same memory. */
static void test_rebuild(void)
{
    frame f;
    frame_open(&f, mirror_box(), (limen_plan_desc){ 0 });
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ 0 }));
    const limen_draw_cmd *a, *b;
    const float (*va)[3], (*vb)[3];
    int n = limen_drawlist_commands(f.dl, &a), nv = limen_drawlist_vertices(f.dl, &va);
    limen_draw_cmd *copy = malloc(sizeof *copy * (size_t)n);
    if (copy && n)
        memcpy(copy, a, sizeof *copy * (size_t)n);
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ 0 }));
    CHECK(limen_drawlist_commands(f.dl, &b) == n && b == a);
    CHECK(limen_drawlist_vertices(f.dl, &vb) == nv && vb == va);
    CHECK(copy && memcmp(copy, b, sizeof *copy * (size_t)n) == 0);
    free(copy);
    frame_close(&f);
}

/* The lights that shade: the first LIMEN_MAX_LIGHTS visible ones, with 1/range^2. */
static void test_lights(void)
{
    limen_scene *s = mirror_box();
    for (int i = 0; i < LIMEN_MAX_LIGHTS + 2; i++) {
        limen_node l;
        CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, NULL, &l));
        CHECK_OK(limen_node_set_position(s, l, (float[3]){ (float)i, 2, 0 }));
        if (i == 0)
            CHECK_OK(limen_node_set_visible(s, l, 0));
        if (i == 1)
            CHECK_OK(limen_light_set_range(s, l, 4));
    }
    frame f;
    frame_open(&f, s, (limen_plan_desc){ 0 });
    CHECK_OK(frame_list(&f, (limen_drawlist_desc){ 0 }));
    const limen_draw_light *l;
    float ambient = -1;
    int n = limen_drawlist_lights(f.dl, &l, &ambient);
    CHECK(n == LIMEN_MAX_LIGHTS && ambient >= 0);
    if (n == LIMEN_MAX_LIGHTS) {
        CHECK(l[0].pos[0] == 1 && l[0].inv_range2 == 1.0f / 16);
        CHECK(l[1].pos[0] == 2 && l[1].inv_range2 == 0);
    }
    frame_close(&f);
}

/* The unit shapes' triangles every backend draws: made once; each level's indices within its
 * vertices; counter-clockwise from outside; a curved shape's vertices pushed out by its
 * level's error (the true surface halfway), errors growing as levels coarsen; uvs (a box
 * face's, a square's) over [0, 1]; NULL for no shape. */
static void test_unit_geometry(void)
{
    CHECK(!limen_unit_geometry(LIMEN_UNIT_NONE) && !limen_unit_geometry(LIMEN_UNIT_COUNT) &&
          !limen_unit_geometry((limen_unit_shape)-1));
    for (int u = LIMEN_UNIT_BOX; u < LIMEN_UNIT_COUNT; u++) {
        const limen_mesh_geometry *g = limen_unit_geometry((limen_unit_shape)u);
        CHECK(g && g == limen_unit_geometry((limen_unit_shape)u));
        if (!g)
            continue;
        bool curved = u == LIMEN_UNIT_BALL || u == LIMEN_UNIT_CYLINDER;
        CHECK(g->lod_count == (curved ? 11 : 1) && g->part_count == 1 && g->material_count == 1);
        CHECK(curved ? !g->uvs : g->uvs != NULL);
        for (int i = 0; g->uvs && i < 2 * g->vertex_count; i++)
            CHECK(g->uvs[i] >= 0 && g->uvs[i] <= 1);
        /* the centre whose direction to a face is outward: the origin, a cylinder's mid-axis */
        const float mid[3] = { 0, u == LIMEN_UNIT_CYLINDER ? 0.5f : 0, 0 };
        for (int k = 0; k < g->lod_count; k++) {
            const limen_mesh_lod *l = &g->lods[k];
            int inward = 0, outside = 0;
            CHECK(l->triangle_count > 0 && l->parts[0].triangle_count == l->triangle_count);
            CHECK(k == 0 || l->error > g->lods[k - 1].error);
            for (int t = 0; t < l->triangle_count; t++) {
                const float *p[3];
                for (int j = 0; j < 3; j++) {
                    uint32_t vi = l->indices[3 * t + j];
                    CHECK(vi < (uint32_t)g->vertex_count);
                    p[j] = g->positions + 3 * (vi < (uint32_t)g->vertex_count ? vi : 0);
                }
                float e1[3], e2[3], n[3], c[3];
                for (int a = 0; a < 3; a++)
                    e1[a] = p[1][a] - p[0][a], e2[a] = p[2][a] - p[0][a],
                    c[a] = (p[0][a] + p[1][a] + p[2][a]) / 3 - mid[a];
                n[0] = e1[1] * e2[2] - e1[2] * e2[1];
                n[1] = e1[2] * e2[0] - e1[0] * e2[2];
                n[2] = e1[0] * e2[1] - e1[1] * e2[0];
                if (u == LIMEN_UNIT_SQUARE)
                    c[0] = c[1] = 0, c[2] = 1;      /* facing +Z */
                inward += n[0] * c[0] + n[1] * c[1] + n[2] * c[2] <= 0;
            }
            /* a ball's vertices at 1 + error; a cylinder's rim the same, off its axis */
            for (int t = 0; curved && t < 3 * l->triangle_count; t++) {
                const float *q = g->positions + 3 * l->indices[t];
                float r = sqrtf(q[0] * q[0] + q[2] * q[2] +
                                (u == LIMEN_UNIT_BALL ? q[1] * q[1] : 0));
                outside += r > 1e-6f && fabsf(r - (1 + l->error)) > 1e-5f;
            }
            CHECK_MSG(!inward && !outside, "unit %d level %d: %d faces inward, %d vertices off "
                      "1 + error (%g)", u, k, inward, outside, l->error);
        }
    }
}

static void test_defaults(void)
{
    limen_drawlist_desc d = limen_drawlist_desc_defaults(NULL);
    CHECK(d.texture_scale == 1.0f && d.method == LIMEN_METHOD_STENCIL);
    CHECK(d.limits.budget.triangles == LIMEN_BUDGET_TRIANGLES_DEFAULT);
    d = limen_drawlist_desc_defaults(&(limen_drawlist_desc){ .method = LIMEN_METHOD_NAIVE,
                                                             .texture_scale = 0.5f });
    CHECK(d.texture_scale == 1.0f);
}

static const check_case cases[] = {
    { "stencil_unique", test_stencil_unique },
    { "stencil_counting", test_stencil_counting },
    { "texture", test_texture },
    { "reversed", test_reversed },
    { "batches_and_budget", test_batches_and_budget },
    { "bad_input", test_bad_input },
    { "rebuild", test_rebuild },
    { "lights", test_lights },
    { "defaults", test_defaults },
    { "unit_geometry", test_unit_geometry },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
