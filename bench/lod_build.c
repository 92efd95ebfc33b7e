/* lod_build.c - what making a mesh costs: limen_mesh_set_triangles (the ray tracer's
 * hierarchy, the levels of detail and each level's measured error, src/core/lod.c) on bumpy
 * spheres of 50,000, 200,000, 800,000 and 1,600,000 triangles made here, on the bunny, and
 * on a textured asset of 16,000 triangles in 500 texture charts (tests/charted.h). Processor
 * time (medians) beside wall time, with the cache of levels off (core/lod_cache.c); the
 * growth from 50k to 800k per triangle, measured in one run (1 means linear). Then the
 * biggest sphere with the cache on, in a folder of its own: made and stored, then made again
 * from the cache, and the second against the first. The spheres are tests/bumpy.h's.
 *
 *   lod_build [--out DIR] [--mesh FILE] [--full]
 *
 * Writes DIR/lod_build.csv and DIR/lod_build.txt; a line per mesh on stderr. --full times
 * the biggest spheres three times instead of once. Peak memory is the process's: run it
 * under /usr/bin/time -v to see it. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/internal.h"
#include "core/mesh.h"
#include "../tests/bumpy.h"
#include "../tests/charted.h"
#include "timing.h"

static void die(const char *what)
{
    fprintf(stderr, "lod_build: %s\n", what);
    exit(1);
}

typedef struct arrays {
    float *pos, *nrm, *uv;      /* nrm, uv: NULL, or per vertex */
    uint32_t *idx;
    int nv, nt;
} arrays;

/* charted_ball's arrays (tests/charted.h): n x n squares a face, charts of tile x tile. */
static arrays asset(int n, int tile)
{
    arrays a = { .nv = charted_verts(n, tile), .nt = 5 * n * n * 2 };
    a.pos = malloc(sizeof(float) * 3 * (size_t)a.nv);
    a.nrm = malloc(sizeof(float) * 3 * (size_t)a.nv);
    a.uv = malloc(sizeof(float) * 2 * (size_t)a.nv);
    a.idx = malloc(sizeof(uint32_t) * 3 * (size_t)a.nt);
    if (!a.pos || !a.nrm || !a.uv || !a.idx)
        die("out of memory");
    charted_ball(n, tile, a.pos, a.nrm, a.uv, a.idx);
    return a;
}

/* bumpy_sphere's arrays (tests/bumpy.h). */
static arrays sphere(int u, int v)
{
    arrays a = { .nv = (u + 1) * (v + 1), .nt = u * v * 2 };
    a.pos = malloc(sizeof(float) * 3 * (size_t)a.nv);
    a.idx = malloc(sizeof(uint32_t) * 3 * (size_t)a.nt);
    if (!a.pos || !a.idx)
        die("out of memory");
    bumpy_sphere(u, v, a.pos, a.idx);
    return a;
}

/* Node n's mesh as the renderer reads it, through *d (the caller destroys it). */
static const limen_mesh_geometry *geometry_of(limen_scene *s, limen_node n, limen_drawables **d)
{
    const limen_drawable *all;
    if (limen_drawables_create(d) || limen_drawables_build(*d, s))
        die("cannot list the mesh");
    limen_drawables_items(*d, &all);
    return all[limen_drawables_find(*d, n)].mesh;
}

/* The bunny's arrays, as the file loads them. */
static arrays from_file(const char *path)
{
    limen_scene *s;
    limen_node n;
    if (limen_scene_create(NULL, &s) || limen_node_create(s, LIMEN_NODE_MESH, "m", &n) ||
        limen_mesh_load(s, n, path))
        die("cannot load the mesh (is the file there?)");
    limen_drawables *d;
    const limen_mesh_geometry *g = geometry_of(s, n, &d);
    arrays a = { .nv = g->vertex_count, .nt = g->triangle_count };
    a.pos = malloc(sizeof(float) * 3 * (size_t)a.nv);
    a.idx = malloc(sizeof(uint32_t) * 3 * (size_t)a.nt);
    if (!a.pos || !a.idx)
        die("out of memory");
    memcpy(a.pos, g->positions, sizeof(float) * 3 * (size_t)a.nv);
    memcpy(a.idx, g->indices, sizeof(uint32_t) * 3 * (size_t)a.nt);
    limen_drawables_destroy(d);
    limen_scene_destroy(s);
    return a;
}

/* The median processor time of `runs` makings of a mesh from a (ms), its levels included
 * (made on another thread for a big mesh: waited for), *wall their median wall time, *first
 * the median wall time until the mesh is there to draw (limen_mesh_set_triangles returns);
 * *levels, *coarsest and errors (12): what the last one made. */
static double make_ms(const arrays *a, int runs, double *wall, double *first, int *levels,
                      int *coarsest, float *errors)
{
    double t[16], w[16], f[16];
    for (int r = 0; r < runs; r++) {
        limen_scene *s;
        limen_node n;
        if (limen_scene_create(NULL, &s) || limen_node_create(s, LIMEN_NODE_MESH, "m", &n))
            die("cannot make a scene");
        double t0 = cpu_ms(), w0 = now_ms();
        limen_status st = limen_mesh_set_triangles(s, n, &(limen_mesh_data){
            .positions = a->pos, .normals = a->nrm, .uvs = a->uv, .vertex_count = a->nv,
            .indices = a->idx, .triangle_count = a->nt });
        f[r] = now_ms() - w0;
        limen__meshes_settle(s, true);
        t[r] = cpu_ms() - t0;
        w[r] = now_ms() - w0;
        if (st)
            die(limen_scene_error(s));
        limen_drawables *d;
        const limen_mesh_geometry *g = geometry_of(s, n, &d);
        *levels = g->lod_count;
        *coarsest = g->lods[g->lod_count - 1].triangle_count;
        for (int k = 0; k < g->lod_count && k < 12; k++)
            errors[k] = g->lods[k].error;
        limen_drawables_destroy(d);
        limen_scene_destroy(s);
    }
    *wall = median(w, runs);
    *first = median(f, runs);
    return median(t, runs);
}

