/* test_lod.c - levels of detail of meshes: how they are made (the bunny in scenes/data, a
 * flat grid made here), that the error each carries bounds its true distance from the full
 * mesh (checked by brute force, independently of the library's measure), and which level a
 * view picks (limen_view_mesh_lod), through a scaled portal too. No GL. */
#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bumpy.h"
#include "cache_dir.h"
#include "charted.h"
#include "check.h"
#include "core/lod_cache.h"
#include "core/lod_target.h"
#include "limen.h"
#include "load.h"

#define HEIGHT 480

/* A scene, its camera at eye looking at `at`, and a mesh node "statue". */
typedef struct fixture {
    limen_scene *s;
    limen_node cam, mesh;
    limen_drawables *d;
} fixture;

static fixture open_scene(const float eye[3], const float at[3])
{
    fixture f = { 0 };
    CHECK_OK(limen_scene_create(NULL, &f.s));
    CHECK_OK(limen_node_create(f.s, LIMEN_NODE_CAMERA, "cam", &f.cam));
    CHECK_OK(limen_node_look_at(f.s, f.cam, eye, at, (float[3]){ 0, 1, 0 }));
    CHECK_OK(limen_scene_set_camera(f.s, f.cam));
    CHECK_OK(limen_node_create(f.s, LIMEN_NODE_MESH, "statue", &f.mesh));
    CHECK_OK(limen_drawables_create(&f.d));
    return f;
}

static void close_scene(fixture *f)
{
    limen_drawables_destroy(f->d);
    limen_scene_destroy(f->s);
}

/* The mesh node's drawable as the renderer reads it (refreshed now). */
static const limen_drawable *item(fixture *f)
{
    CHECK_OK(limen_drawables_build(f->d, f->s));
    const limen_drawable *all;
    limen_drawables_items(f->d, &all);
    int i = limen_drawables_find(f->d, f->mesh);
    CHECK(i >= 0 && all[i].mesh != NULL);
    return i >= 0 ? &all[i] : NULL;
}

/* open_scene from 5 units along +z, the statue a bumpy sphere of u x v quads
 * (tests/bumpy.h) with its levels made (the mesh keeps copies of the arrays made here). */
static fixture sphere_scene(int u, int v)
{
    fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    int nv = (u + 1) * (v + 1), nt = u * v * 2;
    float *pos = malloc(sizeof(float) * 3 * (size_t)nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * (size_t)nt);
    CHECK(pos && idx);
    if (pos && idx) {
        bumpy_sphere(u, v, pos, idx);
        CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
            .positions = pos, .vertex_count = nv, .indices = idx, .triangle_count = nt }));
    }
    free(pos);
    free(idx);
    return f;
}

/* ------------------------------------------------------------------ brute force */

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void vtx(const limen_mesh_geometry *g, uint32_t v, double out[3])
{
    for (int a = 0; a < 3; a++)
        out[a] = g->positions[v * 3 + a];
}

static double seg_dist(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], e[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ap[k] = p[k] - a[k];
    }
    double t = dot(ab, ab) > 0 ? dot(ap, ab) / dot(ab, ab) : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    for (int k = 0; k < 3; k++)
        e[k] = ap[k] - t * ab[k];
    return sqrt(dot(e, e));
}

/* Distance from p to a triangle: through barycentric coordinates of p's projection on the
 * plane (solved by Cramer's rule) when they are all >= 0, else the nearest edge. */
static double tri_dist(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = p[k] - a[k];
    }
    double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v), wu = dot(w, u), wv = dot(w, v);
    double det = uu * vv - uv * uv;
    if (det > 1e-30 * uu * vv) {
        double s = (wu * vv - wv * uv) / det, t = (wv * uu - wu * uv) / det;
        if (s >= 0 && t >= 0 && s + t <= 1) {
            double q[3];
            for (int k = 0; k < 3; k++)
                q[k] = w[k] - s * u[k] - t * v[k];
            return sqrt(dot(q, q));
        }
    }
    return fmin(seg_dist(p, a, b), fmin(seg_dist(p, b, c), seg_dist(p, c, a)));
}

/* Distance from p to the nearest of the triangles idx[0 .. 3n), by trying every one. */
static double mesh_dist(const limen_mesh_geometry *g, const uint32_t *idx, int n, const double p[3])
{
    double best = INFINITY;
    for (int t = 0; t < n; t++) {
        double a[3], b[3], c[3];
        vtx(g, idx[t * 3], a);
        vtx(g, idx[t * 3 + 1], b);
        vtx(g, idx[t * 3 + 2], c);
        best = fmin(best, tri_dist(p, a, b, c));
    }
    return best;
}

static uint64_t rng = 88172645463325252ull;

static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* The largest distance found from samples of level k to the full mesh (edge midpoints of
 * up to 200 of its triangles, and `random` points at random) and from every full-mesh
 * vertex to level k. */
static double brute_hausdorff(const limen_mesh_geometry *g, int k, int random)
{
    const limen_mesh_lod *lv = &g->lods[k], *full = &g->lods[0];
    double worst = 0;
    int stride = lv->triangle_count / 200 + 1;
    for (int t = 0; t < lv->triangle_count; t += stride)
        for (int e = 0; e < 3; e++) {
            double a[3], b[3], m[3];
            vtx(g, lv->indices[t * 3 + e], a);
            vtx(g, lv->indices[t * 3 + (e + 1) % 3], b);
            for (int c = 0; c < 3; c++)
                m[c] = 0.5 * (a[c] + b[c]);
            worst = fmax(worst, mesh_dist(g, full->indices, full->triangle_count, m));
        }
    for (int i = 0; i < random; i++) {
        int t = (int)(uniform() * lv->triangle_count);
        double r1 = sqrt(uniform()), r2 = uniform(), a[3], b[3], c[3], p[3];
        vtx(g, lv->indices[t * 3], a);
        vtx(g, lv->indices[t * 3 + 1], b);
        vtx(g, lv->indices[t * 3 + 2], c);
        for (int x = 0; x < 3; x++)
            p[x] = (1 - r1) * a[x] + r1 * (1 - r2) * b[x] + r1 * r2 * c[x];
        worst = fmax(worst, mesh_dist(g, full->indices, full->triangle_count, p));
    }
    for (int v = 0; v < g->vertex_count; v++) {
        double p[3];
        vtx(g, (uint32_t)v, p);
        worst = fmax(worst, mesh_dist(g, lv->indices, lv->triangle_count, p));
    }
    return worst;
}

/* A triangle's corners and a box around them. */
typedef struct tri_box {
    double a[3], b[3], c[3], lo[3], hi[3];
} tri_box;

static tri_box *boxes_of(const limen_mesh_geometry *g, const limen_mesh_lod *lv)
{
    tri_box *t = malloc(sizeof *t * (size_t)lv->triangle_count);
    for (int i = 0; t && i < lv->triangle_count; i++) {
        vtx(g, lv->indices[i * 3], t[i].a);
        vtx(g, lv->indices[i * 3 + 1], t[i].b);
        vtx(g, lv->indices[i * 3 + 2], t[i].c);
        for (int x = 0; x < 3; x++) {
            t[i].lo[x] = fmin(t[i].a[x], fmin(t[i].b[x], t[i].c[x]));
            t[i].hi[x] = fmax(t[i].a[x], fmax(t[i].b[x], t[i].c[x]));
        }
    }
    return t;
}

/* Triangles filed by the cells of a grid their boxes meet, for brute forces on bigger
 * meshes: the nearest is still found by trying triangles one by one, but only those of the
 * cells around a point, ring by ring, until the next ring lies farther than the nearest. */
typedef struct grid {
    const tri_box *t;
    double lo[3], cell;
    int n[3];
    int *first, *items;         /* cell c holds items[first[c] .. first[c + 1]) */
} grid;

static int cell_of(const grid *g, int a, double x)
{
    int i = (int)floor((x - g->lo[a]) / g->cell);
    return i < 0 ? 0 : i >= g->n[a] ? g->n[a] - 1 : i;
}

