/* test_scale.c - the spatial index changes what is tested, never what is found: plans
 * (views, matrices, surfaces, clones) and traced images are the same with the index as
 * with the scan of everything it replaces (the gallery, random scenes, scenes being edited),
 * world matrices recomputed for what moved equal a full recompute, and the counts of tests
 * show the cost following what a view sees rather than what the scene holds. No timing. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/index.h"
#include "core/internal.h"
#include "core/plan.h"
#include "hall.h"
#include "limen.h"
#include "load.h"

static const char *GALLERY[] = {
    "scenes/plain.lua",        "scenes/mirror_room.lua", "scenes/corridor.lua",
    "scenes/kaleidoscope.lua", "scenes/periscope.lua",   "scenes/water.lua",
    "scenes/portals.lua",      "scenes/tunnel.lua",      "scenes/portal_mirror.lua",
    "scenes/portal_sizes.lua", "scenes/moving_portal.lua", "scenes/flythrough.lua", NULL,
};

/* ------------------------------------------------------------------ comparing */

/* Plans the scene with the index and without it; the two must agree in every field. */
static int check_same_plan(limen_scene *s, const limen_plan_desc *d, const char *what)
{
    limen_plan *a = NULL, *b = NULL;
    limen_plan_create(&a);
    limen_plan_create(&b);
    s->brute_force = false;
    limen_status sa = limen_plan_build(a, s, d);
    s->brute_force = true;
    limen_status sb = limen_plan_build(b, s, d);
    s->brute_force = false;
    CHECK_MSG(sa == sb, "%s: status %d with the index, %d without", what, sa, sb);
    int bad = 0;
    if (!sa && !sb) {
        bad |= limen_plan_count(a) != limen_plan_count(b);
        bad |= limen_plan_truncated(a) != limen_plan_truncated(b);
        for (int i = 0; !bad && i < limen_plan_count(a); i++) {
            bad |= memcmp(limen_plan_view(a, i), limen_plan_view(b, i), sizeof(limen_view)) != 0;
            const limen_view_surface *va, *vb;
            int na = limen_plan_view_surfaces(a, i, &va), nb = limen_plan_view_surfaces(b, i, &vb);
            bad |= na != nb || (na && memcmp(va, vb, sizeof *va * (size_t)na) != 0);
        }
        const limen_clone *ca, *cb;
        int na = limen_plan_clones(a, &ca), nb = limen_plan_clones(b, &cb);
        bad |= na != nb || (na && memcmp(ca, cb, sizeof *ca * (size_t)na) != 0);
        CHECK_MSG(!bad, "%s: the plans differ (%d views with the index, %d without)", what,
                  limen_plan_count(a), limen_plan_count(b));
    }
    int views = limen_plan_count(a);
    limen_plan_destroy(a);
    limen_plan_destroy(b);
    return views;
}

/* Traces with the index and without it: the same bytes. */
static void check_same_trace(limen_scene *s, int w, int h, const char *what)
{
    unsigned char *a = malloc((size_t)w * h * 3), *b = malloc((size_t)w * h * 3);
    limen_trace_desc d = { .width = w, .height = h, .threads = 2 };
    s->brute_force = false;
    CHECK_OK(limen_trace_image(s, &d, a));
    s->brute_force = true;
    CHECK_OK(limen_trace_image(s, &d, b));
    s->brute_force = false;
    long differ = 0;
    for (long i = 0; i < (long)w * h * 3; i++)
        differ += a[i] != b[i];
    CHECK_MSG(differ == 0, "%s: %ld bytes differ between the traces", what, differ);
    free(a);
    free(b);
}

/* World matrices as the refresh left them against a recompute of every node. */
static void check_worlds(limen_scene *s, const char *what)
{
    limen__scene_refresh(s);
    int n = s->cap, bad = 0;
    float (*kept)[16] = malloc(sizeof *kept * (size_t)n);
    for (int i = 0; i < n; i++)
        memcpy(kept[i], &s->nodes[i].world[0][0], sizeof kept[i]);
    s->all_stale = true;
    s->dirty = true;
    limen__scene_refresh(s);
    for (int i = 0; i < n; i++)
        if (limen__alive(&s->nodes[i]))
            bad += memcmp(kept[i], &s->nodes[i].world[0][0], sizeof kept[i]) != 0;
    CHECK_MSG(bad == 0, "%s: %d world matrices differ from a full recompute", what, bad);
    free(kept);
}

/* ------------------------------------------------------------------ random scenes */

static unsigned long long rng = 1;

static float uni(float a, float b)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return a + (b - a) * (float)((rng >> 11) * (1.0 / 9007199254740992.0));
}