int main(int argc, char **argv)
{
    const char *out = "build/bench", *mesh = "scenes/data/bunny.obj";
    bool full = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc)
            out = argv[++i];
        else if (!strcmp(argv[i], "--mesh") && i + 1 < argc)
            mesh = argv[++i];
        else if (!strcmp(argv[i], "--full"))
            full = true;
        else
            die("usage: lod_build [--out DIR] [--mesh FILE] [--full]");
    }
    char path[512];
    limen__out oc, ot;
    snprintf(path, sizeof path, "%s/lod_build.csv", out);
    if (limen__out_open(&oc, path))
        die("cannot write the results");
    snprintf(path, sizeof path, "%s/lod_build.txt", out);
    if (limen__out_open(&ot, path))
        die("cannot write the results");
    fprintf(oc.f, "mesh,triangles,levels,coarsest,cpu_ms,wall_ms,first_ms,us_per_triangle,"
                  "errors\n");

    /* the making itself: no levels kept from an earlier run */
    setenv("LIMEN_CACHE", "off", 1);
    static const struct { const char *name; int u, v, runs; } SPHERES[] = {
        { "sphere_50k", 200, 125, 3 },
        { "sphere_200k", 400, 250, 3 },
        { "sphere_800k", 800, 500, 1 },
        { "sphere_1600k", 1000, 800, 1 },
    };
    enum { NSPHERES = sizeof SPHERES / sizeof SPHERES[0] };
    double per[NSPHERES];
    for (int m = 0; m < NSPHERES + 2; m++) {
        bool ball = m < NSPHERES, file = m == NSPHERES;
        arrays a = ball ? sphere(SPHERES[m].u, SPHERES[m].v) : file ? from_file(mesh) : asset(40, 4);
        int runs = ball ? (full && SPHERES[m].runs == 1 ? 3 : SPHERES[m].runs) : 9, levels = 0,
            coarsest = 0;
        float errors[12] = { 0 };
        double wall, first, ms = make_ms(&a, runs, &wall, &first, &levels, &coarsest, errors);
        const char *name = ball ? SPHERES[m].name : file ? "bunny" : "asset_500_charts";
        if (ball)
            per[m] = ms / a.nt;
        fprintf(oc.f, "%s,%d,%d,%d,%.1f,%.1f,%.1f,%.3f,", name, a.nt, levels, coarsest, ms, wall,
                first, 1e3 * ms / a.nt);
        for (int k = 0; k < levels && k < 12; k++)
            fprintf(oc.f, "%s%.5g", k ? " " : "", errors[k]);
        fprintf(oc.f, "\n");
        fprintf(stderr, "lod_build: %s, %d triangles: %d levels (the coarsest %d triangles) in "
                "%.1f ms of processor time, %.1f ms wall (the mesh there after %.1f ms)\n", name,
                a.nt, levels, coarsest, ms, wall, first);
        fprintf(ot.f, "mesh making (hierarchy, levels, their errors): %-16s %7d triangles "
                      "%8.1f ms processor %8.1f ms wall (the mesh there after %.1f ms wall), "
                      "%d levels to %d triangles, %.0fk triangles a second (processor)\n",
                name, a.nt, ms, wall, first, levels, coarsest, a.nt / ms);
        free(a.pos);
        free(a.nrm);
        free(a.uv);
        free(a.idx);
    }
    fprintf(ot.f, "mesh making: 800k against 50k per triangle: %.2fx (1 = linear)\n",
            per[2] / per[0]);

    /* the biggest sphere again, its levels kept: made (and stored), then read back */
    char dir[] = "/tmp/limen_lod_buildXXXXXX";
    if (!mkdtemp(dir))
        die("cannot make a cache folder");
    setenv("LIMEN_CACHE_DIR", dir, 1);
    unsetenv("LIMEN_CACHE");
    arrays a = sphere(SPHERES[NSPHERES - 1].u, SPHERES[NSPHERES - 1].v);
    int levels = 0, coarsest = 0;
    float errors[12];
    double cold_wall, cold_first, cold = make_ms(&a, 1, &cold_wall, &cold_first, &levels,
                                                 &coarsest, errors);
    double warm_wall, warm_first, warm = make_ms(&a, 1, &warm_wall, &warm_first, &levels,
                                                 &coarsest, errors);
    fprintf(oc.f, "%s_cached,%d,%d,%d,%.1f,%.1f,%.1f,%.3f,\n", SPHERES[NSPHERES - 1].name,
            a.nt, levels, coarsest, warm, warm_wall, warm_first, 1e3 * warm / a.nt);
    fprintf(ot.f, "mesh making with the cache: %s made and stored %.1f ms processor %.1f ms "
                  "wall; read back %.1f ms processor %.1f ms wall: %.3fx\n",
            SPHERES[NSPHERES - 1].name, cold, cold_wall, warm, warm_wall, warm / cold);
    fprintf(stderr, "lod_build: %s with the cache: made and stored %.1f ms, read back %.1f ms "
            "(processor)\n", SPHERES[NSPHERES - 1].name, cold, warm);
    free(a.pos);
    free(a.idx);
    char entry[4200];
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (e->d_name[0] != '.') {
            snprintf(entry, sizeof entry, "%s/%s", dir, e->d_name);
            unlink(entry);
        }
    if (d)
        closedir(d);
    rmdir(dir);
    if (limen__out_close(&oc) || limen__out_close(&ot))
        die("cannot write the results");
    return 0;
}
