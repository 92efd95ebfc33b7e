/* lod_build.c - what making a mesh costs: limen_mesh_set_triangles (the levels of detail
 * and each level's measured error, src/core/lod.c; the ray tracer's hierarchy is made on
 * a ray's first need, not here) on bumpy
 * spheres of 50,000, 200,000, 800,000 and 1,600,000 triangles made here, on the bunny, and
 * on a textured asset of 16,000 triangles in 500 texture charts (tests/charted.h). Processor
 * time (medians) beside wall time, with the cache of levels off (core/lod_cache.c), and the
 * triangles made a second (of processor time); the growth from 50k to 800k per triangle,
 * measured in one run (1 means linear). Then the biggest sphere with the cache on, in a
 * folder of its own: made and stored, then made again from the cache, and the second against
 * the first. Then the biggest sphere as a file (a binary PLY written here) loaded into a
 * scene and drawn (640x480, the default renderer): the first frame's time from the start of
 * loading (its levels still being made, the cache empty; then the cache warm), processor
 * time beside wall time, then frames while its levels are made, until every level's bound is
 * there, then frames with them; the peak memory of the whole process, renderer included, in
 * each of the three phases and in all. The spheres are tests/bumpy.h's.
 *
 * Each measurement runs in a process of its own, so that its peak resident memory (what the
 * kernel reports at its end) is its own.
 *
 *   lod_build [--out DIR] [--mesh FILE] [--full] [--frame]
 *
 * Writes DIR/lod_build.csv and DIR/lod_build.txt; a line per mesh on stderr. --full times
 * the biggest spheres three times instead of once; --frame measures the PLY's frames alone. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
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

/* What one measurement found, sent back from its process. */
typedef struct row {
    int nt, levels, coarsest;
    double ms, wall, first;
    float errors[12];
    double first_cpu, ready_wall, ready_cpu;   /* the frame's measurement */
    double first_peak_mb;       /* the process's peak resident memory at its first frame */
    double build_peak_mb;       /* its peak while the levels were made beside the frames */
    double drawn_peak_mb;       /* its peak while the levels were drawn */
    int frames_beside;          /* frames drawn while the levels were made */
    int failed;
    char why[200];
} row;

typedef void (*measured)(const void *arg, row *out);

/* Runs f(arg) in a process of its own: what it found, its peak resident memory (*peak_mb). */
static row in_child(measured f, const void *arg, double *peak_mb)
{
    int fd[2];
    if (pipe(fd))
        die("no pipe");
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0)
        die("cannot fork");
    if (pid == 0) {
        close(fd[0]);
        row r = { 0 };
        f(arg, &r);
        ssize_t put = write(fd[1], &r, sizeof r);
        _exit(put == (ssize_t)sizeof r ? 0 : 1);
    }
    close(fd[1]);
    row r = { .failed = 1 };
    size_t got = 0;
    while (got < sizeof r) {
        ssize_t n = read(fd[0], (char *)&r + got, sizeof r - got);
        if (n <= 0)
            break;
        got += (size_t)n;
    }
    close(fd[0]);
    int status;
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) ||
        got != sizeof r)
        die("a measurement's process failed");
    if (r.failed)
        die(r.why);
    *peak_mb = ru.ru_maxrss / 1024.0;
    return r;
}

static const struct { const char *name; int u, v, runs; } SPHERES[] = {
    { "sphere_50k", 200, 125, 3 },
    { "sphere_200k", 400, 250, 3 },
    { "sphere_800k", 800, 500, 1 },
    { "sphere_1600k", 1000, 800, 1 },
};
enum { NSPHERES = sizeof SPHERES / sizeof SPHERES[0] };

typedef struct making {
    int m;                      /* a sphere, NSPHERES the file, NSPHERES + 1 the asset */
    int runs;
    const char *mesh;
} making;

static void make_one(const void *arg, row *r)
{
    const making *mk = arg;
    bool ball = mk->m < NSPHERES, file = mk->m == NSPHERES;
    arrays a = ball ? sphere(SPHERES[mk->m].u, SPHERES[mk->m].v) : file ? from_file(mk->mesh)
                                                                     : asset(40, 4);
    r->nt = a.nt;
    r->ms = make_ms(&a, mk->runs, &r->wall, &r->first, &r->levels, &r->coarsest, r->errors);
    free(a.pos);
    free(a.nrm);
    free(a.uv);
    free(a.idx);
}