static bool grid_make(grid *g, const tri_box *t, int nt)
{
    double hi[3];
    *g = (grid){ .t = t };
    for (int a = 0; a < 3; a++) {
        g->lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (int i = 0; i < nt; i++)
        for (int a = 0; a < 3; a++) {
            g->lo[a] = fmin(g->lo[a], t[i].lo[a]);
            hi[a] = fmax(hi[a], t[i].hi[a]);
        }
    /* about as many cells across as a surface of nt triangles has triangles across */
    double across = fmin(fmax(2 * sqrt((double)nt), 1), 64);
    g->cell = fmax(hi[0] - g->lo[0], fmax(hi[1] - g->lo[1], hi[2] - g->lo[2])) / across + 1e-9;
    int cells = 1;
    for (int a = 0; a < 3; a++) {
        g->n[a] = (int)((hi[a] - g->lo[a]) / g->cell) + 1;
        cells *= g->n[a];
    }
    g->first = calloc((size_t)cells + 1, sizeof *g->first);
    int *fill = calloc((size_t)cells, sizeof *fill);
    for (int pass = 0; pass < 2 && g->first && fill; pass++) {
        if (pass == 1) {
            for (int c = 0; c < cells; c++) {
                g->first[c + 1] += g->first[c];
                fill[c] = g->first[c];
            }
            g->items = malloc(sizeof *g->items * (size_t)(g->first[cells] + 1));
            if (!g->items)
                break;
        }
        for (int i = 0; i < nt; i++) {
            int lo[3], up[3];
            for (int a = 0; a < 3; a++) {
                lo[a] = cell_of(g, a, t[i].lo[a]);
                up[a] = cell_of(g, a, t[i].hi[a]);
            }
            for (int x = lo[0]; x <= up[0]; x++)
                for (int y = lo[1]; y <= up[1]; y++)
                    for (int z = lo[2]; z <= up[2]; z++) {
                        int c = (z * g->n[1] + y) * g->n[0] + x;
                        if (pass == 0)
                            g->first[c + 1]++;
                        else
                            g->items[fill[c]++] = i;
                    }
        }
    }
    free(fill);
    return g->items != NULL;
}

static void grid_free(grid *g)
{
    free(g->first);
    free(g->items);
}

/* The distance from p to the nearest triangle of g. */
static double grid_dist(const grid *g, const double p[3])
{
    int at[3];
    for (int a = 0; a < 3; a++)
        at[a] = cell_of(g, a, p[a]);
    /* p's distance outside the grid's box: every cell lies at least that far */
    double out = 0;
    for (int a = 0; a < 3; a++) {
        double hi = g->lo[a] + g->n[a] * g->cell,
               e = fmax(fmax(g->lo[a] - p[a], p[a] - hi), 0);
        out += e * e;
    }
    out = sqrt(out);
    /* inside the grid, how far p lies within its own cell */
    double inner = INFINITY;
    for (int a = 0; a < 3 && out == 0; a++) {
        double below = p[a] - (g->lo[a] + at[a] * g->cell);
        inner = fmin(inner, fmin(below, g->cell - below));
    }
    inner = out > 0 || inner < 0 ? 0 : inner;
    double best = INFINITY;
    int most = g->n[0] + g->n[1] + g->n[2];
    for (int r = 0; r <= most; r++) {
        /* the cells r rings out lie at least r - 1 cells and p's depth in its own away */
        if (r > 0 && (r - 1) * g->cell + inner + out > best)
            break;
        for (int x = at[0] - r; x <= at[0] + r; x++)
            for (int y = at[1] - r; y <= at[1] + r; y++)
                for (int z = at[2] - r; z <= at[2] + r; z++) {
                    if (abs(x - at[0]) != r && abs(y - at[1]) != r && abs(z - at[2]) != r)
                        continue;       /* inside the ring: tried already */
                    if (x < 0 || y < 0 || z < 0 || x >= g->n[0] || y >= g->n[1] ||
                        z >= g->n[2])
                        continue;
                    int c = (z * g->n[1] + y) * g->n[0] + x;
                    for (int k = g->first[c]; k < g->first[c + 1]; k++) {
                        const tri_box *t = &g->t[g->items[k]];
                        best = fmin(best, tri_dist(p, t->a, t->b, t->c));
                    }
                }
    }
    return best;
}

/* brute_hausdorff for bigger meshes, against the full mesh filed in `full`: every
 * full-mesh vertex against level k, and from level k a barycentric lattice of `steps` on
 * every `stride`-th triangle and `random` points at random. */
/* The largest distance to the full mesh (full) found on triangle t of lt, on a lattice of
 * `steps` a side. */
static double tri_sampled(const grid *full, const tri_box *lt, int t, int steps)
{
    double worst = 0;
    for (int i = 0; i <= steps; i++)
        for (int j = 0; i + j <= steps; j++) {
            double u = (double)i / steps, v = (double)j / steps, p[3];
            for (int x = 0; x < 3; x++)
                p[x] = (1 - u - v) * lt[t].a[x] + u * lt[t].b[x] + v * lt[t].c[x];
            worst = fmax(worst, grid_dist(full, p));
        }
    return worst;
}

static double brute_sampled(const limen_mesh_geometry *g, const grid *full, int k, int stride,
                            int steps, int random)
{
    const limen_mesh_lod *lv = &g->lods[k];
    tri_box *lt = boxes_of(g, lv);
    grid lg = { 0 };
    bool ok = lt && grid_make(&lg, lt, lv->triangle_count);
    CHECK(ok);
    double worst = 0;
    int n = lv->triangle_count;
    for (int t = 0; ok && t < n; t += stride)
        worst = fmax(worst, tri_sampled(full, lt, t, steps));
    for (int i = 0; ok && i < random; i++) {
        const tri_box *t = &lt[(int)(uniform() * n)];
        double r1 = sqrt(uniform()), r2 = uniform(), p[3];
        for (int x = 0; x < 3; x++)
            p[x] = (1 - r1) * t->a[x] + r1 * (1 - r2) * t->b[x] + r1 * r2 * t->c[x];
        worst = fmax(worst, grid_dist(full, p));
    }
    for (int v = 0; ok && v < g->vertex_count; v++) {
        double p[3];
        vtx(g, (uint32_t)v, p);
        worst = fmax(worst, grid_dist(&lg, p));
    }
    grid_free(&lg);
    free(lt);
    return worst;
}

/* ------------------------------------------------------------------ building */

static void check_levels(const limen_mesh_geometry *g, const char *what)
{
    CHECK_MSG(g->lod_count >= 5 && g->lod_count <= 12, "%s: %d levels", what, g->lod_count);
    CHECK(g->lods[0].indices == g->indices && g->lods[0].triangle_count == g->triangle_count &&
          g->lods[0].error == 0);
    for (int k = 1; k < g->lod_count; k++) {
        const limen_mesh_lod *a = &g->lods[k - 1], *b = &g->lods[k];
        CHECK_MSG(b->triangle_count > 0 && b->triangle_count * 4 <= a->triangle_count * 3,
                  "%s: level %d has %d triangles after %d", what, k, b->triangle_count,
                  a->triangle_count);
        CHECK_MSG(b->error >= a->error && b->error > 0, "%s: level %d error %g after %g", what,
                  k, b->error, a->error);
        for (int i = 0; i < b->triangle_count * 3; i++)
            if (b->indices[i] >= (uint32_t)g->vertex_count) {
                CHECK_MSG(0, "%s: level %d index %u out of range", what, k, b->indices[i]);
                break;
            }
    }
}

static void test_bunny_levels(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 30 }, (float[3]){ 0, 0, 0 });
    static const char *files[] = { "scenes/data/bunny.obj", "scenes/data/bunny.glb" };
    for (int i = 0; i < 2; i++) {
        CHECK_OK(limen_mesh_load(f.s, f.mesh, files[i]));
        const limen_drawable *d = item(&f);
        if (!d)
            break;
        check_levels(d->mesh, files[i]);
        limen_mesh_info info;
        CHECK_OK(limen_mesh_get(f.s, f.mesh, &info));
        CHECK(info.lod_count == d->mesh->lod_count);
        /* the levels' indices are counted in what the mesh holds */
        size_t lod_bytes = 0;
        for (int k = 1; k < d->mesh->lod_count; k++)
            lod_bytes += (size_t)d->mesh->lods[k].triangle_count * 3 * sizeof(uint32_t);
        CHECK(info.bytes > lod_bytes + (size_t)info.triangle_count * 3 * sizeof(uint32_t) +
                               (size_t)info.vertex_count * 6 * sizeof(float));
    }
    close_scene(&f);
}

/* Each level's error is at least the largest distance a brute force finds between it and
 * the full mesh, either way; and not far above it: the measure aims at 10% over the true
 * distance, the samples fall a little short of it, so more than 30% means the bound has
 * come loose (what a cheaper measure must not trade for its speed). */
static void test_error_bounds(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 30 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/bunny.obj"));
    const limen_drawable *d = item(&f);
    for (int k = 1; d && k < d->mesh->lod_count; k++) {
        double found = brute_hausdorff(d->mesh, k, 400);
        CHECK_MSG(found <= d->mesh->lods[k].error * (1 + 1e-5), "level %d: error %g, found %g",
                  k, d->mesh->lods[k].error, found);
        CHECK(found > 0);
        CHECK_MSG(d->mesh->lods[k].error <= found * 1.3, "level %d: error %g, found %g", k,
                  d->mesh->lods[k].error, found);
    }
    close_scene(&f);
}

/* A bumpy sphere of 20,000 triangles (ripples of two sizes; at its poles, slivers and
 * corners on the axis, as a careless exporter makes them): each level's error bounds a
 * brute force's largest distance, and (where the brute force samples densely) stays within
 * 30% of it or of the level before's. On so smooth a surface the largest distance lies at
 * a vertex, which the measure finds exactly; the bunny's levels are the finer test of the
 * bounds over the pieces' areas. On the coarse levels most of the full mesh's triangles are
 * bounded through their corners alone (side_near), and of the levels' pieces many over a
 * finer level with its triangles' own bounds (via_pick), which the bounds hold still. */
static void test_big_bounds(void)
{
    uint64_t passed = limen__lod_near_passed(), local = limen__lod_local_settled();
    fixture f = sphere_scene(100, 100);
    const limen_drawable *d = item(&f);
    passed = limen__lod_near_passed() - passed;
    local = limen__lod_local_settled() - local;
    CHECK_MSG(d && d->mesh && passed >= 3 * (uint64_t)d->mesh->triangle_count,
              "%llu of the full mesh's triangles bounded through their corners alone",
              (unsigned long long)passed);
    CHECK_MSG(d && d->mesh && local >= (uint64_t)d->mesh->triangle_count / 8,
              "%llu of the levels' pieces bounded over the level before, with its triangles' "
              "own bounds", (unsigned long long)local);
    tri_box *ft = d && d->mesh ? boxes_of(d->mesh, &d->mesh->lods[0]) : NULL;
    grid full = { 0 };
    if (ft && grid_make(&full, ft, d->mesh->triangle_count)) {
        check_levels(d->mesh, "sphere");
        for (int l = 1; l < d->mesh->lod_count; l++) {
            /* a lattice on every triangle of the coarser levels (the largest distance can
             * lie between the points of a sparser one); on some of the finer ones */
            int n = d->mesh->lods[l].triangle_count;
            bool dense = n <= 2500;
            double found = brute_sampled(d->mesh, &full, l, dense ? 1 : n / 1000 + 1,
                                         dense ? 6 : 2, 400),
                   e = d->mesh->lods[l].error, before = d->mesh->lods[l - 1].error;
            CHECK_MSG(found <= e * (1 + 1e-5), "level %d: error %g, found %g", l, e, found);
            /* not far above it either, where the lattice is dense; a level's error starts
             * from the one before's (never finer than a finer level), which the measure
             * may exceed by its own tolerance as it may the largest distance found */
            CHECK_MSG(found > 0 && (!dense || e <= fmax(found, before) * 1.3),
                      "level %d: error %g, found %g, the level before %g", l, e, found, before);
        }
    } else {
        CHECK(!"no mesh, or no memory for the brute force");
    }
    grid_free(&full);
    free(ft);
    close_scene(&f);
}

/* A level's pieces are bounded on two threads, each over its own slices of triangles with
 * its own floor (core/lod.c): the levels and their bounds are the same, to the bit, as when
 * the slices are bounded in turn on one thread, and each still bounds a brute force's
 * largest distance. */
static void test_measure_threads(void)
{
    float errors[2][12] = { { 0 } };
    int counts[2][12] = { { 0 } }, levels[2] = { 0 };
    /* (main turned the cache off: both runs make their levels) */
    for (int run = 0; run < 2; run++) {
        limen__lod_set_measure_threads(run == 0);
        fixture f = sphere_scene(100, 100);
        const limen_drawable *d = item(&f);
        if (d && !d->mesh)
            d = NULL;
        for (int k = 0; d && k < d->mesh->lod_count && k < 12; k++) {
            errors[run][k] = d->mesh->lods[k].error;
            counts[run][k] = d->mesh->lods[k].triangle_count;
        }
        levels[run] = d ? d->mesh->lod_count : 0;
        if (d && run == 1) {
            tri_box *ft = boxes_of(d->mesh, &d->mesh->lods[0]);
            grid full = { 0 };
            CHECK(ft && grid_make(&full, ft, d->mesh->triangle_count));
            for (int l = 1; ft && full.first && l < d->mesh->lod_count; l++) {
                int n = d->mesh->lods[l].triangle_count;
                double found = brute_sampled(d->mesh, &full, l, n / 500 + 1, 3, 200);
                CHECK_MSG(found <= d->mesh->lods[l].error * (1 + 1e-5),
                          "level %d: error %g, found %g", l, d->mesh->lods[l].error, found);
            }
            grid_free(&full);
            free(ft);
        }
        close_scene(&f);
    }
    limen__lod_set_measure_threads(true);
    CHECK_MSG(levels[0] >= 5 && levels[0] == levels[1], "%d levels on threads, %d in turn",
              levels[0], levels[1]);
    for (int k = 0; k < levels[0] && k < 12; k++)
        CHECK_MSG(errors[0][k] == errors[1][k] && counts[0][k] == counts[1][k],
                  "level %d: %d triangles, error %.9g on threads; %d, %.9g in turn", k,
                  counts[0][k], errors[0][k], counts[1][k], errors[1][k]);
}

