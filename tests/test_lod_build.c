/* test_lod_build.c - how a mesh's levels of detail are made (core/lod.c lods_make,
 * core/lod_weld.c): what the simplifier is given, where each level comes from, and that the
 * levels made with both cores used are the levels made in turn. */
#include <float.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

#include "bumpy.h"
#include "check.h"
#include "core/lod_target.h"
#include "core/lod_weld.h"
#include "limen.h"

/* A G x G grid of quads over [0, 1]^2 at x offset dx, height z = bump(x, y), into pos (from
 * vertex v0) and idx (from triangle t0); returns the vertices written. */
static int grid(int g, double dx, bool bumpy, int v0, int t0, float *pos, uint32_t *idx)
{
    for (int j = 0; j <= g; j++)
        for (int i = 0; i <= g; i++) {
            double x = (double)i / g, y = (double)j / g;
            float *p = &pos[(size_t)(v0 + j * (g + 1) + i) * 3];
            p[0] = (float)(x + dx);
            p[1] = (float)y;
            p[2] = bumpy ? (float)(0.05 * sin(7 * x) * cos(5 * y) + 0.02 * sin(23 * x * y)) : 0;
        }
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            uint32_t a = (uint32_t)(v0 + j * (g + 1) + i), b = a + 1,
                     c = a + (uint32_t)(g + 1), d = c + 1;
            uint32_t *t = &idx[(size_t)(t0 + 2 * (j * g + i)) * 3];
            t[0] = a, t[1] = b, t[2] = d;
            t[3] = a, t[4] = d, t[5] = c;
        }
    return (g + 1) * (g + 1);
}

/* A level is given the simplifier over its own vertices alone (limen__lod_simplify from a
 * source): a bumpy patch simplified as a source within a mesh ten times its size (the
 * patch first, a far flat patch after) gives the indices it gives as a mesh of its own,
 * every one a vertex of the source, and its error in the whole mesh's units (relative to
 * the whole extent, as from the whole mesh): fails where the error stays relative to the
 * source's own extent (10x too large here). */
static void test_simplify_sparse(void)
{
    enum { G = 40, NV = (G + 1) * (G + 1), NT = 2 * G * G };
    static float pos[2 * NV * 3];
    static uint32_t idx[2 * NT * 3], out[NT * 3], alone_out[NT * 3];
    grid(G, 0, true, 0, 0, pos, idx);
    grid(G, 9, false, NV, NT, pos, idx);
    limen__mesh whole = { .nverts = 2 * NV, .ntris = 2 * NT, .pos = pos, .idx = idx },
                patch = { .nverts = NV, .ntris = NT, .pos = pos, .idx = idx };
    limen__lod_welded pk = { 0 }, pk_patch = { 0 };
    CHECK(limen__lod_pack(&pk, &whole, idx) && limen__lod_pack(&pk_patch, &patch, idx));
    if (!pk.n || !pk_patch.n) {
        limen__lod_welded_free(&pk);
        limen__lod_welded_free(&pk_patch);
        return;
    }
    size_t want = (size_t)NT / 4 * 3;
    float err = -1, alone_err = -1;
    size_t n = limen__lod_simplify(&pk, idx, (size_t)NT * 3, false, want, FLT_MAX, &err, out);
    size_t alone = limen__lod_simplify(&pk_patch, NULL, (size_t)NT * 3, false, want, FLT_MAX,
                                       &alone_err, alone_out);
    CHECK_MSG(n > 0 && n <= want && n == alone, "%zu indices from the source, %zu alone", n,
              alone);
    CHECK(n == alone && memcmp(out, alone_out, sizeof *out * n) == 0);
    bool within = true;
    for (size_t i = 0; i < n; i++)
        within = within && out[i] < NV;
    CHECK(within);
    /* the same distance, in the whole mesh's units and in the patch's */
    CHECK_MSG(alone_err > 0 && fabs((double)err * pk.scale - (double)alone_err * pk_patch.scale) <=
                                   1e-5 * (double)alone_err * pk_patch.scale,
              "error %g of extent %g from the source, %g of %g alone", err, pk.scale, alone_err,
              pk_patch.scale);
    limen__lod_welded_free(&pk);
    limen__lod_welded_free(&pk_patch);
}

/* The levels of mesh node data's mesh, made in a scene of their own: count levels, each
 * level's triangle count, error and indices (the caller frees *idx). */
typedef struct levels {
    int count;
    int tris[12];
    float error[12];
    uint32_t *idx[12];
} levels;