/* The biggest sphere as a binary PLY at path. */
static void write_ply(const void *arg, row *r)
{
    const char *path = arg;
    arrays a = sphere(SPHERES[NSPHERES - 1].u, SPHERES[NSPHERES - 1].v);
    FILE *f = fopen(path, "wb");
    bool ok = f && fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "element face %d\nproperty list uchar int vertex_indices\n"
                              "end_header\n", a.nv, a.nt) > 0 &&
              fwrite(a.pos, sizeof(float) * 3, (size_t)a.nv, f) == (size_t)a.nv;
    for (int t = 0; ok && t < a.nt; t++) {
        unsigned char three = 3;
        ok = fwrite(&three, 1, 1, f) == 1 && fwrite(&a.idx[t * 3], sizeof(uint32_t), 3, f) == 3;
    }
    if (f && fclose(f))
        ok = false;
    if (!ok) {
        r->failed = 1;
        snprintf(r->why, sizeof r->why, "cannot write %s", path);
    }
    r->nt = a.nt;
    free(a.pos);
    free(a.idx);
}

/* The process's peak resident memory so far (Linux; 0 where it cannot say). */
static double peak_so_far_mb(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "VmHWM:", 6))
            kb = atof(line + 6);
    if (f)
        fclose(f);
    return kb / 1024;
}

/* Sets the process's peak resident memory back to what it holds now (Linux: clear_refs),
 * so that the next peak_so_far_mb is a phase's own; false where it cannot. */
static bool peak_reset(void)
{
    FILE *f = fopen("/proc/self/clear_refs", "w");
    bool ok = f && fputs("5", f) >= 0;
    if (f && fclose(f))
        ok = false;
    return ok;
}

/* The file at path loaded into a scene and drawn, in three phases, each with its own peak
 * resident memory: the first frame, from the start of loading; then frames drawn while its
 * levels are made (a frame, then up to a second's wait for them, again and again, as a
 * viewer that redraws now and then would), until they are there; then frames with them
 * (the renderer's copy of a level made, the full mesh's dropped). */
static void first_frame(const void *arg, row *r)
{
    const char *path = arg;
    limen_scene *s;
    limen_node cam, n;
    limen_renderer *rd = NULL;
    double c0 = cpu_ms(), w0 = now_ms();
    bool ok = !limen_scene_create(NULL, &s) &&
              !limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam) &&
              !limen_node_look_at(s, cam, (float[3]){ 0, 0.5f, 3 }, (float[3]){ 0, 0, 0 },
                                  (float[3]){ 0, 1, 0 }) &&
              !limen_scene_set_camera(s, cam) &&
              !limen_node_create(s, LIMEN_NODE_MESH, "m", &n) && !limen_mesh_load(s, n, path);
    if (ok && limen_renderer_create(&(limen_renderer_desc){ .width = 640, .height = 480 }, &rd))
        ok = false;
    limen_frame_stats st;
    if (ok && limen_render_frame(rd, s, NULL, &st))
        ok = false;
    r->first = now_ms() - w0;
    r->first_cpu = cpu_ms() - c0;
    r->first_peak_mb = peak_so_far_mb();
    bool phases = peak_reset();
    limen_mesh_info info = { 0 };
    while (ok && !limen_mesh_get(s, n, &info) && info.lod_count < 2 && now_ms() - w0 < 6e5) {
        ok = !limen_render_frame(rd, s, NULL, &st);
        r->frames_beside++;
        for (double t = now_ms(); ok && now_ms() - t < 1000;) {
            limen__meshes_settle(s, false);
            if (!limen_mesh_get(s, n, &info) && info.lod_count >= 2)
                break;
            usleep(20000);
        }
    }
    r->ready_wall = now_ms() - w0;
    r->ready_cpu = cpu_ms() - c0;
    r->build_peak_mb = phases ? peak_so_far_mb() : 0;
    phases = phases && peak_reset();
    /* and frames with the levels (the renderer's copy of the level drawn made) */
    for (int i = 0; ok && i < 3; i++)
        ok = !limen_render_frame(rd, s, NULL, &st);
    r->drawn_peak_mb = phases ? peak_so_far_mb() : 0;
    if (ok) {
        limen_drawables *d;
        const limen_mesh_geometry *g = geometry_of(s, n, &d);
        r->nt = g->triangle_count;
        r->levels = g->lod_count;
        r->coarsest = g->lods[g->lod_count - 1].triangle_count;
        limen_drawables_destroy(d);
    } else {
        r->failed = 1;
        snprintf(r->why, sizeof r->why, "%s", rd && *limen_renderer_error(rd)
                                                 ? limen_renderer_error(rd)
                                                 : limen_scene_error(s));
    }
    limen_renderer_destroy(rd);
    limen_scene_destroy(s);
}