/* A flat grid simplifies to its outline: two triangles, no error. */
static void test_flat_grid(void)
{
    enum { N = 16 };
    float pos[(N + 1) * (N + 1) * 3];
    uint32_t idx[N * N * 6];
    int k = 0;
    for (int y = 0; y <= N; y++)
        for (int x = 0; x <= N; x++) {
            float *p = &pos[(y * (N + 1) + x) * 3];
            p[0] = (float)x;
            p[1] = (float)y;
            p[2] = 0;
        }
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            uint32_t a = (uint32_t)(y * (N + 1) + x), b = a + 1, c = a + N + 1, e = c + 1;
            uint32_t q[6] = { a, b, e, a, e, c };
            for (int i = 0; i < 6; i++)
                idx[k++] = q[i];
        }
    fixture f = open_scene((float[3]){ 8, 8, 30 }, (float[3]){ 8, 8, 0 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
        .positions = pos, .vertex_count = (N + 1) * (N + 1), .indices = idx,
        .triangle_count = N * N * 2 }));
    const limen_drawable *d = item(&f);
    if (d) {
        const limen_mesh_geometry *g = d->mesh;
        const limen_mesh_lod *last = &g->lods[g->lod_count - 1];
        CHECK_MSG(last->triangle_count == 2, "%d levels, the last of %d triangles", g->lod_count,
                  last->triangle_count);
        CHECK_MSG(last->error <= 1e-5 * N, "error %g", last->error);
        CHECK(brute_hausdorff(g, g->lod_count - 1, 50) <= 1e-6);
    }
    close_scene(&f);
}

/* A fold: two flat grids at a right angle, their vertices on the ridge doubled with each
 * side's own normal. The ridge does not hold the simplifier back: the fold comes down to
 * its two rectangles, four triangles with no error. Every level's corners keep the normal
 * of their own side. */
static void test_seam_sides(void)
{
    enum { N = 8, SIDE = (N + 1) * (N + 1) };
    float pos[2 * SIDE * 3], nrm[2 * SIDE * 3];
    uint32_t idx[2 * N * N * 6];
    int k = 0;
    for (int side = 0; side < 2; side++) {
        for (int j = 0; j <= N; j++)
            for (int i = 0; i <= N; i++) {
                float *p = &pos[(side * SIDE + j * (N + 1) + i) * 3];
                float *n = &nrm[(side * SIDE + j * (N + 1) + i) * 3];
                /* side 0: z = 0, y from 0 to N; side 1: y = N, z from 0 to N */
                p[0] = (float)i;
                p[1] = side ? N : (float)j;
                p[2] = side ? (float)j : 0;
                n[0] = 0;
                n[1] = side ? -1.0f : 0;
                n[2] = side ? 0 : 1.0f;
            }
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                uint32_t a = (uint32_t)(side * SIDE + j * (N + 1) + i), b = a + 1, c = a + N + 1,
                         e = c + 1;
                /* side 0 faces +z; side 1 faces -y */
                uint32_t q[6] = { a, b, e, a, e, c };
                for (int x = 0; x < 6; x++)
                    idx[k++] = q[x];
            }
    }
    fixture f = open_scene((float[3]){ 4, -10, 10 }, (float[3]){ 4, 4, 4 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
        .positions = pos, .normals = nrm, .vertex_count = 2 * SIDE, .indices = idx,
        .triangle_count = 2 * N * N * 2 }));
    const limen_drawable *d = item(&f);
    if (d) {
        const limen_mesh_geometry *g = d->mesh;
        const limen_mesh_lod *last = &g->lods[g->lod_count - 1];
        CHECK_MSG(g->lod_count >= 2 && last->triangle_count <= 4 && last->error <= 1e-5 * N,
                  "%d levels, the coarsest %d triangles off by %g", g->lod_count,
                  last->triangle_count, last->error);
        for (int l = 1; l < g->lod_count; l++)
            for (int t = 0; t < g->lods[l].triangle_count; t++) {
                const uint32_t *ix = &g->lods[l].indices[t * 3];
                double a[3], b[3], c[3], u[3], v[3], fn[3];
                vtx(g, ix[0], a);
                vtx(g, ix[1], b);
                vtx(g, ix[2], c);
                for (int x = 0; x < 3; x++) {
                    u[x] = b[x] - a[x];
                    v[x] = c[x] - a[x];
                }
                fn[0] = u[1] * v[2] - u[2] * v[1];
                fn[1] = u[2] * v[0] - u[0] * v[2];
                fn[2] = u[0] * v[1] - u[1] * v[0];
                double len = sqrt(dot(fn, fn));
                for (int x = 0; x < 3 && len > 0; x++) {     /* no face: no side */
                    const float *nr = &g->normals[ix[x] * 3];
                    double cosine = (fn[0] * nr[0] + fn[1] * nr[1] + fn[2] * nr[2]) / len;
                    CHECK_MSG(cosine > 0.99, "level %d triangle %d corner %d: normal at %g", l,
                              t, x, cosine);
                }
            }
    }
    close_scene(&f);
}

/* ------------------------------------------------------------------ the pick */

/* The pixels level k's error covers in view v, as limen.h states it: error * the node's
 * stretch * the view's scale * proj[5] * height / 2 / the nearest depth of the bounding
 * sphere. NAN where the eye is inside the sphere's slab. */
static double projected(const limen_view *v, const limen_drawable *d, int k)
{
    const float *m = v->view, *w = d->world, *c = d->centre;
    double scale = sqrt((double)m[0] * m[0] + (double)m[4] * m[4] + (double)m[8] * m[8]);
    double stretch = 0;
    for (int col = 0; col < 3; col++)
        stretch = fmax(stretch, sqrt((double)w[col * 4] * w[col * 4] +
                                     (double)w[col * 4 + 1] * w[col * 4 + 1] +
                                     (double)w[col * 4 + 2] * w[col * 4 + 2]));
    double z = -(m[2] * c[0] + m[6] * c[1] + m[10] * c[2] + m[14]);
    double nearest = z - d->radius * scale;
    if (!(nearest > 0))
        return NAN;
    return d->mesh->lods[k].error * stretch * scale * v->proj[5] * HEIGHT / 2 / nearest;
}

/* The pick at `pixels` is the coarsest level within it: it fits, the next does not. */
static int check_pick(const limen_view *v, const limen_drawable *d, float pixels)
{
    int k = limen_view_mesh_lod(v, HEIGHT, d, pixels);
    int n = d->mesh->lod_count;
    CHECK(k >= 0 && k < n);
    double here = projected(v, d, k);
    if (k > 0)
        CHECK_MSG(here <= pixels * (1 + 1e-5), "level %d covers %g px > %g", k, here, pixels);
    if (k + 1 < n && !isnan(here))
        CHECK_MSG(projected(v, d, k + 1) > pixels * (1 - 1e-5), "level %d would do at %g px",
                  k + 1, projected(v, d, k + 1));
    return k;
}

static limen_plan *plan_of(limen_scene *s, float pixels)
{
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    limen_plan_desc pd = { .width = 640, .height = HEIGHT };
    pd.limits.lod_pixels = pixels;
    limen_status st = limen_plan_build(p, s, &pd);
    CHECK_MSG(st == LIMEN_OK, "%s", limen_scene_error(s));
    return p;
}

static void test_pick(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 0 }, (float[3]){ 0, 0, -1 });
    CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/bunny.obj"));
    limen_plan *p = plan_of(f.s, 0);
    const limen_view *v = limen_plan_view(p, 0);
    int prev = 0, coarser = 0;
    for (float z = 2; z < 4000; z *= 1.5f) {
        CHECK_OK(limen_node_set_position(f.s, f.mesh, (float[3]){ 1, 0, -z }));
        const limen_drawable *d = item(&f);
        if (!d)
            break;
        int k = check_pick(v, d, 1);
        CHECK_MSG(k >= prev, "farther, finer: level %d after %d at z = %g", k, prev, z);
        prev = k;
        if (z < 3)
            CHECK_MSG(k == 0, "the eye inside the bounds: level %d", k);
        CHECK(limen_view_mesh_lod(v, HEIGHT, d, 0) == check_pick(v, d, LIMEN_LOD_DEFAULT));
        CHECK(limen_view_mesh_lod(v, HEIGHT, d, LIMEN_LOD_FULL) == 0);
        int loose = check_pick(v, d, 8);
        CHECK(loose >= k);
        coarser += loose > k;
        /* a node scaled up shows its error larger */
        CHECK_OK(limen_node_set_scale(f.s, f.mesh, (float[3]){ 1, 3, 1 }));
        d = item(&f);
        CHECK(check_pick(v, d, 1) <= k);
        CHECK_OK(limen_node_set_scale(f.s, f.mesh, (float[3]){ 1, 1, 1 }));
    }
    CHECK_MSG(prev == 0 ? 0 : prev >= 5, "at 4000 units: level %d", prev);
    CHECK(coarser > 0);
    limen_plan_destroy(p);
    close_scene(&f);
}

/* Through a portal whose exit is half the entrance's size, the child view's units are
 * twice the world's: the pick is the same as from an eye of world units at the same place. */
static void test_pick_scaled_portal(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 4 }, (float[3]){ 0, 0, 0 });
    limen_node a, b;
    CHECK_OK(limen_node_create(f.s, LIMEN_NODE_PORTAL, "a", &a));
    CHECK_OK(limen_node_set_dims(f.s, a, (float[3]){ 4, 4, 0 }));
    CHECK_OK(limen_node_create(f.s, LIMEN_NODE_PORTAL, "b", &b));
    CHECK_OK(limen_node_set_position(f.s, b, (float[3]){ 100, 0, 0 }));
    CHECK_OK(limen_node_set_dims(f.s, b, (float[3]){ 4, 4, 0 }));
    CHECK_OK(limen_node_set_scale(f.s, b, (float[3]){ 0.5f, 0.5f, 0.5f }));
    CHECK_OK(limen_portal_link(f.s, a, b));
    CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/bunny.obj"));
    limen_plan *p = plan_of(f.s, 0);
    CHECK(limen_plan_count(p) >= 2);
    const limen_view *child = limen_plan_view(p, 1);
    if (child) {
        double scale = sqrt((double)child->view[0] * child->view[0] +
                            (double)child->view[4] * child->view[4] +
                            (double)child->view[8] * child->view[8]);
        CHECK_MSG(fabs(scale - 2) < 1e-3, "child view scale %g", scale);
        /* the same eye and gaze in world units */
        limen_view plain = *child;
        for (int i = 0; i < 16; i++)
            if (i % 4 != 3)
                plain.view[i] = (float)(child->view[i] / scale);
        int seen = 0;
        for (float z = 3; z < 3000; z *= 1.5f) {
            CHECK_OK(limen_node_set_position(f.s, f.mesh, (float[3]){ 100, 0, z }));
            const limen_drawable *d = item(&f);
            if (!d)
                break;
            int k = check_pick(child, d, 1);
            CHECK_MSG(k == limen_view_mesh_lod(&plain, HEIGHT, d, 1), "z = %g: level %d", z, k);
            seen |= 1 << k;
        }
        CHECK_MSG(seen & ~1, "the portal view never picked a coarser level (%x)", seen);
    }
    limen_plan_destroy(p);
    close_scene(&f);
}