static levels make_levels(const limen_mesh_data *data)
{
    levels lv = { 0 };
    limen_scene *s;
    limen_node n;
    limen_drawables *d;
    CHECK_OK(limen_scene_create(NULL, &s));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "ball", &n));
    CHECK_OK(limen_mesh_set_triangles(s, n, data));
    CHECK_OK(limen_drawables_create(&d));
    CHECK_OK(limen_drawables_build(d, s));
    const limen_drawable *all;
    limen_drawables_items(d, &all);
    int i = limen_drawables_find(d, n);
    const limen_mesh_geometry *g = i >= 0 ? all[i].mesh : NULL;
    for (int k = 0; g && k < g->lod_count && k < 12; k++) {
        size_t len = (size_t)g->lods[k].triangle_count * 3;
        lv.tris[k] = g->lods[k].triangle_count;
        lv.error[k] = g->lods[k].error;
        lv.idx[k] = malloc(sizeof(uint32_t) * (len ? len : 1));
        if (lv.idx[k])
            memcpy(lv.idx[k], g->lods[k].indices, sizeof(uint32_t) * len);
        lv.count = k + 1;
    }
    limen_drawables_destroy(d);
    limen_scene_destroy(s);
    return lv;
}

static void free_levels(levels *lv)
{
    for (int k = 0; k < lv->count; k++)
        free(lv->idx[k]);
}

/* Whether every vertex level b's triangles name is one that level a's name (nv vertices). */
static bool vertices_within(const levels *lv, int a, int b, int nv)
{
    bool *in = calloc((size_t)nv, sizeof *in), all = in != NULL;
    for (int i = 0; in && i < lv->tris[a] * 3; i++)
        in[lv->idx[a][i]] = true;
    for (int i = 0; in && i < lv->tris[b] * 3; i++)
        all = all && in[lv->idx[b][i]];
    free(in);
    return all;
}

/* The bumpy sphere both ways are made of: 19,200 triangles. */
enum {
    BOTH_U = 120,
    BOTH_V = 80,
    BOTH_NV = (BOTH_U + 1) * (BOTH_V + 1),
    BOTH_NT = BOTH_U * BOTH_V * 2
};

/* The sphere's levels made twice, on threads (both[0]) and in turn (both[1],
 * limen__lod_set_measure_threads(false)). */
static void levels_both_ways(levels both[2])
{
    static float pos[BOTH_NV * 3];
    static uint32_t idx[BOTH_NT * 3];
    bumpy_sphere(BOTH_U, BOTH_V, pos, idx);
    limen_mesh_data data = { .positions = pos, .vertex_count = BOTH_NV, .indices = idx,
                             .triangle_count = BOTH_NT };
    for (int run = 0; run < 2; run++) {
        limen__lod_set_measure_threads(run == 0);
        both[run] = make_levels(&data);
    }
    limen__lod_set_measure_threads(true);
}

/* Whether both ways made the same levels, to the index, with the same bounds, to the bit. */
static void check_same_levels(const levels both[2])
{
    CHECK_MSG(both[0].count == both[1].count, "%d / %d levels", both[0].count, both[1].count);
    for (int k = 0; k < both[0].count && k < both[1].count; k++)
        CHECK_MSG(both[0].tris[k] == both[1].tris[k] && both[0].error[k] == both[1].error[k] &&
                      memcmp(both[0].idx[k], both[1].idx[k],
                             sizeof(uint32_t) * 3 * both[0].tris[k]) == 0,
                  "level %d: %d triangles, error %.9g on threads; %d, %.9g in turn", k,
                  both[0].tris[k], both[0].error[k], both[1].tris[k], both[1].error[k]);
}

/* A mesh of 8192 triangles or more has its levels 2 and 3 simplified from level 1 (half
 * the work of simplifying the full mesh again): every vertex they name is one of level 1's
 * (the simplifier only moves onto a source's own vertices; from the full mesh, level 2
 * names vertices level 1 dropped). Those levels made again, on threads and in turn
 * (limen__lod_set_measure_threads(false)), are the same levels, to the index, with the same
 * bounds, to the bit. */
static void test_levels_from_first(void)
{
    levels both[2];
    levels_both_ways(both);
    levels *lv = &both[0];
    CHECK_MSG(lv->count >= 5, "%d levels", lv->count);
    for (int k = 2; k <= 3 && k < lv->count; k++)
        CHECK_MSG(vertices_within(lv, 1, k, BOTH_NV), "level %d names vertices level 1 has not", k);
    check_same_levels(both);
    free_levels(&both[0]);
    free_levels(&both[1]);
}

/* levels_both_ways with the next level simplified beside this one for every mesh (the size
 * from which this is done lowered): how many levels so made were kept. */