static void empty_dir(const char *dir)
{
    char entry[4200];
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (e->d_name[0] != '.') {
            snprintf(entry, sizeof entry, "%s/%s", dir, e->d_name);
            unlink(entry);
        }
    if (d)
        closedir(d);
}

int main(int argc, char **argv)
{
    const char *out = "build/bench", *mesh = "scenes/data/bunny.obj";
    bool full = false, frame_only = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc)
            out = argv[++i];
        else if (!strcmp(argv[i], "--mesh") && i + 1 < argc)
            mesh = argv[++i];
        else if (!strcmp(argv[i], "--full"))
            full = true;
        else if (!strcmp(argv[i], "--frame"))
            frame_only = true;
        else
            die("usage: lod_build [--out DIR] [--mesh FILE] [--full] [--frame]");
    }
    char path[512];
    limen__out oc, ot;
    /* the folder made where it is not there (its parent must be) */
    struct stat st;
    if (stat(out, &st) && mkdir(out, 0755))
        die("cannot make the results' folder (--out DIR: its parent must be there)");
    snprintf(path, sizeof path, "%s/lod_build.csv", out);
    if (limen__out_open(&oc, path))
        die("cannot write the results");
    snprintf(path, sizeof path, "%s/lod_build.txt", out);
    if (limen__out_open(&ot, path))
        die("cannot write the results");
    fprintf(oc.f, "mesh,triangles,levels,coarsest,cpu_ms,wall_ms,first_ms,us_per_triangle,"
                  "triangles_per_s,peak_mb,errors\n");

    /* the making itself: no levels kept from an earlier run */
    setenv("LIMEN_CACHE", "off", 1);
    double per[NSPHERES];
    for (int m = 0; m < NSPHERES + 2 && !frame_only; m++) {
        bool ball = m < NSPHERES, file = m == NSPHERES;
        making mk = { .m = m, .mesh = mesh,
                      .runs = ball ? (full && SPHERES[m].runs == 1 ? 3 : SPHERES[m].runs) : 9 };
        double peak;
        row r = in_child(make_one, &mk, &peak);
        const char *name = ball ? SPHERES[m].name : file ? "bunny" : "asset_500_charts";
        if (ball)
            per[m] = r.ms / r.nt;
        fprintf(oc.f, "%s,%d,%d,%d,%.1f,%.1f,%.1f,%.3f,%.0f,%.0f,", name, r.nt, r.levels,
                r.coarsest, r.ms, r.wall, r.first, 1e3 * r.ms / r.nt, 1e3 * r.nt / r.ms, peak);
        for (int k = 0; k < r.levels && k < 12; k++)
            fprintf(oc.f, "%s%.5g", k ? " " : "", r.errors[k]);
        fprintf(oc.f, "\n");
        fprintf(stderr, "lod_build: %s, %d triangles: %d levels (the coarsest %d triangles) in "
                "%.1f ms of processor time, %.1f ms wall (the mesh there after %.1f ms), peak "
                "%.0f MB\n", name, r.nt, r.levels, r.coarsest, r.ms, r.wall, r.first, peak);
        fprintf(ot.f, "mesh making (levels, their errors): %-16s %7d triangles "
                      "%8.1f ms processor %8.1f ms wall (the mesh there after %.1f ms wall), "
                      "%d levels to %d triangles, %.0fk triangles a second (processor), peak "
                      "%.0f MB\n",
                name, r.nt, r.ms, r.wall, r.first, r.levels, r.coarsest, r.nt / r.ms, peak);
    }
    if (!frame_only)
        fprintf(ot.f, "mesh making: 800k against 50k per triangle: %.2fx (1 = linear)\n",
                per[2] / per[0]);

    /* the biggest sphere again, its levels kept: made (and stored), then read back */
    char dir[] = "/tmp/limen_lod_buildXXXXXX";
    if (!mkdtemp(dir))
        die("cannot make a cache folder");
    setenv("LIMEN_CACHE_DIR", dir, 1);
    unsetenv("LIMEN_CACHE");
    making big = { .m = NSPHERES - 1, .runs = 1 };
    for (int once = 0; once < 1 && !frame_only; once++) {
        double cold_peak, warm_peak;
        row cold = in_child(make_one, &big, &cold_peak), warm = in_child(make_one, &big, &warm_peak);
        fprintf(oc.f, "%s_cached,%d,%d,%d,%.1f,%.1f,%.1f,%.3f,%.0f,%.0f,\n",
                SPHERES[NSPHERES - 1].name, warm.nt, warm.levels, warm.coarsest, warm.ms,
                warm.wall, warm.first, 1e3 * warm.ms / warm.nt, 1e3 * warm.nt / warm.ms,
                warm_peak);
        fprintf(ot.f, "mesh making with the cache: %s made and stored %.1f ms processor %.1f "
                      "ms wall; read back %.1f ms processor %.1f ms wall: %.3fx\n",
                SPHERES[NSPHERES - 1].name, cold.ms, cold.wall, warm.ms, warm.wall,
                warm.ms / cold.ms);
        fprintf(stderr, "lod_build: %s with the cache: made and stored %.1f ms, read back "
                "%.1f ms (processor)\n", SPHERES[NSPHERES - 1].name, cold.ms, warm.ms);
    }
    empty_dir(dir);

    /* the biggest sphere as a file, loaded and drawn: the cache empty, then warm */
    char ply[600];
    snprintf(ply, sizeof ply, "%s/sphere_1600k.ply", dir);
    double unused;
    in_child(write_ply, ply, &unused);
    char cache[600];
    snprintf(cache, sizeof cache, "%s/cache", dir);
    if (mkdir(cache, 0700))
        die("cannot make a cache folder");
    setenv("LIMEN_CACHE_DIR", cache, 1);
    for (int warm_cache = 0; warm_cache < 2; warm_cache++) {
        double peak;
        row r = in_child(first_frame, ply, &peak);
        /* the kernel's peak is the last phase's (each phase sets it back): the greatest */
        peak = fmax(peak, fmax(r.first_peak_mb, fmax(r.build_peak_mb, r.drawn_peak_mb)));
        const char *how = warm_cache ? "the cache warm" : "the cache empty";
        fprintf(oc.f, "first_frame_%s,%d,%d,%d,%.1f,%.1f,%.1f,,,%.0f,\n",
                warm_cache ? "warm" : "cold", r.nt, r.levels, r.coarsest, r.ready_cpu,
                r.ready_wall, r.first, peak);
        fprintf(ot.f, "first frame of a %d-triangle PLY (640x480), %s: %.1f ms wall %.1f ms "
                      "processor from the start of loading, peak %.0f MB for the whole process "
                      "by then\n", r.nt, how, r.first, r.first_cpu, r.first_peak_mb);
        fprintf(ot.f, "  then its levels made beside %d frames (a frame, then up to a second's "
                      "wait): every level's bound there after %.1f ms wall %.1f ms processor "
                      "from the start of loading (%d levels to %d triangles), peak %.0f MB for "
                      "the whole process meanwhile\n", r.frames_beside, r.ready_wall,
                r.ready_cpu, r.levels, r.coarsest, r.build_peak_mb);
        fprintf(ot.f, "  then 3 frames with the levels: peak %.0f MB meanwhile; the whole "
                      "process's peak %.0f MB\n", r.drawn_peak_mb, peak);
        fprintf(stderr, "lod_build: first frame of the PLY, %s: %.1f ms wall (%.1f processor), "
                "peak %.0f MB by then; levels after %.1f ms wall (%.1f processor) beside %d "
                "frames, peak %.0f MB meanwhile; %.0f MB drawing them; %.0f MB in all\n", how,
                r.first, r.first_cpu, r.first_peak_mb, r.ready_wall, r.ready_cpu,
                r.frames_beside, r.build_peak_mb, r.drawn_peak_mb, peak);
    }
    empty_dir(cache);
    rmdir(cache);
    empty_dir(dir);
    rmdir(dir);
    if (limen__out_close(&oc) || limen__out_close(&ot))
        die("cannot write the results");
    return 0;
}