/* The plan's JSON lists each view's meshes with the level it picks. */
static void test_plan_json(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 0 }, (float[3]){ 0, 0, -1 });
    CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/bunny.obj"));
    CHECK_OK(limen_node_set_position(f.s, f.mesh, (float[3]){ 0, 0, -200 }));
    limen_node hidden;      /* out of sight: not listed */
    CHECK_OK(limen_node_create(f.s, LIMEN_NODE_MESH, "behind", &hidden));
    CHECK_OK(limen_mesh_load(f.s, hidden, "scenes/data/bunny.obj"));
    CHECK_OK(limen_node_set_position(f.s, hidden, (float[3]){ 0, 0, 200 }));
    for (int full = 0; full < 2; full++) {
        limen_plan *p = plan_of(f.s, full ? LIMEN_LOD_FULL : 2);
        const limen_drawable *d = item(&f);
        int k = d ? limen_view_mesh_lod(limen_plan_view(p, 0), HEIGHT, d, full ? LIMEN_LOD_FULL : 2)
                  : -1;
        CHECK(full ? k == 0 : k > 0);
        char path[] = "/tmp/limen-lod-XXXXXX", want[128], text[8192] = "";
        int fd = mkstemp(path);
        CHECK(fd >= 0);
        if (fd >= 0)
            close(fd);
        CHECK_OK(limen_plan_write_json(p, f.s, path));
        read_text(path, text, sizeof text);
        remove(path);
        int tris = d ? d->mesh->lods[k > 0 ? k : 0].triangle_count : 0;
        snprintf(want, sizeof want, "\"meshes\": [{\"node\": \"statue\", \"lod\": %d, "
                 "\"triangles\": %d, \"parts\": [{\"first\": 0, \"count\": %d, "
                 "\"material\": 0}]", k, tris, tris);
        CHECK_MSG(strstr(text, want) != NULL, "no '%s' in %s", want, text);
        limen_plan_destroy(p);
    }
    close_scene(&f);
}

/* lod_pixels: a number of pixels >= 0, or LIMEN_LOD_FULL. */
static void test_lod_pixels(void)
{
    fixture f = open_scene((float[3]){ 0, 0, 4 }, (float[3]){ 0, 0, 0 });
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    float bad[] = { NAN, INFINITY, -INFINITY, -0.5f, -2 };
    for (int i = 0; i < 5; i++) {
        limen_plan_desc pd = { 0 };
        pd.limits.lod_pixels = bad[i];
        CHECK(limen_plan_build(p, f.s, &pd) == LIMEN_ERR_ARG);
        CHECK_MSG(strstr(limen_scene_error(f.s), "level-of-detail bound must be a finite number "
                                                 "of pixels >= 0, or LIMEN_LOD_FULL"),
                  "%s", limen_scene_error(f.s));
    }
    float good[] = { 0, LIMEN_LOD_FULL, 0.25f, 1e6f };
    for (int i = 0; i < 4; i++) {
        limen_plan_desc pd = { 0 };
        pd.limits.lod_pixels = good[i];
        CHECK_OK(limen_plan_build(p, f.s, &pd));
    }
    limen_plan_destroy(p);
    close_scene(&f);
}

/* Degenerate input costs what other input does: 80,000 copies of one triangle (half of them
 * wound the other way), then 80,000 of one with no area (three corners on a line). The
 * edges' pairing (core/lod_target.c) looks at a few slots a half-edge, not at every copy
 * before it (which took 24 s for the first); the copies wound opposite ways pair up, those
 * wound alike cannot. The whole build then makes the mesh and its levels. */
static void test_degenerate(void)
{
    enum { COPIES = 80000 };
    float pos[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0 };
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * COPIES);
    if (!idx) {
        CHECK(idx);
        return;
    }
    for (int flat = 0; flat < 2; flat++) {
        uint32_t c = flat ? 3 : 2;      /* (0,0,0) (1,0,0) (2,0,0): on a line */
        for (int t = 0; t < COPIES; t++) {
            idx[t * 3] = 0;
            idx[t * 3 + 1] = t % 2 ? c : 1;
            idx[t * 3 + 2] = t % 2 ? 1 : c;
        }
        limen__mesh m = { .nverts = 4, .ntris = COPIES, .pos = pos, .idx = idx };
        limen__lod_target tg = { 0 };
        CHECK(limen__lod_target_make(&tg, &m, NULL));
        uint64_t half_edges = 3ull * COPIES;
        CHECK_MSG(tg.probes <= 4 * half_edges, "%s: %llu probes for %llu half-edges",
                  flat ? "flat" : "copies", (unsigned long long)tg.probes,
                  (unsigned long long)half_edges);
        /* each copy wound one way pairs each edge with a copy wound the other */
        uint32_t paired = 0;
        for (uint32_t t = 0; tg.across && t < COPIES; t++)
            for (int e = 0; e < 3; e++)
                if (tg.across[t][e] != UINT32_MAX) {
                    paired++;
                    CHECK(tg.across[t][e] % 2 != t % 2);
                    CHECK(tg.across[tg.across[t][e]][0] == t ||
                          tg.across[tg.across[t][e]][1] == t ||
                          tg.across[tg.across[t][e]][2] == t);
                }
        CHECK_MSG(paired == 3u * COPIES, "%u of %u edges paired", paired, 3u * COPIES);
        limen__lod_target_free(&tg);
        fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
        limen_status st = limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
            .positions = pos, .vertex_count = 4, .indices = idx, .triangle_count = COPIES });
        if (flat) {
            /* a mesh with no area at all is refused, and said to be degenerate */
            CHECK(st == LIMEN_ERR_ARG && strstr(limen_scene_error(f.s), "degenerate"));
        } else {
            CHECK_OK(st);
            const limen_drawable *d = st ? NULL : item(&f);
            CHECK(d && d->mesh->lod_count >= 1 && d->mesh->triangle_count == COPIES);
        }
        close_scene(&f);
    }
    free(idx);
}

/* ------------------------------------------------------------------ assets */

/* How many of a level's triangles have corners of two charts (chart: per vertex). */
static int level_across(const limen_mesh_lod *lv, const int *chart)
{
    int across = 0;
    for (int t = 0; t < lv->triangle_count; t++) {
        const uint32_t *c = &lv->indices[t * 3];
        across += chart[c[0]] != chart[c[1]] || chart[c[0]] != chart[c[2]];
    }
    return across;
}

/* The levels of a textured mesh (data, each vertex in chart[v], what: its name in messages):
 * at least min_levels, the coarsest at most 1/fraction of the triangles where fraction > 0,
 * no level triangle across charts, each level's error at least the largest distance a
 * brute force finds on a lattice (and that distance above 0 where positive). */
static void chart_levels(const limen_mesh_data *data, const int *chart, int min_levels,
                         int fraction, bool positive, const char *what)
{
    fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, data));
    const limen_drawable *d = item(&f);
    tri_box *ft = d ? boxes_of(d->mesh, &d->mesh->lods[0]) : NULL;
    grid full = { 0 };
    if (ft && grid_make(&full, ft, d->mesh->triangle_count)) {
        const limen_mesh_geometry *g = d->mesh;
        int last = g->lods[g->lod_count - 1].triangle_count;
        CHECK_MSG(g->lod_count >= min_levels && (fraction <= 0 ||
                                                 last * fraction <= data->triangle_count),
                  "%s: %d levels, the coarsest %d triangles", what, g->lod_count, last);
        for (int k = 1; k < g->lod_count; k++) {
            const limen_mesh_lod *lv = &g->lods[k];
            int across = level_across(lv, chart);
            CHECK_MSG(across == 0, "%s, level %d: %d of %d triangles across charts", what, k,
                      across, lv->triangle_count);
            if (getenv("LIMEN_TEST_VERBOSE"))
                fprintf(stderr, "%s, level %d: %d triangles, error %g\n", what, k,
                        lv->triangle_count, lv->error);
            /* a lattice on every triangle: the largest distance lies where the charts meet
             * as often as anywhere */
            double found = brute_sampled(g, &full, k, 1, 4, 400);
            CHECK_MSG(found <= lv->error * (1 + 1e-5), "%s, level %d: error %g, found %g",
                      what, k, lv->error, found);
            CHECK(!positive || found > 0);
        }
    } else {
        CHECK(!"no mesh, or no memory for the brute force");
    }
    grid_free(&full);
    free(ft);
    close_scene(&f);
}

/* chart_levels over a's arrays (tests/charted.h). */
static void arrays_levels(const charted_arrays *a, int nv, int nt, int min_levels,
                          int fraction, bool positive, const char *what)
{
    chart_levels(&(limen_mesh_data){ .positions = a->pos, .normals = a->nrm, .uvs = a->uv,
                                     .vertex_count = nv, .indices = a->idx,
                                     .triangle_count = nt },
                 a->chart, min_levels, fraction, positive, what);
}

/* chart_levels over charted_ball(n, tile) (tests/charted.h), its charts tile x tile squares. */
static void ball_levels(int n, int tile, int min_levels, int fraction, bool positive,
                        const char *what)
{
    int nt = 5 * n * n * 2, nv = charted_verts(n, tile);
    charted_arrays a;
    if (charted_arrays_make(&a, nv, nt)) {
        charted_ball(n, tile, a.pos, a.nrm, a.uv, a.idx);
        for (int v = 0; v < nv; v++)
            a.chart[v] = charted_chart(tile, (uint32_t)v);
        arrays_levels(&a, nv, nt, min_levels, fraction, positive, what);
    } else {
        CHECK(!"out of memory");
    }
    charted_arrays_free(&a);
}

/* A textured asset of 16,000 triangles, as an exporter makes one (tests/charted.h): texture
 * charts of tile x tile squares, so seams along every edge between them (one position, two
 * texture coordinates), and an open side (a border). The seams and the border do not stop
 * the simplifier: at least min_levels levels (five or more: the coarsest at most 1/16 of
 * the triangles), each with an error that bounds a brute force's largest distance. No
 * triangle of any level takes its corners from two charts: the texture is not smeared
 * across a seam, each corner's texture coordinate is its own position's on the full mesh. */
static void asset_levels(int tile, int min_levels)
{
    char what[32];
    snprintf(what, sizeof what, "charts of %d", tile);
    ball_levels(40, tile, min_levels, min_levels >= 5 ? 16 : 0, true, what);
}

/* One chart a face; and 500 charts of 4 x 4 squares, whose corners (where four charts meet)
 * meshoptimizer's simplifier cannot move, nor the seams' vertices next to them, so it is
 * stuck at a quarter of the triangles: the coarse levels are made by collapses within the
 * charts (core/lod_charts.c), which move the seams along themselves up to those corners,
 * down to two triangles a chart, 1/16 of the triangles (five levels, the full mesh's
 * included). */
static void test_asset_levels(void)
{
    asset_levels(40, 6);
    asset_levels(4, 5);
}