static limen_node add(limen_scene *s, limen_node_kind kind, float x, float y, float z)
{
    limen_node n = { 0 };
    limen_node_create(s, kind, NULL, &n);
    limen_node_set_position(s, n, (float[3]){ x, y, z });
    limen_node_set_rotation(s, n, (float[3]){ uni(-3, 3), uni(-3, 3), uni(-3, 3) });
    return n;
}

/* Mirrors, linked portals and shapes at random in a box, some under rotated and scaled
 * groups (shears), some hidden, a camera inside. */
static limen_scene *random_scene(unsigned long long seed, int shapes, int surfaces)
{
    rng = seed;
    limen_scene *s = NULL;
    limen_scene_create(&(limen_scene_desc){ .max_nodes = 4096 }, &s);
    limen_node groups[4];
    for (int g = 0; g < 4; g++) {
        groups[g] = add(s, LIMEN_NODE_GROUP, uni(-2, 2), uni(-2, 2), uni(-2, 2));
        limen_node_set_scale(s, groups[g], (float[3]){ uni(0.5f, 2), uni(0.5f, 2), uni(0.5f, 2) });
        if (g)
            limen_node_set_parent(s, groups[g], groups[g - 1]);
    }
    limen_node prev = { 0 };
    for (int i = 0; i < surfaces; i++) {
        bool portal = i % 3 != 0;
        limen_node n = add(s, portal ? LIMEN_NODE_PORTAL : LIMEN_NODE_MIRROR, uni(-8, 8),
                           uni(-8, 8), uni(-8, 8));
        float w = uni(1, 4);
        limen_node_set_dims(s, n, (float[3]){ w, portal ? w * 0.75f : uni(1, 4), 0 });
        if (portal && prev.id) {
            limen_portal_link(s, prev, n);
            prev.id = 0;
        } else if (portal) {
            prev = n;
        }
    }
    static const limen_node_kind kinds[] = { LIMEN_NODE_BOX, LIMEN_NODE_SPHERE,
                                             LIMEN_NODE_CYLINDER, LIMEN_NODE_QUAD };
    for (int i = 0; i < shapes; i++) {
        limen_node n = add(s, kinds[i % 4], uni(-8, 8), uni(-8, 8), uni(-8, 8));
        limen_node_set_dims(s, n, (float[3]){ uni(0.1f, 1), uni(0.1f, 1), uni(0.1f, 1) });
        limen_node_set_color(s, n, (float[3]){ uni(0, 1), uni(0, 1), uni(0, 1) });
        if (i % 5 == 0)
            limen_node_set_parent(s, n, groups[i % 4]);
        if (i % 11 == 0)
            limen_node_set_visible(s, n, 0);
    }
    limen_node light = add(s, LIMEN_NODE_LIGHT, 3, 6, 3);
    limen_node_set_color(s, light, (float[3]){ 1, 1, 1 });
    limen_node cam = add(s, LIMEN_NODE_CAMERA, 0, 0, 0);
    limen_node_look_at(s, cam, (float[3]){ uni(-3, 3), uni(-3, 3), 9 }, (float[3]){ 0, 0, 0 },
                       (float[3]){ 0, 1, 0 });
    limen_scene_set_camera(s, cam);
    return s;
}

/* ------------------------------------------------------------------ tests */

static void test_gallery_same(void)
{
    for (const char **g = GALLERY; *g; g++) {
        limen_script *sc = check_load_script(*g);
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        check_same_plan(s, NULL, *g);
        check_same_plan(s, &(limen_plan_desc){ .width = 320, .height = 240, .cull = LIMEN_CULL_FRUSTUM }, *g);
        check_same_plan(s, &(limen_plan_desc){ .limits.max_views = 7 }, *g);
        check_same_trace(s, 96, 72, *g);
        if (limen_script_animated(sc)) {
            for (int k = 1; k <= 3; k++) {
                CHECK_OK(limen_script_update(sc, 0.7 * k));
                check_same_plan(s, NULL, *g);
                check_worlds(s, *g);
            }
            check_same_trace(s, 96, 72, *g);
        }
        limen_script_destroy(sc);
    }
}

static void test_random_same(void)
{
    for (unsigned long long seed = 1; seed <= 12; seed++) {
        char what[64];
        snprintf(what, sizeof what, "random scene %llu", seed);
        limen_scene *s = random_scene(seed, 60 + 20 * (int)seed, 6 + (int)seed);
        check_same_plan(s, NULL, what);
        check_same_plan(s, &(limen_plan_desc){ .limits = { .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = 3 } }, what);
        check_worlds(s, what);
        if (seed <= 4)
            check_same_trace(s, 64, 48, what);
        limen_scene_destroy(s);
    }
}