static uint64_t levels_beside_both_ways(levels both[2])
{
    limen__lod_set_beside_above(0);
    uint64_t kept0 = limen__lod_beside_kept();
    levels_both_ways(both);
    uint64_t kept = limen__lod_beside_kept() - kept0;
    limen__lod_set_beside_above(LIMEN__LOD_SPLIT_ABOVE);
    return kept;
}

/* A big mesh's next level is simplified beside the one before it, where both sources are
 * taken whole, and kept where the one before came out within a tenth of what it was asked
 * for (the next one then asked for half of that): the levels are those made
 * in turn, to the index, with the same bounds, to the bit (here on a small mesh, the size
 * from which this is done lowered to every mesh). */
static void test_levels_beside(void)
{
    levels both[2];
    uint64_t kept = levels_beside_both_ways(both);
    /* levels 4, 6, 8 and 10 made beside 3, 5, 7 and 9 (where those come out within a tenth
     * of what they were asked for) */
    CHECK_MSG(kept >= 2, "%llu levels made beside", (unsigned long long)kept);
    CHECK_MSG(both[0].count >= 8, "%d levels", both[0].count);
    check_same_levels(both);
    free_levels(&both[0]);
    free_levels(&both[1]);
}

/* A big mesh's level is simplified from the one two before it where that one is big
 * (limen__lod_set_near_source, here lowered to every level): every vertex level k names is
 * one of level k - 2's from level 4 on (levels 2 and 3 come from level 1; from three before,
 * a small mesh's source, level k names vertices level k - 2 dropped), the next level made
 * beside this one takes the same source (the beside path lowered to every mesh too), and the
 * levels are those made in turn, to the index, with the same bounds, to the bit. */
static void test_levels_near_source(void)
{
    limen__lod_set_near_source(0);
    levels both[2];
    uint64_t kept = levels_beside_both_ways(both);
    limen__lod_set_near_source(LIMEN__LOD_NEAR_SOURCE);
    levels *lv = &both[0];
    CHECK_MSG(lv->count >= 8, "%d levels", lv->count);
    CHECK_MSG(kept >= 2, "%llu levels made beside", (unsigned long long)kept);
    for (int k = 4; k < lv->count; k++)
        CHECK_MSG(vertices_within(lv, k - 2, k, BOTH_NV),
                  "level %d names vertices level %d has not", k, k - 2);
    check_same_levels(both);
    free_levels(&both[0]);
    free_levels(&both[1]);
}

/* The weld by position (limen__lod_shadow) is meshoptimizer's shadow index buffer, to the
 * index: on a bumpy sphere (its seam and poles repeat positions), with a quarter of its
 * vertices moved onto others', its corners in a scrambled order, and 0 beside -0 (two
 * positions, as their bits are). */
static void test_shadow_as_meshopt(void)
{
    enum { U = 60, V = 40, NV = (U + 1) * (V + 1), NT = U * V * 2 };
    static float pos[NV * 3];
    static uint32_t idx[NT * 3], mine[NT * 3], theirs[NT * 3];
    bumpy_sphere(U, V, pos, idx);
    for (int variant = 0; variant < 3; variant++) {
        if (variant == 1)
            for (int i = 0; i < NV; i += 4)
                memcpy(&pos[i * 3], &pos[(size_t)((i * 7 + 3) % NV) * 3], sizeof(float) * 3);
        if (variant == 2) {
            for (size_t i = 0; i < (size_t)NT * 3; i++)
                mine[i] = idx[(i * 7919) % ((size_t)NT * 3)];
            memcpy(idx, mine, sizeof idx);
            pos[0] = 0.0f;
            pos[1] = pos[2] = 1;
            pos[3] = -0.0f;
            pos[4] = pos[5] = 1;
        }
        limen__mesh m = { .nverts = NV, .ntris = NT, .pos = pos, .idx = idx };
        CHECK(limen__lod_shadow(&m, mine));
        meshopt_generateShadowIndexBuffer(theirs, idx, (size_t)NT * 3, pos, NV,
                                          sizeof(float) * 3, sizeof(float) * 3);
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)NT * 3; i++)
            differ += mine[i] != theirs[i];
        CHECK_MSG(differ == 0, "variant %d: %zu corners welded otherwise", variant, differ);
    }
}

static const check_case cases[] = {
    { "shadow_as_meshopt", test_shadow_as_meshopt },
    { "simplify_sparse", test_simplify_sparse },
    { "levels_from_first", test_levels_from_first },
    { "levels_beside", test_levels_beside },
    { "levels_near_source", test_levels_near_source },
    { 0 },
};

int main(int argc, char **argv)
{
    /* the levels checked are the ones made here, not ones kept from an earlier build */
    setenv("LIMEN_CACHE", "off", 1);
    return check_run(argc, argv, cases);
}