/* Parts are seams too: the ball of five faces again, its texture coordinates now the same
 * on both sides of every edge between faces (no seam in the texture), but each face a part
 * of its own (a material each). No level's triangle takes corners from two parts, so none
 * is drawn in another part's material; without the parts in the weld, the simplifier joins
 * across their borders. */
static void test_part_seams(void)
{
    enum { N = 20, NV = 5 * (N + 1) * (N + 1), NT = 5 * N * N * 2 };
    charted_arrays a;       /* its charts: per vertex, its face, which is its part */
    if (!charted_arrays_make(&a, NV, NT)) {
        CHECK(!"out of memory");
        goto done;
    }
    float *pos = a.pos, *nrm = a.nrm, *uv = a.uv;
    uint32_t *idx = a.idx;
    int *part = a.chart;
    charted_ball(N, N, pos, nrm, uv, idx);
    for (int v = 0; v < NV; v++)
        part[v] = charted_chart(N, (uint32_t)v);
    for (int v = 0; v < NV; v++) {      /* the texture laid over the ball from the front */
        uv[v * 2] = 0.5f + 0.5f * pos[v * 3];
        uv[v * 2 + 1] = 0.5f + 0.5f * pos[v * 3 + 1];
    }
    limen_mesh_part parts[5];
    limen_material mats[5];
    memset(mats, 0, sizeof mats);
    for (int p = 0; p < 5; p++) {
        parts[p] = (limen_mesh_part){ p * N * N * 2, N * N * 2, p };
        mats[p].name = "";
        for (int c = 0; c < 4; c++)
            mats[p].base_color[c] = 1;
    }
    fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
        .positions = pos, .normals = nrm, .uvs = uv, .vertex_count = NV, .indices = idx,
        .triangle_count = NT, .part_count = 5, .parts = parts, .material_count = 5,
        .materials = mats }));
    const limen_drawable *d = item(&f);
    if (d) {
        const limen_mesh_geometry *g = d->mesh;
        CHECK_MSG(g->lod_count >= 5, "%d levels", g->lod_count);
        for (int k = 1; k < g->lod_count; k++) {
            const limen_mesh_lod *lv = &g->lods[k];
            int mixed = level_across(lv, part);
            /* the simplifier keeps them apart; the coarsest, clustered, may not */
            CHECK_MSG(mixed == 0 || lv->triangle_count * 32 < NT,
                      "level %d: %d of %d triangles across parts", k, mixed, lv->triangle_count);
        }
    }
    close_scene(&f);
done:
    charted_arrays_free(&a);
}

/* ------------------------------------------------------------------ the cache */

/* The levels of a bumpy sphere of u * v * 2 triangles, made in a scene of their own: their
 * counts, errors and indices, one after another, into *out (malloc'd); returns the levels. */
static int sphere_levels(int u, int v, float **out, size_t *len)
{
    int nv = (u + 1) * (v + 1), nt = u * v * 2;
    float *pos = malloc(sizeof(float) * 3 * (size_t)nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * (size_t)nt);
    *out = NULL;
    *len = 0;
    int levels = 0;
    if (pos && idx) {
        bumpy_sphere(u, v, pos, idx);
        fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
        CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
            .positions = pos, .vertex_count = nv, .indices = idx, .triangle_count = nt }));
        const limen_drawable *d = item(&f);
        if (d) {
            const limen_mesh_geometry *g = d->mesh;
            size_t n = 0;
            for (int k = 0; k < g->lod_count; k++)
                n += 2 + 3 * (size_t)g->lods[k].triangle_count;
            *out = malloc(sizeof(float) * n);
            for (int k = 0; *out && k < g->lod_count; k++) {
                (*out)[(*len)++] = (float)g->lods[k].triangle_count;
                (*out)[(*len)++] = g->lods[k].error;
                for (int i = 0; i < 3 * g->lods[k].triangle_count; i++)
                    (*out)[(*len)++] = (float)g->lods[k].indices[i];
            }
            levels = g->lod_count;
        }
        close_scene(&f);
    }
    free(pos);
    free(idx);
    return levels;
}

static long long mtime_ns(const char *path)
{
    struct stat st;
    return lstat(path, &st) ? -1 : st.st_mtim.tv_sec * 1000000000ll + st.st_mtim.tv_nsec;
}

static void set_old(const char *path, long sec)
{
    struct timespec t[2] = { { .tv_sec = sec }, { .tv_sec = sec } };
    utimensat(AT_FDCWD, path, t, AT_SYMLINK_NOFOLLOW);
}

static bool same_levels(const float *a, size_t na, const float *b, size_t nb)
{
    return a && b && na == nb && !memcmp(a, b, sizeof *a * na);
}

/* Levels kept between runs (core/lod_cache.c): the first load of a mesh stores one entry;
 * the next reads it (the entry is touched: used) and gets the same levels; an entry that is
 * damaged (a byte flipped, cut short, emptied), a link or a pipe is ignored (no hang, the
 * levels made again, the same), and a damaged one replaced by a whole one; LIMEN_CACHE=off
 * writes nothing; over the size limit the entry used least recently goes. */
static void test_cache(void)
{
    char dir[] = "/tmp/limen_lod_cacheXXXXXX", path[4200], other[4200];
    if (!mkdtemp(dir)) {
        CHECK(!"no temporary folder");
        return;
    }
    setenv("LIMEN_CACHE_DIR", dir, 1);
    unsetenv("LIMEN_CACHE");
    float *made, *again;
    size_t nmade, nagain;
    int levels = sphere_levels(40, 40, &made, &nmade);
    CHECK_MSG(levels >= 4, "%d levels", levels);
    CHECK(entries(dir, path, sizeof path) == 1);
    unsigned char whole[1 << 16];
    FILE *f = fopen(path, "rb");
    size_t size = f ? fread(whole, 1, sizeof whole, f) : 0;
    if (f)
        fclose(f);
    CHECK(size > 64 && size < sizeof whole);

    /* read back: the same levels, and the entry used */
    set_old(path, 1000000);
    sphere_levels(40, 40, &again, &nagain);
    CHECK(same_levels(made, nmade, again, nagain));
    CHECK(mtime_ns(path) > 1000000 * 1000000000ll);
    free(again);

    /* damaged: ignored, made again, and replaced by a whole entry; the last three whole
     * (their checksums made to match) but wrong: an index past the vertices, a level's count
     * above the one before, an error below the one before */
    for (int damage = 0; damage < 7; damage++) {
        f = fopen(path, "wb");
        if (f) {
            size_t at = 48 + 8 * (size_t)levels + 4 * 100;
            if (damage == 0) {                  /* an index moved to its neighbour */
                whole[at] ^= 0x01;
                fwrite(whole, 1, size, f);
                whole[at] ^= 0x01;
            } else if (damage == 1) {           /* cut short */
                fwrite(whole, 1, size - 9, f);
            } else if (damage == 2) {           /* a level's count raised, past the others */
                unsigned char bad[sizeof whole];
                memcpy(bad, whole, size);
                bad[8 + 40 + 8] ^= 0xff;
                fwrite(bad, 1, size, f);
            } else if (damage >= 4) {
                unsigned char bad[sizeof whole];
                memcpy(bad, whole, size);
                size_t lv = 8 + 40;     /* the levels' counts and errors */
                if (damage == 4) {
                    uint32_t past = 40 * 40 * 2 * 3;
                    memcpy(bad + lv + 8 * (size_t)levels + 4 * 7, &past, 4);
                } else if (damage == 5) {
                    uint32_t c;
                    memcpy(&c, bad + lv + 8 * 1, 4);
                    memcpy(bad + lv + 8 * 2, &c, 4);
                } else {
                    float e;
                    memcpy(&e, bad + lv + 8 * 2 + 4, 4);
                    e *= 0.5f;
                    memcpy(bad + lv + 8 * 3 + 4, &e, 4);
                }
                uint64_t sum = limen__lod_cache_checksum(bad, size - 8);
                memcpy(bad + size - 8, &sum, 8);
                fwrite(bad, 1, size, f);
            }                                   /* else (3) empty */
            fclose(f);
        }
        set_old(path, 1000000);
        sphere_levels(40, 40, &again, &nagain);
        CHECK_MSG(same_levels(made, nmade, again, nagain), "damage %d", damage);
        free(again);
        unsigned char back[sizeof whole];
        f = fopen(path, "rb");
        size_t nback = f ? fread(back, 1, sizeof back, f) : 0;
        if (f)
            fclose(f);
        CHECK_MSG(nback == size && !memcmp(back, whole, size), "damage %d: not replaced",
                  damage);
    }

    /* a pipe (which a careless open would wait on forever) and a link: left alone */
    unlink(path);
    CHECK(mkfifo(path, 0600) == 0);
    sphere_levels(40, 40, &again, &nagain);
    CHECK(same_levels(made, nmade, again, nagain));
    free(again);
    struct stat st;
    CHECK(lstat(path, &st) == 0 && S_ISFIFO(st.st_mode));
    unlink(path);
    snprintf(other, sizeof other, "%s/elsewhere", dir);
    f = fopen(other, "wb");
    if (f) {
        fwrite(whole, 1, size, f);
        fclose(f);
    }
    CHECK(symlink(other, path) == 0);
    set_old(other, 1000000);
    sphere_levels(40, 40, &again, &nagain);
    CHECK(same_levels(made, nmade, again, nagain));
    free(again);
    CHECK(lstat(path, &st) == 0 && S_ISLNK(st.st_mode));
    CHECK(mtime_ns(other) == 1000000 * 1000000000ll);  /* not read through the link */
    unlink(path);
    unlink(other);

    /* off: nothing written */
    setenv("LIMEN_CACHE", "off", 1);
    sphere_levels(40, 40, &again, &nagain);
    free(again);
    CHECK(entries(dir, path, sizeof path) == 0);
    unsetenv("LIMEN_CACHE");

    /* the size limit: room for one entry; the one used least recently goes */
    char limit[32];
    snprintf(limit, sizeof limit, "%.6f", (double)size * 1.5 / 1048576.0);
    setenv("LIMEN_CACHE_MB", limit, 1);
    sphere_levels(40, 40, &again, &nagain);
    free(again);
    CHECK(entries(dir, path, sizeof path) == 1);
    set_old(path, 1000000);
    snprintf(other, sizeof other, "%s", path);
    sphere_levels(40, 41, &again, &nagain);
    free(again);
    CHECK(entries(dir, path, sizeof path) == 1);
    CHECK(strcmp(path, other) != 0);
    unlink(path);
    unsetenv("LIMEN_CACHE_MB");

    free(made);
    rmdir(dir);
    setenv("LIMEN_CACHE", "off", 1);
    unsetenv("LIMEN_CACHE_DIR");
}

/* ------------------------------------------------------------------ on another thread */

typedef struct reader {
    const limen_scene *s;
    limen_node mesh;
    int odd;                    /* level counts other than one seen */
} reader;

/* Reads the mesh (const calls, as limen.h's THREADS allows beside one another) while its
 * levels are made. */