/* Edits between plans: moves (refits), reparenting (subtrees), creation and destruction
 * (rebuilds), resizing; after each, the same plan and images as the full scans, and the
 * same world matrices as a full recompute. */
static void test_edits_same(void)
{
    limen_scene *s = random_scene(99, 150, 12);
    limen_node all[512];
    int n = limen_scene_nodes(s, all, 512);
    check_same_plan(s, NULL, "before edits");
    for (int round = 0; round < 12; round++) {
        char what[64];
        snprintf(what, sizeof what, "edit round %d", round);
        for (int k = 0; k < 20; k++) {
            limen_node x = all[(int)uni(0, (float)n - 0.01f)];
            if (!limen_node_valid(s, x))
                continue;
            limen_node_kind kind = limen_node_get_kind(s, x);
            if (kind == LIMEN_NODE_CAMERA)
                continue;
            switch (k % 5) {
            case 0:
                limen_node_set_position(s, x, (float[3]){ uni(-8, 8), uni(-8, 8), uni(-8, 8) });
                break;
            case 1: {
                limen_move_result mr;
                limen_node_move(s, x, (float[3]){ uni(-1, 1), uni(-1, 1), uni(-1, 1) }, &mr);
                break;
            }
            case 2: {
                limen_node p = all[(int)uni(0, (float)n - 0.01f)];
                if (limen_node_set_parent(s, x, p))
                    limen_node_set_parent(s, x, (limen_node){ 0 });
                break;
            }
            case 3:
                if (kind != LIMEN_NODE_GROUP && kind != LIMEN_NODE_LIGHT)
                    limen_node_set_dims(s, x, (float[3]){ uni(0.5f, 2), uni(0.5f, 2), 1 });
                break;
            default:
                if (round % 3 == 0 && kind != LIMEN_NODE_GROUP) {
                    limen_node_destroy(s, x);
                    limen_node fresh = add(s, LIMEN_NODE_SPHERE, uni(-6, 6), uni(-6, 6), 0);
                    for (int i = 0; i < n; i++)
                        if (all[i].id == x.id)
                            all[i] = fresh;
                } else {
                    limen_node_set_rotation(s, x, (float[3]){ uni(-3, 3), uni(-3, 3), 0 });
                }
            }
        }
        check_same_plan(s, NULL, what);
        check_worlds(s, what);
        if (round % 4 == 3)
            check_same_trace(s, 64, 48, what);
    }
    limen_scene_destroy(s);
}

/* Plans the hall; returns the exact surface tests per view, and the straddling tests, the
 * views and the surfaces those views found. */
static double hall_tests(int spheres, int pairs, bool brute, long *straddle_tests, int *views,
                         double *found)
{
    limen_scene *s = hall_create(spheres, pairs, 3);
    limen_plan *p = NULL;
    limen_plan_create(&p);
    s->brute_force = brute;
    CHECK_OK(limen_plan_build(p, s, NULL));
    *views = limen_plan_count(p);
    *straddle_tests = s->straddle_tests;
    double per_view = (double)p->surface_tests / *views;
    *found = (double)p->nview_surfaces / *views;
    limen_plan_destroy(p);
    limen_scene_destroy(s);
    return per_view;
}

static void test_cost_follows_visibility(void)
{
    long st_small, st_big, st_brute;
    int v_small, v_big, v_brute;
    double f_small, f_big, f_brute;
    /* 16 times the surfaces (the hall 16 times as long): every view still tests every
     * surface without the index; with it, about those the view finds */
    double small = hall_tests(200, 10, false, &st_small, &v_small, &f_small);
    double big = hall_tests(200, 160, false, &st_big, &v_big, &f_big);
    double brute = hall_tests(200, 160, true, &st_brute, &v_brute, &f_brute);
    CHECK_MSG(brute >= 319, "without the index every view tests every surface (%g)", brute);
    CHECK(v_big == v_brute && f_big == f_brute);
    /* the longer hall shows more portals, many of them under a pixel far away (which the
     * exact test rejects): the tests grow, but by less than half as much as the surfaces */
    CHECK_MSG(big < 8 * small, "surface tests per view: %g (finding %g) with 20 surfaces, %g "
              "(finding %g) with 320", small, f_small, big, f_big);
    CHECK_MSG(big < brute / 16, "surface tests per view: %g with the index, %g without", big,
              brute);
    /* 16 times the spheres: the straddling tests are a small share of the shapes, where the
     * scan tests every shape against every portal */
    hall_tests(1000, 50, false, &st_small, &v_small, &f_small);
    hall_tests(16000, 50, false, &st_big, &v_big, &f_big);
    CHECK_MSG(st_big < 16000 / 10, "straddling tests: %ld for 16,000 spheres", st_big);
    CHECK_MSG(st_big <= 32 * (st_small + 1), "straddling tests: %ld for 1,000, %ld for 16,000",
              st_small, st_big);
    CHECK(v_small == v_big);
}

