/* lod_build.c - what making a mesh costs: limen_mesh_set_triangles (the ray tracer's
 * hierarchy, the levels of detail and each level's measured error, src/core/lod.c) on bumpy
 * spheres of 50,000, 200,000 and 800,000 triangles made here, and on the bunny. Processor
 * time, medians; the growth from 50k to 800k per triangle, measured in one run (1 means
 * linear). The spheres are tests/bumpy.h's.
 *
 *   lod_build [--out DIR] [--mesh FILE] [--full]
 *
 * Writes DIR/lod_build.csv and DIR/lod_build.txt; a line per mesh on stderr. --full times
 * the biggest sphere three times instead of once. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "../tests/bumpy.h"
#include "timing.h"

static void die(const char *what)
{
    fprintf(stderr, "lod_build: %s\n", what);
    exit(1);
}

typedef struct arrays {
    float *pos;
    uint32_t *idx;
    int nv, nt;
} arrays;

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

/* The median processor time of `runs` makings of a mesh from a (ms); *levels, *coarsest
 * and errors (12): what the last one made. */
static double make_ms(const arrays *a, int runs, int *levels, int *coarsest, float *errors)
{
    double t[16];
    for (int r = 0; r < runs; r++) {
        limen_scene *s;
        limen_node n;
        if (limen_scene_create(NULL, &s) || limen_node_create(s, LIMEN_NODE_MESH, "m", &n))
            die("cannot make a scene");
        double t0 = cpu_ms();
        limen_status st = limen_mesh_set_triangles(s, n, &(limen_mesh_data){
            .positions = a->pos, .vertex_count = a->nv, .indices = a->idx,
            .triangle_count = a->nt });
        t[r] = cpu_ms() - t0;
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
    fprintf(oc.f, "mesh,triangles,levels,coarsest,cpu_ms,us_per_triangle,errors\n");

    static const struct { const char *name; int u, v, runs; } SPHERES[] = {
        { "sphere_50k", 200, 125, 3 },
        { "sphere_200k", 400, 250, 3 },
        { "sphere_800k", 800, 500, 1 },
    };
    double per[3];
    for (int m = 0; m < 4; m++) {
        arrays a = m < 3 ? sphere(SPHERES[m].u, SPHERES[m].v) : from_file(mesh);
        int runs = m < 3 ? (full ? 3 : SPHERES[m].runs) : 9, levels = 0, coarsest = 0;
        float errors[12] = { 0 };
        double ms = make_ms(&a, runs, &levels, &coarsest, errors);
        const char *name = m < 3 ? SPHERES[m].name : "bunny";
        if (m < 3)
            per[m] = ms / a.nt;
        fprintf(oc.f, "%s,%d,%d,%d,%.1f,%.3f,", name, a.nt, levels, coarsest, ms, 1e3 * ms / a.nt);
        for (int k = 0; k < levels && k < 12; k++)
            fprintf(oc.f, "%s%.5g", k ? " " : "", errors[k]);
        fprintf(oc.f, "\n");
        fprintf(stderr, "lod_build: %s, %d triangles: %d levels in %.1f ms of processor time\n",
                name, a.nt, levels, ms);
        fprintf(ot.f, "mesh making (hierarchy, levels, their errors): %-11s %7d triangles "
                      "%8.1f ms\n", name, a.nt, ms);
        free(a.pos);
        free(a.idx);
    }
    fprintf(ot.f, "mesh making: 800k against 50k per triangle: %.2fx (1 = linear)\n",
            per[2] / per[0]);
    if (limen__out_close(&oc) || limen__out_close(&ot))
        die("cannot write the results");
    return 0;
}