static void *read_mesh(void *arg)
{
    reader *r = arg;
    for (int i = 0; i < 2000; i++) {
        limen_mesh_info info;
        if (limen_mesh_get(r->s, r->mesh, &info) != LIMEN_OK || info.lod_count != 1)
            r->odd++;
    }
    return NULL;
}

/* A mesh's levels made on another thread (limen__mesh_lods_start, for a mesh above the size
 * set): the mesh is there at once with its full level alone, and stays so, to every reader,
 * until the scene's thread takes the levels (at a refresh, which every call that reads the
 * world makes): then they are the same levels, counts, errors and indices, as made on the
 * scene's thread, under a new id (the renderer uploads them). A scene destroyed while its
 * levels are made stops the thread and frees everything (the sanitizer build checks). */
static void test_async(void)
{
    enum { U = 100, V = 60, NV = (U + 1) * (V + 1), NT = U * V * 2 };
    float *pos = malloc(sizeof(float) * 3 * NV), *made = NULL;
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * NT);
    if (!pos || !idx) {
        CHECK(!"out of memory");
        free(pos);
        free(idx);
        return;
    }
    bumpy_sphere(U, V, pos, idx);
    limen_mesh_data data = { .positions = pos, .vertex_count = NV, .indices = idx,
                             .triangle_count = NT };
    size_t nmade = 0;
    int levels = sphere_levels(U, V, &made, &nmade);
    CHECK(levels >= 4);
    limen_mesh_info info;
    size_t bytes = 0;           /* what the mesh holds with its levels made in place */
    {
        fixture g = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
        CHECK_OK(limen_mesh_set_triangles(g.s, g.mesh, &data));
        CHECK_OK(limen_mesh_get(g.s, g.mesh, &info));
        bytes = info.bytes;
        close_scene(&g);
    }

    limen__lod_set_async_above(1000);
    fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &data));
    CHECK_OK(limen_mesh_get(f.s, f.mesh, &info));
    CHECK_MSG(info.lod_count == 1, "%d levels before the hand-over", info.lod_count);
    /* counted (against a script's memory cap) at no less than it will hold */
    CHECK_MSG(info.bytes >= bytes, "%zu bytes before the hand-over, %zu after", info.bytes,
              bytes);
    reader rd[2] = { { f.s, f.mesh, 0 }, { f.s, f.mesh, 0 } };
    pthread_t th[2];
    for (int i = 0; i < 2; i++)
        CHECK(pthread_create(&th[i], NULL, read_mesh, &rd[i]) == 0);
    for (int i = 0; i < 2; i++)
        pthread_join(th[i], NULL);
    CHECK(rd[0].odd == 0 && rd[1].odd == 0);
    const limen_drawable *d = item(&f);
    uint64_t id = d ? d->mesh->id : 0;
    bool waited = d && d->mesh->lod_count == 1;
    /* each refresh (here the drawables' build) takes the levels once they are made: waited
     * for, not timed (a second's work, given minutes on a busy machine) */
    for (int i = 0; i < 30000 && d && d->mesh->lod_count == 1; i++) {
        usleep(10000);
        d = item(&f);
    }
    if (d) {
        const limen_mesh_geometry *g = d->mesh;
        size_t n = 0;
        bool same = g->lod_count == levels;
        for (int k = 0; same && k < g->lod_count; k++) {
            same = n + 2 + 3 * (size_t)g->lods[k].triangle_count <= nmade &&
                   made[n] == (float)g->lods[k].triangle_count && made[n + 1] == g->lods[k].error;
            n += 2;
            for (int i = 0; same && i < 3 * g->lods[k].triangle_count; i++)
                same = made[n++] == (float)g->lods[k].indices[i];
        }
        CHECK_MSG(same && n == nmade, "%d levels handed over, %d made here", g->lod_count, levels);
        CHECK(!waited || g->id != id);
        CHECK_OK(limen_mesh_get(f.s, f.mesh, &info));
        CHECK_MSG(info.bytes == bytes, "%zu bytes, %zu made in place", info.bytes, bytes);
    }
    close_scene(&f);

    /* destroyed while the levels are made */
    for (int i = 0; i < 3; i++) {
        limen_scene *s;
        limen_node n;
        CHECK_OK(limen_scene_create(NULL, &s));
        CHECK_OK(limen_node_create(s, LIMEN_NODE_MESH, "m", &n));
        CHECK_OK(limen_mesh_set_triangles(s, n, &data));
        if (i == 2)
            usleep(20000);
        limen_scene_destroy(s);
    }
    limen__lod_set_async_above(LIMEN__LOD_ASYNC_TRIS);
    free(made);
    free(pos);
    free(idx);
}

/* ------------------------------------------------------------------ laying a piece over */

/* A mesh over the arrays (not copied: nverts vertices at pos, ntris triangles idx) with its
 * bounds, as core/lod.c's measuring takes the full mesh; its hierarchy not yet made. */
static limen__mesh bare_mesh(const float *pos, uint32_t nverts, const uint32_t *idx,
                             uint32_t ntris)
{
    limen__mesh m = { .nverts = nverts, .ntris = ntris, .pos = (float *)pos,
                      .idx = (uint32_t *)idx };
    for (int a = 0; a < 3; a++) {
        m.lo[a] = INFINITY;
        m.hi[a] = -INFINITY;
    }
    for (size_t v = 0; v < (size_t)nverts * 3; v++) {
        m.lo[v % 3] = fmin(m.lo[v % 3], pos[v]);
        m.hi[v % 3] = fmax(m.hi[v % 3], pos[v]);
    }
    return m;
}

/* The largest distance a brute force finds from the triangles a (na of them, a lattice of
 * `steps` on each) to the triangles b (nb), both over pos. */
static double lattice_dist(const float *pos, const uint32_t *a, int na, const uint32_t *b, int nb,
                           int steps)
{
    double worst = 0;
    for (int t = 0; t < na; t++)
        for (int i = 0; i <= steps; i++)
            for (int j = 0; i + j <= steps; j++) {
                double p[3], best = INFINITY;
                for (int x = 0; x < 3; x++)
                    p[x] = (1 - (double)(i + j) / steps) * pos[a[t * 3] * 3 + x] +
                           (double)i / steps * pos[a[t * 3 + 1] * 3 + x] +
                           (double)j / steps * pos[a[t * 3 + 2] * 3 + x];
                for (int u = 0; u < nb; u++) {
                    double c[3][3];
                    for (int k = 0; k < 3; k++)
                        for (int x = 0; x < 3; x++)
                            c[k][x] = pos[b[u * 3 + k] * 3 + x];
                    best = fmin(best, tri_dist(p, c[0], c[1], c[2]));
                }
                worst = fmax(worst, best);
            }
    return worst;
}

/* A level's triangle far larger than the full mesh's is bounded by laying it over them whole
 * (core/lod.c lay_bound: the triangles under it, seen along its normal, cover it where their
 * border stays outside it). On random bumpy grids, some with a hole or a fold (an overhang,
 * seen turned over) under a coarse triangle: the bound (limen__lod_measure) is at least a
 * brute force's largest distance, either way, and within 30% of it. Fails where a border
 * inside the piece (the hole's) is let pass, or where nothing covers the piece (a hole that
 * is exactly a level's triangle) and the count of covering triangles is not checked. */
static void test_lay_bound(void)
{
    enum { G = 16, K = 4, NV = (G + 1) * (G + 1) };
    float pos[NV * 3];
    uint32_t idx[G * G * 6], lidx[(G / K) * (G / K) * 6];
    for (int seed = 0; seed < 9; seed++) {
        double f[3][3];
        for (int k = 0; k < 3; k++)
            for (int x = 0; x < 3; x++)
                f[k][x] = uniform();
        for (int j = 0; j <= G; j++)
            for (int i = 0; i <= G; i++) {
                double x = (double)i / G, y = (double)j / G, z = 0;
                for (int k = 0; k < 3; k++)
                    z += 0.004 * sin(6.28 * (1 + 3 * f[k][0]) * x + 6.28 * (1 + 3 * f[k][1]) * y +
                                    6.28 * f[k][2]);
                z += 0.002 * (uniform() - 0.5);
                pos[(j * (G + 1) + i) * 3] = (float)x;
                pos[(j * (G + 1) + i) * 3 + 1] = (float)y;
                pos[(j * (G + 1) + i) * 3 + 2] = (float)z;
            }
        /* a hole of 2 x 2 cells (seeds 1, 3, ...), or a fold (seeds 2, 6): a column of
         * vertices pushed past its neighbours, so that a strip of cells is seen turned over
         * and the sheet runs back over itself */
        int hx = 1 + (int)(uniform() * (G - 3)), hy = 1 + (int)(uniform() * (G - 3));
        bool hole = seed % 2 == 1, fold = seed % 4 == 2;
        if (fold)
            for (int j = 0; j <= G; j++)
                pos[(j * (G + 1) + hx) * 3] += (float)(1.6 / G);
        /* or (seed 8) a hole that is exactly a level's triangle: the full mesh meets it
         * only along its border */
        bool tile = seed == 8;
        int lt = 0;
        for (int j = 0; j < G; j += K)
            for (int i = 0; i < G; i += K) {
                uint32_t a = (uint32_t)(j * (G + 1) + i), b = a + K, c = a + K * (G + 1),
                         d = c + K;
                bool flip = uniform() < 0.5 && !(tile && lt == 0);
                uint32_t q[2][6] = { { a, b, d, a, d, c }, { a, b, c, b, d, c } };
                memcpy(&lidx[lt * 3], q[flip], sizeof q[0]);
                lt += 2;
            }
        int nt = 0;
        for (int j = 0; j < G; j++)
            for (int i = 0; i < G; i++) {
                if (hole && i >= hx && i < hx + 2 && j >= hy && j < hy + 2)
                    continue;
                uint32_t a = (uint32_t)(j * (G + 1) + i), b = a + 1, c = a + G + 1, d = c + 1;
                uint32_t q[6] = { a, b, d, a, d, c };
                /* the first level triangle, (0,0) (K,0) (K,K), holds the cells below its
                 * diagonal and the lower halves of those on it */
                if (tile && i < K && j < K && j <= i) {
                    if (j == i) {
                        memcpy(&idx[nt * 3], q + 3, sizeof q / 2);
                        nt++;
                    }
                    continue;
                }
                memcpy(&idx[nt * 3], q, sizeof q);
                nt += 2;
            }
        limen__mesh m = bare_mesh(pos, NV, idx, (uint32_t)nt);
        CHECK(limen__mesh_bvh(&m));
        double e = m.bvh ? limen__lod_measure(&m, lidx, (uint32_t)lt) : NAN;
        double found = fmax(lattice_dist(pos, lidx, lt, idx, nt, 16),
                            lattice_dist(pos, idx, nt, lidx, lt, 4));
        CHECK_MSG(found <= e * (1 + 1e-5), "seed %d%s: bound %g, found %g", seed,
                  hole ? " (hole)" : fold ? " (fold)" : tile ? " (tile)" : "", e, found);
        CHECK_MSG(e <= found * 1.3, "seed %d%s: bound %g, found %g", seed,
                  hole ? " (hole)" : fold ? " (fold)" : tile ? " (tile)" : "", e, found);
        free(m.bvh);
        free(m.tri_order);
    }
}