/* The shapes listed for a view: every sphere whose centre shows inside the view's scissor
 * rectangle, in front of its clip plane, is there; through a portal far fewer than all. */
static void test_view_things(void)
{
    limen_scene *s = hall_create(4000, 50, 5);
    limen_plan *p = NULL;
    limen_plan_create(&p);
    CHECK_OK(limen_plan_build(p, s, NULL));
    int narrow = 0;
    for (int i = 0; i < limen_plan_count(p); i++) {
        const limen_view *v = limen_plan_view(p, i);
        const limen_node *things;
        int n = limen_plan_things(p, i, &things);
        CHECK(n >= 0 && n <= 4000);
        if (v->depth > 0 && n < 1000)
            narrow++;
        int missing = 0;
        for (int k = 0; k < s->cap; k++) {
            const limen__node *nd = &s->nodes[k];
            if (!limen__alive(nd) || nd->kind != LIMEN_NODE_SPHERE)
                continue;
            const float *c = nd->world[3];
            float e[4], cl[4];
            for (int r = 0; r < 4; r++)
                e[r] = v->view[r] * c[0] + v->view[4 + r] * c[1] + v->view[8 + r] * c[2] +
                       v->view[12 + r];
            for (int r = 0; r < 4; r++)
                cl[r] = v->proj[r] * e[0] + v->proj[4 + r] * e[1] + v->proj[8 + r] * e[2] +
                        v->proj[12 + r] * e[3];
            if (!(cl[3] > 0.01f))
                continue;
            float px = (cl[0] / cl[3] + 1) * 0.5f * 640, py = (cl[1] / cl[3] + 1) * 0.5f * 480;
            const int *sc = v->scissor;
            if (px < sc[0] || px > sc[0] + sc[2] || py < sc[1] || py > sc[1] + sc[3])
                continue;
            if (v->depth > 0 && v->clip_plane[0] * c[0] + v->clip_plane[1] * c[1] +
                                        v->clip_plane[2] * c[2] + v->clip_plane[3] < 0)
                continue;
            limen_node h = limen__node_handle(s, k);
            bool found = false;
            for (int j = 0; j < n && !found; j++)
                found = things[j].id == h.id;
            missing += !found;
        }
        CHECK_MSG(missing == 0, "view %d: %d spheres in sight not listed", i, missing);
    }
    CHECK_MSG(narrow > limen_plan_count(p) / 2, "views through portals listing few shapes: %d "
              "of %d", narrow, limen_plan_count(p));
    const limen_node *none;
    CHECK(limen_plan_things(p, limen_plan_count(p), &none) == 0 && none == NULL);
    limen_plan_destroy(p);
    limen_scene_destroy(s);
}

/* A hall with shapes straddling its portals: the same clones and images both ways. */
static void test_hall_same(void)
{
    limen_scene *s = hall_create(3000, 20, 9);
    int views = check_same_plan(s, NULL, "hall");
    CHECK(views > 20);
    limen_plan *p = NULL;
    limen_plan_create(&p);
    CHECK_OK(limen_plan_build(p, s, NULL));
    const limen_clone *c;
    CHECK_MSG(limen_plan_clones(p, &c) > 5, "the hall should have spheres through its portals");
    limen_plan_destroy(p);
    check_same_trace(s, 120, 90, "hall");
    limen_scene_destroy(s);
}

/* ------------------------------------------------------------------ churn */

/* Every leaf of the tree: parents that point back, boxes that hold their children and
 * items, heights, and items that know their leaf. Returns the items found. */
static int check_subtree(const limen__bvh *b, int at, int parent, int depth, int *bad)
{
    const limen__bvh_node *nd = &b->nodes[at];
    *bad += nd->parent != parent || depth > 100;
    int items = 0;
    if (nd->count > 0) {
        *bad += nd->height != 0;
        for (int i = 0; i < nd->count; i++) {
            int id = b->order[nd->first + i];
            if (id < 0 || !limen__bvh_holds(b, id) || b->leaf[id] != at) {
                (*bad)++;
                continue;
            }
            items++;
            for (int k = 0; k < 3; k++)
                *bad += b->boxes[id].lo[k] < nd->box.lo[k] || b->boxes[id].hi[k] > nd->box.hi[k];
        }
        return items;
    }
    *bad += nd->count < 0;
    if (nd->count < 0)
        return 0;
    int l = nd->first;
    items = check_subtree(b, l, at, depth + 1, bad) + check_subtree(b, l + 1, at, depth + 1, bad);
    int h = b->nodes[l].height > b->nodes[l + 1].height ? b->nodes[l].height
                                                          : b->nodes[l + 1].height;
    *bad += nd->height != h + 1;
    for (int c = 0; c < 2; c++)
        for (int k = 0; k < 3; k++)
            *bad += b->nodes[l + c].box.lo[k] < nd->box.lo[k] ||
                    b->nodes[l + c].box.hi[k] > nd->box.hi[k];
    return items;
}