/* ------------------------------------------------------------------ whole across charts */

/* Vertices in the order of their positions (sort_pos: the mesh's), by index where the same. */
static const float *sort_pos;

static int pos_cmp(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    int c = memcmp(&sort_pos[x * 3], &sort_pos[y * 3], sizeof(float) * 3);
    return c ? c : (x > y) - (x < y);
}

static int edge_cmp(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The edges of a level between welded positions (id), sorted, into edges (3 a triangle). */
static void level_edges(const limen_mesh_lod *lv, const uint32_t *id, uint64_t *edges)
{
    for (int t = 0; t < lv->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = id[lv->indices[t * 3 + k]], b = id[lv->indices[t * 3 + (k + 1) % 3]];
            edges[t * 3 + k] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(edges, (size_t)lv->triangle_count * 3, sizeof *edges, edge_cmp);
}

/* The 500-chart ball's levels (tests/charted.h) are whole where the charts meet: welded by
 * position, every edge of a level has two triangles (one on each side of a seam, each in
 * its own chart, with its own texture coordinates) or more (meshoptimizer's finer levels
 * may hold a fin: two triangles back to back), but the open side's, whose ends lie on the
 * full mesh's open side. A seam moved on one side alone would leave a crack: an edge of one
 * triangle there. */
static void test_chart_levels_whole(void)
{
    enum { N = 40, TILE = 4, NT = 5 * N * N * 2 };
    int nv = charted_verts(N, TILE);
    float *pos = malloc(sizeof(float) * 3 * nv), *nrm = malloc(sizeof(float) * 3 * nv),
          *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * NT), *order = malloc(sizeof(uint32_t) * nv),
             *id = malloc(sizeof(uint32_t) * nv);
    uint64_t *edges = malloc(sizeof(uint64_t) * 3 * NT);
    bool *rim = calloc(nv, sizeof *rim);
    if (!pos || !nrm || !uv || !idx || !order || !id || !edges || !rim) {
        CHECK(!"out of memory");
        goto done;
    }
    charted_ball(N, TILE, pos, nrm, uv, idx);
    fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
        .positions = pos, .normals = nrm, .uvs = uv, .vertex_count = nv, .indices = idx,
        .triangle_count = NT }));
    const limen_drawable *d = item(&f);
    if (d) {
        const limen_mesh_geometry *g = d->mesh;
        for (int v = 0; v < nv; v++)
            order[v] = (uint32_t)v;
        sort_pos = g->positions;
        qsort(order, nv, sizeof *order, pos_cmp);
        for (int i = 0; i < nv; i++)
            id[order[i]] = i > 0 && !memcmp(&g->positions[order[i] * 3],
                                            &g->positions[order[i - 1] * 3], sizeof(float) * 3)
                               ? id[order[i - 1]]
                               : order[i];
        CHECK_MSG(g->lod_count >= 5, "%d levels", g->lod_count);
        for (int k = 0; k < g->lod_count; k++) {
            const limen_mesh_lod *lv = &g->lods[k];
            size_t ne = (size_t)lv->triangle_count * 3;
            level_edges(lv, id, edges);
            int open = 0, astray = 0;
            for (size_t i = 0; i < ne;) {
                size_t j = i;
                while (j < ne && edges[j] == edges[i])
                    j++;
                uint32_t a = (uint32_t)(edges[i] >> 32), b = (uint32_t)edges[i];
                if (j - i == 1) {
                    open++;
                    if (k == 0)
                        rim[a] = rim[b] = true;     /* the full mesh's open side */
                    else
                        astray += !rim[a] || !rim[b];
                }
                i = j;
            }
            CHECK_MSG(astray == 0 && open > 0, "level %d (%d triangles): %d open edges, %d of "
                      "them off the open side", k, lv->triangle_count, open, astray);
        }
    }
    close_scene(&f);
done:
    free(pos);
    free(nrm);
    free(uv);
    free(idx);
    free(order);
    free(id);
    free(edges);
    free(rim);
}

/* Vertices in the order of their positions and texture coordinates (sort_pos, sort_uv). */
static const float *sort_uv;

static int pos_uv_cmp(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    int c = memcmp(&sort_pos[x * 3], &sort_pos[y * 3], sizeof(float) * 3);
    if (!c)
        c = memcmp(&sort_uv[x * 2], &sort_uv[y * 2], sizeof(float) * 2);
    return c ? c : (x > y) - (x < y);
}

static uint32_t chart_of(uint32_t *up, uint32_t v)
{
    while (up[v] != v)
        v = up[v] = up[up[v]];
    return v;
}

/* A textured model with parts (the spider: five materials, each its own texture) keeps its
 * levels (seven, down to 1/50 of its triangles, where levels that ended at the first
 * across its charts left five: its legs, closed thin parts, flatten into fins; six asked,
 * down to 1/20), and no triangle of any level takes corners from two of its charts (found
 * here: corners joined by the full mesh's triangles and where two vertices share position
 * and texture coordinates), which would show the texture between them smeared. */
static void test_textured_levels_in_charts(void)
{
    fixture f = open_scene((float[3]){ 0, 60, 110 }, (float[3]){ 0, 0, 0 });
    CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/spider/spider.obj"));
    const limen_drawable *d = item(&f);
    const limen_mesh_geometry *g = d ? d->mesh : NULL;
    uint32_t *up = g ? malloc(sizeof *up * g->vertex_count) : NULL,
             *order = g ? malloc(sizeof *order * g->vertex_count) : NULL;
    int *chart = g ? malloc(sizeof *chart * g->vertex_count) : NULL;
    if (!g || !g->uvs || !up || !order || !chart) {
        CHECK(!"no textured mesh, or no memory");
        goto done;
    }
    int nv = g->vertex_count;
    for (int v = 0; v < nv; v++)
        up[v] = order[v] = (uint32_t)v;
    for (int t = 0; t < g->triangle_count; t++)
        for (int k = 1; k < 3; k++)
            up[chart_of(up, g->indices[t * 3 + k])] = chart_of(up, g->indices[t * 3]);
    sort_pos = g->positions;
    sort_uv = g->uvs;
    qsort(order, nv, sizeof *order, pos_uv_cmp);
    for (int i = 1; i < nv; i++)
        if (!memcmp(&g->positions[order[i] * 3], &g->positions[order[i - 1] * 3],
                    sizeof(float) * 3) &&
            !memcmp(&g->uvs[order[i] * 2], &g->uvs[order[i - 1] * 2], sizeof(float) * 2))
            up[chart_of(up, order[i])] = chart_of(up, order[i - 1]);
    int last = g->lods[g->lod_count - 1].triangle_count;
    CHECK_MSG(g->lod_count >= 6 && last * 20 <= g->triangle_count, "%d levels, the coarsest %d "
              "triangles of %d", g->lod_count, last, g->triangle_count);
    for (int v = 0; v < nv; v++)
        chart[v] = (int)chart_of(up, (uint32_t)v);
    for (int k = 1; k < g->lod_count; k++) {
        const limen_mesh_lod *lv = &g->lods[k];
        int across = level_across(lv, chart);
        CHECK_MSG(across == 0, "level %d: %d of %d triangles across charts", k, across,
                  lv->triangle_count);
    }
done:
    free(up);
    free(order);
    free(chart);
    close_scene(&f);
}

/* The ball's charts as bricks (tests/charted.h charted_bricks: 8 x 4 squares, every other
 * row shifted by half a brick, 275 charts), where three charts meet at each corner, as on a
 * model an exporter unwrapped: such a corner stays where it is (no neighbour lies on all
 * three charts), and a brick keeps its four corners and the two where its neighbours'
 * sides end on it, so about four triangles: the fewest the charts allow are 990. The levels
 * reach them, five down to 1/16 of the triangles (meshoptimizer alone stuck at 2,531
 * triangles: four levels; halving within the charts then stops at 1,265, from which 990 is
 * too small a step, which ended the levels at 1/12.6: now a level's target steps down to
 * the floor, core/lod_charts.c limen__lod_charts_want), no triangle of any across two
 * charts, and each level's error bounds a brute force's largest distance. */
static void test_brick_charts(void)
{
    enum { N = 40, BW = 8, BH = 4, NT = 5 * N * N * 2 };
    int nv = charted_bricks(N, BW, BH, NULL, NULL, NULL, NULL, NULL);
    charted_arrays a;
    if (charted_arrays_make(&a, nv, NT)) {
        CHECK(charted_bricks(N, BW, BH, a.pos, a.nrm, a.uv, a.idx, a.chart) == nv);
        arrays_levels(&a, nv, NT, 5, 16, false, "bricks");
    } else {
        CHECK(!"out of memory");
    }
    charted_arrays_free(&a);
}

/* Concave charts (tests/charted.h charted_ells: each 2 x 2 block of 4 x 4 squares an L of
 * three and the square of the fourth, 250 charts), whose L's inner corner (two charts alone
 * meet there) moves along its seams: the levels keep to the charts, five down to 1/16 of
 * the triangles (1,000), and each level's error bounds a brute force's largest distance. The
 * level after, where the inner corners have moved onto the seams' ends and the L shows its
 * texture over half the square, is not kept: its seams lie 0.15 from the full mesh's, its
 * bound 0.06 (core/lod.c, limen__lod_rim_drift). */
static void test_concave_charts(void)
{
    enum { N = 40, NT = 5 * N * N * 2 };
    int *square = malloc(sizeof(int) * 5 * N * N);
    int nv = square ? (charted_ells(N, 4, square), charted_layout(N, square, NULL, NULL, NULL,
                                                                    NULL, NULL))
                    : -1;
    charted_arrays a;
    if (charted_arrays_make(&a, nv, NT)) {
        CHECK(charted_layout(N, square, a.pos, a.nrm, a.uv, a.idx, a.chart) == nv);
        arrays_levels(&a, nv, NT, 5, 16, false, "concave");
    } else {
        CHECK(!"out of memory");
    }
    free(square);
    charted_arrays_free(&a);
}

/* A ball of 980 charts (3 x 3 squares each, four meeting at every corner, 17,640
 * triangles): a chart keeps at least two triangles, so the charts allow no fewer than
 * 1,960 (1/9), and the levels reach them (where halving and then the floor did not both fit
 * in the levels' room, the levels stopped at 2,940: core/lod_charts.c
 * limen__lod_charts_want); within the charts, each level's error above a brute force's
 * largest distance. 1/16 would need triangles across charts. */
static void test_many_charts(void)
{
    enum { N = 42, TILE = 3, NT = 5 * N * N * 2, CHARTS = 5 * (N / TILE) * (N / TILE) };
    ball_levels(N, TILE, 4, NT / (2 * CHARTS), false, "980 charts");
}

/* A ball where every square is a chart of its own (8,000 charts): the charts allow no
 * fewer triangles than the full mesh has, and meshoptimizer is stuck on its seams at once,
 * before any level: the levels within the charts start from the full mesh (their floor
 * found from it too), and none is kept where each would cross charts. */
static void test_square_charts(void)
{
    asset_levels(1, 1);
}

/* ------------------------------------------------------------------ measuring, kept numbers */

/* The measure of each level of g against its full mesh, with what the measuring keeps for
 * the pieces after (lay_bound's vertices as a piece sees them, convex_bound's distances from
 * a vertex to a triangle: core/lod.c) on or off, into e[k]; false where it could not run. */
static bool measures(const limen_mesh_geometry *g, bool memo, double e[12])
{
    limen__mesh m = bare_mesh(g->positions, (uint32_t)g->vertex_count, g->indices,
                              (uint32_t)g->triangle_count);
    if (!limen__mesh_bvh(&m))
        return false;
    limen__lod_set_measure_memo(memo);
    for (int k = 1; k < g->lod_count && k < 12; k++)
        e[k] = limen__lod_measure(&m, g->lods[k].indices, (uint32_t)g->lods[k].triangle_count);
    limen__lod_set_measure_memo(true);
    free(m.bvh);
    free(m.tri_order);
    return true;
}

/* What the measuring keeps for the pieces after is what it would find again: every level's
 * measure (the bunny's, a bumpy sphere's of 34,000 triangles, more vertices than
 * lay_bound's table has slots, shuffled, measured on two threads) the
 * same to the bit with it kept and found anew each time. Fails where a kept number is
 * given to a piece or a pair it is not of (a vertex's distance to another triangle, a
 * vertex seen from another piece). */
static void test_measure_memo(void)
{
    enum { U = 170, V = 100, NV = (U + 1) * (V + 1), NT = U * V * 2 };
    float *pos = malloc(sizeof(float) * 3 * NV);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * NT);
    CHECK(pos && idx);
    for (int mesh = 0; pos && idx && mesh < 2; mesh++) {
        fixture f = open_scene((float[3]){ 0, 0, 5 }, (float[3]){ 0, 0, 0 });
        if (mesh == 0) {
            CHECK_OK(limen_mesh_load(f.s, f.mesh, "scenes/data/bunny.obj"));
        } else {
            bumpy_sphere(U, V, pos, idx);
            /* its vertices shuffled, so that a piece meets vertices far apart in number */
            uint32_t *to = malloc(sizeof *to * NV);
            float *moved = malloc(sizeof(float) * 3 * NV);
            CHECK(to && moved);
            for (int v = 0; to && moved && v < NV; v++)
                to[v] = (uint32_t)v;
            for (int v = NV - 1; to && moved && v > 0; v--) {
                int o = (int)(uniform() * (v + 1)) % (v + 1);
                uint32_t sw = to[v];
                to[v] = to[o];
                to[o] = sw;
            }
            for (int v = 0; to && moved && v < NV; v++)
                memcpy(&moved[to[v] * 3], &pos[v * 3], sizeof(float) * 3);
            for (int i = 0; to && moved && i < NT * 3; i++)
                idx[i] = to[idx[i]];
            CHECK_OK(limen_mesh_set_triangles(f.s, f.mesh, &(limen_mesh_data){
                .positions = moved ? moved : pos, .vertex_count = NV, .indices = idx,
                .triangle_count = NT }));
            free(to);
            free(moved);
        }
        const limen_drawable *d = item(&f);
        double kept[12] = { 0 }, anew[12] = { 0 };
        CHECK(d && d->mesh->lod_count >= 5);
        if (d && measures(d->mesh, true, kept) && measures(d->mesh, false, anew)) {
            for (int k = 1; k < d->mesh->lod_count && k < 12; k++)
                CHECK_MSG(kept[k] == anew[k] && kept[k] > 0,
                          "%s, level %d: %a kept, %a found anew", mesh ? "sphere" : "bunny",
                          k, kept[k], anew[k]);
        } else {
            CHECK(!"no mesh, or no memory for its hierarchy");
        }
        close_scene(&f);
    }
    free(pos);
    free(idx);
}

/* A bumpy sphere of U x V quads made into a scene, its mesh bare for the measuring (with its
 * hierarchy) and the full mesh's triangles on a grid for the brute force. */
typedef struct measured {
    fixture f;
    const limen_mesh_geometry *g;
    limen__mesh m;
    tri_box *ft;
    grid full;
    bool ok;                    /* all of it made, with at least `levels` levels */
} measured;

static measured measured_sphere(int u, int v, int levels)
{
    measured s = { .f = sphere_scene(u, v) };
    const limen_drawable *d = item(&s.f);
    s.g = d ? d->mesh : NULL;
    s.m = bare_mesh(s.g ? s.g->positions : NULL, s.g ? (uint32_t)((u + 1) * (v + 1)) : 0,
                    s.g ? s.g->indices : NULL, (uint32_t)(u * v * 2));
    s.ft = s.g ? boxes_of(s.g, &s.g->lods[0]) : NULL;
    s.ok = s.g && s.g->lod_count >= levels && limen__mesh_bvh(&s.m) && s.ft &&
           grid_make(&s.full, s.ft, s.g->triangle_count);
    CHECK_MSG(s.ok, "no levels, or no memory for the hierarchy or the brute force");
    return s;
}

static void measured_free(measured *s)
{
    grid_free(&s->full);
    free(s->ft);
    free(s->m.bvh);
    free(s->m.tri_order);
    close_scene(&s->f);
}

/* Whether every triangle of the level lv (its boxes lt) has no point of a lattice on it
 * farther from the full mesh than its own bound (own); `checked` counts those looked at. */
static bool own_bounds_hold(const measured *s, const limen_mesh_lod *lv, const tri_box *lt,
                            const float *own, int *checked)
{
    for (int t = 0; t < lv->triangle_count; t++, (*checked)++) {
        double found = tri_sampled(&s->full, lt, t, 4);
        if (!(found <= own[t] * (1 + 1e-5) + 1e-9)) {
            CHECK_MSG(false, "%d triangles: triangle %d's bound %g, found %g", lv->triangle_count,
                      t, own[t], found);
            return false;
        }
    }
    return true;
}

/* A coarse level's pieces laid first over a finer level (within its bound of the full
 * mesh; core/lod.c's via_bound), as the build does for the coarse levels of a big mesh:
 * some pieces settle there (fails where none does: the finer level never asked, or asked
 * to settle more than the answer holds), the bound is no looser than laying every piece
 * over the full mesh (within 1%: the pieces cut differ) and still bounds a brute force's
 * largest distance. */
static void test_via_levels(void)
{
    enum { U = 200, V = 160, NT = U * V * 2 };
    measured s = measured_sphere(U, V, 8);
    const limen_mesh_geometry *g = s.g;
    uint64_t settled = 0;
    int asked = 0;
    if (s.ok) {
        for (int k = 3; k < g->lod_count; k++) {
            /* the coarsest finer level within 0.6 of the level before's bound, as the build */
            int j = k - 1;
            while (j >= 1 && !(g->lods[j].error <= 0.6 * g->lods[k - 1].error))
                j--;
            if (j < 1 || g->lods[j].triangle_count * 8 > NT)
                continue;
            const limen_mesh_lod *lv = &g->lods[k], *fine = &g->lods[j];
            uint64_t n = 0;
            double direct = limen__lod_measure(&s.m, lv->indices, (uint32_t)lv->triangle_count),
                   via = limen__lod_measure_via(&s.m, lv->indices, (uint32_t)lv->triangle_count,
                                                fine->indices, (uint32_t)fine->triangle_count,
                                                fine->error, &n),
                   found = brute_sampled(g, &s.full, k, 1, 6, 400);
            settled += n;
            asked++;
            CHECK_MSG(via <= direct * 1.01 && found <= via * (1 + 1e-5),
                      "level %d over level %d: %a, over the full mesh %a, found %a", k, j, via,
                      direct, found);
        }
    }
    CHECK_MSG(asked >= 2 && settled > 0, "%d levels over a finer one, %llu pieces settled",
              asked, (unsigned long long)settled);
    measured_free(&s);
}

/* Each triangle of a level keeps its own bound, which the next level's pieces add to their
 * offsets over it (via_pick): each such bound holds every point of its triangle found on a
 * lattice, the level's measured directly and the next level's measured over it; and the next
 * level's pieces are settled that way, its error no looser than measured directly. */
static void test_local_bounds(void)
{
    measured s = measured_sphere(120, 100, 6);
    int checked = 0;
    if (s.ok) {
        const limen_mesh_lod *a = &s.g->lods[3], *b = &s.g->lods[4];
        float *la = malloc(sizeof *la * (size_t)a->triangle_count),
              *lb = malloc(sizeof *lb * (size_t)b->triangle_count);
        tri_box *ta = boxes_of(s.g, a), *tb = boxes_of(s.g, b);
        uint64_t before = limen__lod_local_settled();
        double ea = la ? limen__lod_measure_local(&s.m, a->indices, (uint32_t)a->triangle_count,
                                                   NULL, 0, NULL, la)
                       : NAN,
               eb = lb && !isnan(ea)
                        ? limen__lod_measure_local(&s.m, b->indices, (uint32_t)b->triangle_count,
                                                   a->indices, (uint32_t)a->triangle_count, la, lb)
                        : NAN,
               direct = limen__lod_measure(&s.m, b->indices, (uint32_t)b->triangle_count);
        uint64_t settled = limen__lod_local_settled() - before;
        CHECK_MSG(!isnan(ea) && !isnan(eb) && ta && tb, "measured: %g %g", ea, eb);
        if (ta && !isnan(ea) && own_bounds_hold(&s, a, ta, la, &checked) && tb && !isnan(eb))
            own_bounds_hold(&s, b, tb, lb, &checked);
        CHECK_MSG(settled >= (uint64_t)b->triangle_count / 4 && eb <= direct * 1.01,
                  "%llu pieces settled over level 3; level 4 %g, directly %g",
                  (unsigned long long)settled, eb, direct);
        free(la);
        free(lb);
        free(ta);
        free(tb);
    }
    CHECK(checked > 0);
    measured_free(&s);
}

static const check_case cases[] = {
    { "bunny_levels", test_bunny_levels },
    { "error_bounds", test_error_bounds },
    { "big_bounds", test_big_bounds },
    { "local_bounds", test_local_bounds },
    { "measure_threads", test_measure_threads },
    { "flat_grid", test_flat_grid },
    { "seam_sides", test_seam_sides },
    { "pick", test_pick },
    { "pick_scaled_portal", test_pick_scaled_portal },
    { "plan_json", test_plan_json },
    { "lod_pixels", test_lod_pixels },
    { "degenerate", test_degenerate },
    { "cache", test_cache },
    { "asset_levels", test_asset_levels },
    { "part_seams", test_part_seams },
    { "async", test_async },
    { "lay_bound", test_lay_bound },
    { "chart_levels_whole", test_chart_levels_whole },
    { "textured_levels_in_charts", test_textured_levels_in_charts },
    { "brick_charts", test_brick_charts },
    { "concave_charts", test_concave_charts },
    { "many_charts", test_many_charts },
    { "square_charts", test_square_charts },
    { "measure_memo", test_measure_memo },
    { "via_levels", test_via_levels },
    { 0 },
};

int main(int argc, char **argv)
{
    /* the levels checked are the ones made here, not ones kept from an earlier build */
    setenv("LIMEN_CACHE", "off", 1);
    return check_run(argc, argv, cases);
}