static int cmp_slot(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* What the tree answers against a scan of the live nodes it should hold (ascending slots). */
static int sorted_query(const limen__bvh *b, const double (*pl)[4], int np, const limen__box *q,
                        int **out, int *cap)
{
    int n = 0;
    if (q ? limen__bvh_query_box(b, q, out, &n, cap, NULL) < 0
          : limen__bvh_query_planes(b, pl, np, 0, out, &n, cap, NULL) < 0)
        return -1;
    if (n > 1)
        qsort(*out, (size_t)n, sizeof **out, cmp_slot);
    return n;
}

/* The index against the scene: each tree holds exactly the live shapes (surfaces), with the
 * boxes they have now; its plane and box queries find what a scan of them finds; the portal
 * and surface lists are the live ones, ascending. */
static void check_index(limen_scene *s, const char *what)
{
    limen__spatial *x = limen__scene_index(s);
    CHECK_MSG(x != NULL, "%s: no index", what);
    if (!x)
        return;
    const limen__bvh *trees[2] = { limen__index_shapes(x), limen__index_surfaces(x) };
    int bad = 0, held[2] = { 0, 0 };
    size_t cap_ints = sizeof(int) * (size_t)s->cap;
    int *want = malloc(cap_ints), *port = malloc(cap_ints), *surf = malloc(cap_ints);
    int np = 0, ns = 0;
    limen__box *boxes = malloc(sizeof *boxes * (size_t)s->cap);
    for (int k = 0; k < s->cap; k++) {
        const limen__node *n = &s->nodes[k];
        bool alive = limen__alive(n), surface = alive && limen__is_surface(n);
        bool shape = alive && !surface && n->kind != LIMEN_NODE_GROUP &&
                     n->kind != LIMEN_NODE_LIGHT && n->kind != LIMEN_NODE_CAMERA;
        want[k] = shape ? 0 : surface ? 1 : -1;
        if (surface)
            surf[ns++] = k;
        if (surface && n->kind == LIMEN_NODE_PORTAL)
            port[np++] = k;
        if (want[k] < 0)
            continue;
        limen__node_box(n, &boxes[k]);
        held[want[k]]++;
        const limen__bvh *b = trees[want[k]];
        bad += !limen__bvh_holds(b, k) || memcmp(&b->boxes[k], &boxes[k], sizeof boxes[k]);
    }
    for (int t = 0; t < 2; t++) {
        for (int k = 0; k < s->cap; k++)
            bad += want[k] != t && limen__bvh_holds(trees[t], k);
        int found = trees[t]->nnodes ? check_subtree(trees[t], 0, -1, 0, &bad) : 0;
        bad += found != held[t] || trees[t]->nitems != held[t];
    }
    CHECK_MSG(bad == 0, "%s: the trees do not hold the live nodes as they are (%d faults)", what,
              bad);
    const int *list;
    int n = limen__index_portals(x, &list);
    CHECK_MSG(n == np && (!n || !memcmp(list, port, sizeof *port * (size_t)n)),
              "%s: the portal list differs from the live portals", what);
    n = limen__index_surface_slots(x, &list);
    CHECK_MSG(n == ns && (!n || !memcmp(list, surf, sizeof *surf * (size_t)n)),
              "%s: the surface list differs from the live surfaces", what);
    /* queries: frusta at random, boxes at random and the portals' */
    int *got = NULL, cap = 0, wrong = 0;
    for (int q = 0; q < 12; q++) {
        double pl[5][4];
        limen__box box;
        int npl = 1 + q % 5;
        for (int i = 0; i < npl; i++) {
            for (int k = 0; k < 3; k++)
                pl[i][k] = uni(-1, 1);
            pl[i][3] = uni(-4, 4);
        }
        if (q < 6) {
            for (int k = 0; k < 3; k++) {
                double c = uni(-9, 9), e = uni(0, 5);
                box.lo[k] = c - e;
                box.hi[k] = c + e;
            }
        } else if (np) {
            limen__node_box(&s->nodes[port[q % np]], &box);
        }
        const limen__box *qb = q < 6 || np ? &box : NULL;
        for (int t = 0; t < 2; t++) {
            int m = sorted_query(trees[t], (const double(*)[4])pl, npl, qb, &got, &cap);
            int j = 0;
            for (int k = 0; k < s->cap && m >= 0; k++) {
                if (want[k] != t ||
                    (qb ? !limen__box_meets(&boxes[k], qb)
                        : limen__box_outside(&boxes[k], (const double(*)[4])pl, npl, 0)))
                    continue;
                wrong += j >= m || got[j] != k;
                j++;
            }
            wrong += m < 0 || j != m;
        }
    }
    CHECK_MSG(wrong == 0, "%s: %d query answers differ from a scan of the live nodes", what,
              wrong);
    free(got);
    free(want);
    free(port);
    free(surf);
    free(boxes);
}

/* A scene like s, made afresh: its live nodes created in ascending slot order (so the new
 * slots keep their order), with the same names, kinds, transforms, sizes, visibility,
 * parents, partners and camera. */
static limen_scene *copy_scene(limen_scene *s, const float eye[3])
{
    limen_scene *c = NULL;
    limen_scene_create(&(limen_scene_desc){ .max_nodes = 4096 }, &c);
    limen_node *to = calloc((size_t)s->cap, sizeof *to);
    for (int k = 0; k < s->cap; k++) {
        const limen__node *n = &s->nodes[k];
        if (!limen__alive(n))
            continue;
        CHECK_OK(limen_node_create(c, n->kind, n->name, &to[k]));
        if (n->kind == LIMEN_NODE_CAMERA) {
            limen_node_look_at(c, to[k], eye, (float[3]){ 0, 0, 0 }, (float[3]){ 0, 1, 0 });
            limen_scene_set_camera(c, to[k]);
            continue;
        }
        limen_node_set_position(c, to[k], n->pos);
        limen_node_set_rotation(c, to[k], n->euler);
        limen_node_set_scale(c, to[k], n->scale);
        limen_node_set_color(c, to[k], n->color);
        limen_node_set_visible(c, to[k], n->visible);
        if (n->kind != LIMEN_NODE_GROUP && n->kind != LIMEN_NODE_LIGHT)
            CHECK_OK(limen_node_set_dims(c, to[k], n->dims));
    }
    for (int k = 0; k < s->cap; k++) {
        const limen__node *n = &s->nodes[k];
        if (!limen__alive(n))
            continue;
        if (n->parent)
            CHECK_OK(limen_node_set_parent(c, to[k], to[n->parent - 1]));
        if (n->pair && (int)n->pair - 1 > k)
            CHECK_OK(limen_portal_link(c, to[k], to[n->pair - 1]));
    }
    free(to);
    return c;
}

static int cmp_line(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Sorts the lines of text after `from`, each without its trailing comma: the clones, which
 * the plan lists in the order the nodes were created (which a copy made in slot order does
 * not keep), one a line. */
static void sort_lines(char *text, const char *from)
{
    char *at = strstr(text, from);
    if (!at)
        return;
    at += strlen(from);
    char *lines[4096], *copy = strdup(at);
    int n = 0;
    for (char *l = strtok(copy, "\n"); l && n < 4096; l = strtok(NULL, "\n")) {
        size_t len = strlen(l);
        if (len && l[len - 1] == ',')
            l[len - 1] = 0;
        lines[n++] = l;
    }
    qsort(lines, (size_t)n, sizeof *lines, cmp_line);
    for (int i = 0; i < n; i++)
        at += sprintf(at, "%s\n", lines[i]);
    free(copy);
}

/* The plan's JSON (names, not slots), through a temporary file, its clones sorted;
 * malloc'd. Adds its views and clones to *seen. */
static char *plan_text(limen_scene *s, long seen[2])
{
    limen_plan *p = NULL;
    limen_plan_create(&p);
    limen_status st = limen_plan_build(p, s, &(limen_plan_desc){ .width = 160, .height = 120 });
    CHECK_MSG(st == LIMEN_OK, "plan: %s", limen_scene_error(s));
    const limen_clone *clones;
    seen[0] += limen_plan_count(p);
    seen[1] += limen_plan_clones(p, &clones);
    /* in memory where there is a /dev/shm: the file is flushed to its disk */
    char path[64];
    snprintf(path, sizeof path, "%s/limen-churn-XXXXXX",
             access("/dev/shm", W_OK) ? "/tmp" : "/dev/shm");
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0)
        close(fd);
    CHECK_OK(limen_plan_write_json(p, s, path));
    limen_plan_destroy(p);
    FILE *f = fopen(path, "rb");
    char *text = calloc(1 << 20, 1);
    if (f && text)
        CHECK(fread(text, 1, (1 << 20) - 1, f) < (1 << 20) - 1);
    if (f)
        fclose(f);
    remove(path);
    if (text)
        sort_lines(text, "\"clones\": [");
    return text;
}

/* Nodes created, destroyed, moved, re-parented, resized, hidden and shown at random, with
 * bursts (a third destroyed at once, fifty created at once): after every step the index
 * holds exactly the live nodes as they are, its queries find what a scan finds, and the plan
 * is the plan of the same scene made afresh; now and then the traces with and without the
 * index are the same bytes (the tracer's Embree copy follows the trees). The changes go in
 * as leaves: far fewer full builds than changes. */
static void test_churn_same(void)
{
    rng = 2024;
    limen_scene *s = NULL;
    limen_scene_create(&(limen_scene_desc){ .max_nodes = 4096 }, &s);
    const float eye[3] = { 1, 2, 14 };
    limen_node cam = add(s, LIMEN_NODE_CAMERA, 0, 0, 0);
    limen_node_look_at(s, cam, eye, (float[3]){ 0, 0, 0 }, (float[3]){ 0, 1, 0 });
    limen_scene_set_camera(s, cam);
    limen_node light = add(s, LIMEN_NODE_LIGHT, 3, 6, 3);
    limen_node_set_color(s, light, (float[3]){ 1, 1, 1 });
    int made = 0, changes = 0;
    static const limen_node_kind kinds[] = {
        LIMEN_NODE_SPHERE, LIMEN_NODE_BOX,    LIMEN_NODE_CYLINDER, LIMEN_NODE_QUAD,
        LIMEN_NODE_SPHERE, LIMEN_NODE_MIRROR, LIMEN_NODE_PORTAL,   LIMEN_NODE_GROUP,
    };
    limen_node *live = malloc(sizeof *live * 4096);
    char what[64];
    long builds = -1, seen[2] = { 0, 0 };
    for (int step = 0; step < 400; step++) {
        int n = limen_scene_nodes(s, live, 4096);
        int op = step == 150 ? 8 : step == 300 ? 9 : n < 40 ? 0 : (int)uni(0, 7.99f);
        limen_node x = live[(int)uni(0, (float)n - 0.01f)];
        limen_node_kind kind = limen_node_get_kind(s, x);
        bool fixed = kind == LIMEN_NODE_CAMERA || kind == LIMEN_NODE_LIGHT;
        if (op == 0 || op == 1 || op == 9) {   /* create (fifty at step 300) */
            for (int i = 0; i < (op == 9 ? 50 : 1); i++) {
                limen_node_kind k = kinds[(int)uni(0, 7.99f)];
                snprintf(what, sizeof what, "n%d", made++);
                limen_node m = { 0 };
                CHECK_OK(limen_node_create(s, k, what, &m));
                limen_node_set_position(s, m, (float[3]){ uni(-6, 6), uni(-6, 6), uni(-6, 6) });
                limen_node_set_rotation(s, m, (float[3]){ uni(-3, 3), uni(-3, 3), uni(-3, 3) });
                if (k == LIMEN_NODE_PORTAL) {   /* linked to one left unpaired */
                    float w = uni(2, 6);
                    limen_node_set_dims(s, m, (float[3]){ w, 0.75f * w, 0 });
                    for (int j = 0; j < n; j++)
                        if (limen_node_get_kind(s, live[j]) == LIMEN_NODE_PORTAL &&
                            !limen_portal_get_partner(s, live[j]).id &&
                            limen_portal_link(s, m, live[j]) == LIMEN_OK)
                            break;
                } else if (k != LIMEN_NODE_GROUP) {
                    limen_node_set_dims(s, m,
                                        (float[3]){ uni(0.3f, 2), uni(0.3f, 2), uni(0.3f, 2) });
                }
                if (uni(0, 1) < 0.3f)
                    limen_node_set_parent(s, m, live[(int)uni(0, (float)n - 0.01f)]);
                changes++;
            }
        } else if (op == 2 || op == 8) {    /* destroy (a third at step 150) */
            for (int i = 0; i < (op == 8 ? n / 3 : 1); i++) {
                limen_node y = op == 8 ? live[(i * 3 + 1) % n] : x;
                limen_node_kind k = limen_node_get_kind(s, y);
                if (k != LIMEN_NODE_CAMERA && k != LIMEN_NODE_LIGHT &&
                    limen_node_destroy(s, y) == LIMEN_OK)
                    changes++;
            }
        } else if (fixed) {
            continue;
        } else if (op == 3) {
            limen_node_set_position(s, x, (float[3]){ uni(-6, 6), uni(-6, 6), uni(-6, 6) });
        } else if (op == 4) {
            limen_node p = live[(int)uni(0, (float)n - 0.01f)];
            if (uni(0, 1) < 0.3f)
                p.id = 0;
            limen_node_set_parent(s, x, p);     /* refused where it makes a cycle */
        } else if (op == 5) {
            limen_node_set_visible(s, x, !limen_node_get_visible(s, x));
        } else if (op == 6 && kind != LIMEN_NODE_GROUP && kind != LIMEN_NODE_PORTAL) {
            limen_node_set_dims(s, x, (float[3]){ uni(0.3f, 3), uni(0.3f, 3), uni(0.3f, 3) });
        } else {
            float k = uni(0.5f, 2);     /* uniform: linked portals keep their shapes */
            limen_node_set_scale(s, x, (float[3]){ k, k, k });
        }
        snprintf(what, sizeof what, "churn step %d", step);
        check_index(s, what);
        if (builds < 0 && step >= 5) {
            /* one node more: its leaf goes in, the trees are not built again */
            long before = limen__index_builds(limen__scene_index(s));
            limen_node m = add(s, LIMEN_NODE_SPHERE, 0, 0, 0);
            check_index(s, "one sphere created");
            CHECK_MSG(limen__index_builds(limen__scene_index(s)) == before,
                      "one node created rebuilt the index");
            limen_node_destroy(s, m);
            check_index(s, "that sphere destroyed");
            CHECK_MSG(limen__index_builds(limen__scene_index(s)) == before,
                      "one node destroyed rebuilt the index");
            builds = before;
        }
        limen_scene *c = copy_scene(s, eye);
        long unused[2];
        char *a = plan_text(s, seen), *b = plan_text(c, unused);
        CHECK_MSG(a && b && !strcmp(a, b), "%s: the plan differs from the same scene made "
                  "afresh", what);
        free(a);
        free(b);
        limen_scene_destroy(c);
        if (step % 100 == 99)
            check_same_trace(s, 48, 36, what);
    }
    builds = limen__index_builds(limen__scene_index(s)) - builds;
    CHECK_MSG(builds * 8 < changes, "%ld full builds for %d nodes created and destroyed", builds,
              changes);
    /* plans worth comparing: views through mirrors and portals, shapes through portals */
    CHECK_MSG(seen[0] > 4 * 400 && seen[1] > 400, "%ld views, %ld clones in 400 plans", seen[0],
              seen[1]);
    free(live);
    limen_scene_destroy(s);
}

/* Spheres created one by one ever further along a line, each the farthest yet, go in below
 * the one before: the tree deepens by one each time. Past the depth the traversals' stacks
 * allow, the index is built again rather than walked too deep (check_index checks the
 * depth), though far fewer nodes came than the quarter that rebuilds. */
static void test_churn_deep(void)
{
    limen_scene *s = NULL;
    limen_scene_create(&(limen_scene_desc){ .max_nodes = 4096 }, &s);
    rng = 5;
    for (int i = 0; i < 600; i++)
        add(s, LIMEN_NODE_SPHERE, uni(-8, 8), uni(-8, 8), uni(-8, 8));
    check_index(s, "a cloud of spheres");
    long before = limen__index_builds(limen__scene_index(s));
    int deepest = 0;
    for (int i = 0; i < 140; i++) {
        limen_node m = { 0 };
        CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, NULL, &m));
        limen_node_set_position(s, m, (float[3]){ 50.0f + 2.0f * (float)i, 1, -3 });
        limen__spatial *x = limen__scene_index(s);
        const limen__bvh *b = limen__index_shapes(x);
        deepest = b->nodes[0].height > deepest ? b->nodes[0].height : deepest;
        if (i % 20 == 19)
            check_index(s, "a line of spheres");
    }
    long builds = limen__index_builds(limen__scene_index(s)) - before;
    CHECK_MSG(builds >= 1 && builds <= 2 && deepest > 80 && deepest <= 100,
              "%ld builds, the tree %d deep at most", builds, deepest);
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "gallery_same", test_gallery_same },
    { "random_same", test_random_same },
    { "edits_same", test_edits_same },
    { "hall_same", test_hall_same },
    { "cost_follows_visibility", test_cost_follows_visibility },
    { "view_things", test_view_things },
    { "churn_same", test_churn_same },
    { "churn_deep", test_churn_deep },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
