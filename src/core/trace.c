/* trace.c - the reference ray tracer: the ground truth that the rasterizer is measured
 * against (docs/DESIGN.md, "Ground truth"). Every rule below copies what the planner
 * (core/plan.c) and the renderer (core/drawlist.c, gl/backend.c) do, so that a difference
 * between the two pictures is an error of the rasterizing method, not of the rules.
 *
 * Camera. limen_camera_matrices(s, W/H, NO): pixel column x, GL row y (0 = bottom; PNG row
 * r is GL row H-1-r) is sampled at its centre, NDC ((x+0.5)*2/W-1, (y+0.5)*2/H-1), or at
 * limen_trace_desc.samples points (x+sx, y+sy) averaged with equal weights. The ray
 * runs from the eye along camera_world * (nx tan(fovy/2) aspect, ny tan(fovy/2), -1), in
 * double (not through a float projection, whose far point is lost when far/near is large,
 * nor through the far plane at all, which the tracer does not model). Shapes count only from the near
 * plane on, as the rasterizer's near clip drops what is nearer; mirrors and portals count
 * from the eye on, as the renderer draws them depth-clamped (a camera closer to a portal
 * than its near distance still sees through it).
 *
 * Shapes passing through portals (limen__find_straddlers): a closed shape whose bounding
 * sphere crosses a portal's plane over its rectangle exists only in front of that plane,
 * and a copy carried by the portal matrix exists only in front of the partner's plane, as
 * the renderer draws them with a second clip distance.
 *
 * Shapes, exact, in each node's unit space M = world * diag(scale): box [-0.5, 0.5]^3
 * (scale = dims), sphere of radius 1 (r, r, r), cylinder of radius 1 with y in [0, 1] and
 * caps (r, h, r), quad, mirror and portal on [-0.5, 0.5]^2 at z = 0 (w, h, 1), a mesh's
 * triangles in its own frame (scale 1; Moller-Trumbore in double over the asset's BVH). Only live,
 * visible nodes; groups, lights and cameras are never hit. Closed shapes (box, sphere,
 * cylinder) are hit only where the ray enters them: the renderer culls their back faces, so
 * a ray that starts inside one (or whose entry was near-clipped) passes out unseen. Flat
 * shapes and meshes are hit from both sides (the renderer draws meshes without culling, as
 * their files need not be closed); a mesh cut at a portal shows what lies behind the cut.
 *
 * Shading, as the fragment shader: colour = albedo * (ambient + (1 - ambient) *
 * sum_i light_i * w_i * max(0, n . normalize(light_pos_i - p))), clamped to [0, 1], no
 * shadows; w_i = clamp(1 - (d/R)^4, 0, 1)^2 for a light of range R > 0 at distance d, else 1.
 * Lights: the first 8 live, visible LIGHT nodes in creation order (world translation, colour).
 * n = normalize(N * n_unit), N the inverse transpose of M's 3x3, n_unit the unit-space
 * point (sphere), (x, 0, z) of it (cylinder side), or the face normal (caps, box faces,
 * quads; a mesh's face normal, or its vertex normals interpolated where it is smooth),
 * turned to face the incoming ray (the shader turns it towards the view's eye, which
 * lies on the ray's line behind its origin). Checker: c = floor(unit point * scale / cell),
 * k = c.x + c.y (+ c.z except for QUAD nodes), odd k -> checker_b, even -> colour.
 *
 * Textures (limen_node_set_texture_filter): a pixel's ray carries its differentials, how its
 * origin and unit direction change to the next pixel's ray across and up (d(dir) from the
 * lens, 2 tan(fovy/2) aspect / W and 2 tan(fovy/2) / H along the camera's axes). At a hit
 * they give the point's steps on the tangent plane (the hit's normal), and through the
 * unit-space point the steps of the texture coordinates (a face's axes, or a triangle's
 * texture-coordinate gradient), from which the level is picked by OpenGL's rule. A mirror
 * or portal maps the point's steps and the direction's by its matrix (the direction then
 * renormalised), so a floor seen in a mirror or through a scaled portal takes the level
 * the renderer's pixels do. OpenGL takes its steps between the pixels of a 2x2 quad, the
 * tracer at the pixel itself: the levels differ by a fraction where the steps change
 * quickly, well inside the bound.
 *
 * Surfaces. A mirror or a paired portal S is entered from its front (the ray moving against
 * its +Z normal; equivalent to the planner's "eye in front" test). Passing it: a mirror
 * reflects (origin = hit point, direction reflected, colour multiplied by its tint); a
 * portal maps origin and direction by X = limen__surface_matrix_d (scaled portals scale the
 * path; the direction is renormalised and distances are measured in world units). The next
 * segment starts on the exit plane (the mirror itself, or the partner B), moves to its
 * front, and never hits the exit surface, which the renderer never draws in that view. A
 * mirror seen from behind is a matte quad of its back colour (checker as any quad, not a
 * QUAD). A portal seen from behind is not there. An unpaired portal, or one whose partner
 * is hidden, shows its fill colour from the front (flat, unlit).
 *
 * Limits. A ray that has passed b surfaces and enters S goes on only if b+1 is within S's
 * depth under the limits (limen__limits_depth: its own max_depth, capped or overridden as
 * the planner does, `--depth N` / `--depth-override N`); otherwise it ends
 * on S's fill colour, which the tints of the mirrors already passed still multiply (as in
 * the renderer). Where nothing is hit: the background, times those tints.
 *
 * Not modelled, on purpose: the far plane (scenes fit well inside it; the oblique far plane
 * of a nested view is an artefact of the method, not of the scene), the view budget
 * max_views (a truncated tree is an error the comparison should see), a multisampled
 * frame's resolve beyond averaging its samples (limen_trace_desc.samples), 8-bit rounding of intermediate colours in a framebuffer (the tracer
 * multiplies the clamped shade by the product of the tints in double and rounds once), and
 * the tessellation of curved shapes (the tracer is what the meshes approximate).
 *
 * Levels of detail (limen_trace_desc.lod_pixels, lod_level): the full mesh unless asked;
 * asked, each mesh prim is traced at one level, the one the camera's view draws its node at
 * (limen_view_mesh_lod) or the one forced, through a copy of its asset that holds the
 * level's triangles, parts and a hierarchy over them (tracer_levels). A mesh seen in a
 * mirror or through a portal keeps that level, where the renderer chooses per view.
 *
 * Images are traced by pthreads over interleaved rows; every thread only reads a snapshot
 * of the scene (`tracer`) taken before they start. Each segment tests only the prims whose
 * boxes in the scene's spatial index it meets, found through Embree (core/rtc.c) or
 * limen's own BVH (core/bvh.c); the tests above decide, so the picture is the same. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/bvh.h"
#include "core/dmath.h"
#include "core/index.h"
#include "core/internal.h"
#include "core/kinds.h"
#include "core/mesh.h"
#include "core/texture.h"

#define MAX_THREADS 256

enum shape { SHAPE_BOX, SHAPE_SPHERE, SHAPE_CYLINDER, SHAPE_FLAT, SHAPE_MESH };

/* One hittable node, in double precision. */
typedef struct prim {
    int node;                   /* index in the scene's pool */
    limen_node_kind kind;
    enum shape shape;
    bool flat;                  /* a flat shape (not a surface): its checker in unit xy */
    limen_uv_rule uv;           /* limen_kind_info.uv */
    double m[16], minv[16];     /* unit space -> world and back */
    double nmat[9];             /* inverse transpose of m's 3x3, column-major */
    double scale[3];
    double bc[3], br;           /* world bounding sphere */
    const limen__mesh *mesh;    /* meshes: the triangles, in unit space (scale 1) */
    bool smooth;                /* meshes: interpolated vertex normals */
    const limen__texture *tex;  /* albedo = texel * colour, or NULL */
    double repeat[2];           /* texture coordinates scaled by these */
    limen_texture_filter filter;
    double color[3], checker_b[3], cell;
    /* mirrors and portals */
    double plane[4];            /* world, front = +Z side */
    double x[16];               /* surface matrix */
    bool has_x;                 /* a mirror, or a portal with a visible partner */
    int exit;                   /* prim index of the exit surface (self or partner); -1 none */
    double tint[3], back[3], fill[3];
    int max_depth;
    /* a closed shape passing through a portal: itself, or its copy out of the partner */
    bool has_cut;
    double cut[4];              /* world plane; only what lies in front of it exists */
    double unit_c[3], unit_r;   /* bounding sphere in unit space */
} prim;

/* A read-only snapshot of the scene for tracing. */
typedef struct tracer {
    const limen_scene *s;
    prim *prims;
    int n;
    double lpos[LIMEN__MAX_LIGHTS][3], lcol[LIMEN__MAX_LIGHTS][3], lrange[LIMEN__MAX_LIGHTS];
    int nlights;
    double ambient, background[3];
    /* images: the scene's spatial index finds the prims near a ray (core/index.c) */
    bool indexed;
    const limen__bvh *shapes, *surfaces;
    const limen__rtc *rtc;      /* the same through Embree; NULL: walk them here */
    int *prim_of;               /* per node slot: its prim, or -1 */
    double (*spheres)[4];       /* per prim: bc, br, packed for the ray's first test */
    int nbase;                  /* prims [nbase, n) are copies of straddlers, not indexed */
    struct level *levels;       /* meshes at a level of detail (limen_trace_desc.lod_*) */
    int nlevels;
} tracer;

/* An asset at level k: a copy with the level's triangles, owned by the tracer. */
typedef struct level {
    const limen__mesh *src;
    int k;
    bool baked;                 /* the level's baked mesh (not for a node with a texture) */
    limen__mesh *mesh;
} level;

/* Texture coordinates at a hit: u, v, then (meshes) how each changes with the unit-space
 * point, du/dpu and dv/dpu, for the pixel's footprint (flat shapes' follow from the face). */
enum { UV_N = 11 };
/* ... of which a mesh hit's barycentric coordinates and triangle (its material) */
enum { UV_BU = 8, UV_BV = 9, UV_TRI = 10 };

/* Where one path ended (for limen_ray_cast). */
typedef struct record {
    bool hit;
    int prim;
    double point[3], normal[3], distance;
    int count;
    int chain[LIMEN_HIT_MAX_SURFACES];   /* prim indices */
    double seg_o[3], seg_d[3];
} record;

/* ------------------------------------------------------------------ small vectors */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static bool normalize3(double v[3])
{
    double len = sqrt(dot3(v, v));
    if (!(len > 0) || !isfinite(len))
        return false;
    v[0] /= len;
    v[1] /= len;
    v[2] /= len;
    return true;
}

/* Direction (w = 0) through a 4x4 matrix. */
static void d_dir(const double m[16], const double v[3], double out[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = m[i] * v[0] + m[4 + i] * v[1] + m[8 + i] * v[2];
    memcpy(out, r, sizeof r);
}

/* ------------------------------------------------------------------ snapshot */

/* Shapes and surfaces (a mesh once it has triangles). */
static bool hittable(const limen__node *n)
{
    const limen_kind_info *ki = limen_kind_get(n->kind);
    return (ki->shape || ki->surface) && (ki->unit || n->mesh);
}

static void copy3f(const float f[3], double d[3])
{
    d[0] = f[0];
    d[1] = f[1];
    d[2] = f[2];
}

/* The inverse, normal matrix and bounding sphere of a prim from its unit-space matrix m;
 * false (and never hit) when m is degenerate (a zero dimension draws no pixel either). */
static bool derive(prim *p)
{
    if (!limen__d_inv(p->m, p->minv)) {
        p->br = -1;
        return false;
    }
    /* N = (M3^-1)^T: element (r, c) of N is element (c, r) of M^-1 */
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            p->nmat[c * 3 + r] = p->minv[r * 4 + c];
    limen__d_point(p->m, p->unit_c, p->bc);
    double frob = 0;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            frob += p->m[c * 4 + r] * p->m[c * 4 + r];
    p->br = sqrt(frob) * p->unit_r * (1.0 + 1e-9);
    return true;
}

static void setup_prim(limen_scene *s, const limen__node *n, prim *p)
{
    memset(p, 0, sizeof *p);
    p->node = limen__index(s, n);
    p->kind = n->kind;
    p->exit = -1;
    /* the kind's unit shape's intersection; the rest of its facts from its row (core/kinds.c) */
    const limen_kind_info *ki = limen_kind_get(n->kind);
    switch (ki->unit) {
    case LIMEN_UNIT_BOX: p->shape = SHAPE_BOX; break;
    case LIMEN_UNIT_BALL: p->shape = SHAPE_SPHERE; break;
    case LIMEN_UNIT_CYLINDER: p->shape = SHAPE_CYLINDER; break;
    case LIMEN_UNIT_SQUARE: p->shape = SHAPE_FLAT; break;
    case LIMEN_UNIT_NONE:       /* hittable without one: a mesh's triangles */
    case LIMEN_UNIT_COUNT:
        p->shape = SHAPE_MESH;
        p->mesh = n->mesh;
        p->smooth = n->smooth || n->mesh->file_normals;
        break;
    }
    p->flat = ki->flat && ki->shape;   /* a mirror's back is checked in xyz, as drawn */
    p->uv = ki->uv;
    /* unit space: the unit shape's (the mesh's own frame), scaled to the node's dims */
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        p->scale[a] = ki->unit && ki->scale[a] >= 0 ? n->dims[ki->scale[a]] : 1.0;
        lo[a] = ki->unit ? ki->lo[a] : n->mesh->lo[a];
        hi[a] = ki->unit ? ki->hi[a] : n->mesh->hi[a];
    }
    limen__kind_sphere(n->kind, lo, hi, p->unit_c, &p->unit_r);
    double w[16];
    limen__d_from_f(&n->world[0][0], w);
    memcpy(p->m, w, sizeof w);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 4; r++)
            p->m[c * 4 + r] *= p->scale[c];
    if (!derive(p))
        return;
    copy3f(n->color, p->color);
    copy3f(n->checker_b, p->checker_b);
    if (ki->uv != LIMEN_UV_NONE)
        p->tex = n->texture;    /* a mesh's own are its materials' (limen__mesh_material_at) */
    p->repeat[0] = n->tex_repeat[0];
    p->repeat[1] = n->tex_repeat[1];
    p->filter = n->tex_filter;
    p->cell = n->checker_cell;
    if (limen__is_surface(n)) {
        limen__surface_plane_d(n, p->plane);
        copy3f(n->tint, p->tint);
        copy3f(n->back, p->back);
        copy3f(n->fill, p->fill);
        p->max_depth = n->max_depth;
        p->has_x = limen__surface_matrix_d(s, n, p->x);
        if (n->kind == LIMEN_NODE_PORTAL && n->pair) {
            const limen__node *b = &s->nodes[n->pair - 1];
            if (!limen__alive(b) || !b->visible)
                p->has_x = false;   /* the planner shows the fill then */
        }
    }
}

static void level_mesh_free(limen__mesh *m)
{
    if (!m)
        return;
    free(m->idx);
    free(m->parts);
    free(m->tri_part);
    free(m->bvh);
    free(m->tri_order);
    free(m);
}

static void tracer_free(tracer *t)
{
    for (int i = 0; i < t->nlevels; i++)
        level_mesh_free(t->levels[i].mesh);
    free(t->levels);
    t->levels = NULL;
    t->nlevels = 0;
    free(t->prims);
    free(t->prim_of);
    free(t->spheres);
    t->prims = NULL;
    t->prim_of = NULL;
    t->spheres = NULL;
}

/* Rays look up prims through the scene's index: its boxes (wider than each node's exact
 * extent) only choose which exact tests run, in double precision as before. The copies
 * of shapes passing through portals are not in it and are tested on every segment. */
static void tracer_index(tracer *t, limen_scene *s)
{
    limen__spatial *x = limen__scene_index(s);
    if (!x || !t->prim_of)
        return;     /* the tracer tests every prim, as for single rays (limen_ray_cast) */
    t->shapes = limen__index_shapes(x);
    t->surfaces = limen__index_surfaces(x);
    t->rtc = limen__index_rtc(x);
    t->indexed = true;
}

static limen_status tracer_init(tracer *t, limen_scene *s, const char *fn)
{
    memset(t, 0, sizeof *t);
    t->s = s;
    limen__scene_refresh(s);
    int count = 0;
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        if (i >= 0 && s->nodes[i].visible && hittable(&s->nodes[i]))
            count++;
    }
    size_t cap = s->cap > 0 ? (size_t)s->cap : 1;
    int *slot = malloc(sizeof *slot * cap), *through = malloc(sizeof *through * cap);
    int clones = through ? limen__find_straddlers(s, through) : 0;
    t->prims = malloc(sizeof *t->prims * (size_t)(count + clones > 0 ? count + clones : 1));
    if (!t->prims || !slot || !through) {
        free(slot);
        free(through);
        tracer_free(t);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", fn);
    }
    for (int i = 0; i < s->cap; i++)
        slot[i] = -1;
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        if (i < 0)
            continue;
        const limen__node *n = &s->nodes[i];
        if (n->kind == LIMEN_NODE_LIGHT && n->visible && t->nlights < LIMEN__MAX_LIGHTS) {
            copy3f(n->world[3], t->lpos[t->nlights]);
            copy3f(n->color, t->lcol[t->nlights]);
            t->lrange[t->nlights] = n->range;
            t->nlights++;
        }
        if (n->visible && hittable(n)) {
            slot[i] = t->n;
            setup_prim(s, n, &t->prims[t->n++]);
        }
    }
    t->nbase = t->n;
    /* the meshes' hierarchies, where not made yet (limen__mesh_hierarchy), before any ray */
    for (int i = 0; i < t->n; i++)
        if (t->prims[i].mesh && !limen__mesh_hierarchy(t->prims[i].mesh)) {
            free(slot);
            free(through);
            tracer_free(t);
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", fn);
        }
    for (int i = 0; i < t->n; i++) {
        prim *p = &t->prims[i];
        const limen__node *n = &s->nodes[p->node];
        if (n->kind == LIMEN_NODE_MIRROR)
            p->exit = i;
        else if (n->kind == LIMEN_NODE_PORTAL && p->has_x)
            p->exit = slot[n->pair - 1];
    }
    /* shapes passing through portals: cut at the entry, and a copy out of the partner */
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        int a = i >= 0 ? through[i] : -1;
        double x[16];
        if (a < 0 || slot[i] < 0 || !limen__surface_matrix_d(s, &s->nodes[a], x))
            continue;
        prim *orig = &t->prims[slot[i]], *copy = &t->prims[t->n];
        orig->has_cut = true;
        limen__surface_plane_d(&s->nodes[a], orig->cut);
        *copy = *orig;
        limen__d_mul(x, orig->m, copy->m);
        limen__surface_plane_d(&s->nodes[s->nodes[a].pair - 1], copy->cut);
        if (derive(copy))
            t->n++;
    }
    t->prim_of = slot;
    free(through);
    t->spheres = malloc(sizeof *t->spheres * (size_t)(t->n > 0 ? t->n : 1));
    if (!t->spheres) {
        tracer_free(t);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", fn);
    }
    for (int i = 0; i < t->n; i++) {
        memcpy(t->spheres[i], t->prims[i].bc, sizeof t->prims[i].bc);
        t->spheres[i][3] = t->prims[i].br;
    }
    t->ambient = s->ambient;
    copy3f(s->background, t->background);
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ levels of detail */

/* Asset src with level k's triangles in place of the full mesh's: the same vertices,
 * normals, texture coordinates, colours and materials (a baked level's own), the level's
 * triangles and parts, and
 * a hierarchy over them, so that every test and every lookup below works on it unchanged.
 * NULL when out of memory. */
static limen__mesh *level_mesh_make(const limen__mesh *src, int k, bool baked)
{
    const limen_mesh_lod *l = &src->lods[k];
    limen__mesh *m = malloc(sizeof *m);
    if (!m)
        return NULL;
    /* a baked level: its own vertices, texture and material, as the renderer draws it */
    if (baked) {
        src = src->lod_baked[k];
        l = &src->lods[0];
    }
    *m = *src;
    m->ntris = (uint32_t)l->triangle_count;
    m->idx = malloc(sizeof *m->idx * 3 * (size_t)m->ntris);
    m->parts = malloc(sizeof *m->parts * (size_t)(src->nparts ? src->nparts : 1));
    m->tri_part = src->nparts > 1 ? malloc(sizeof *m->tri_part * (size_t)m->ntris) : NULL;
    m->bvh = NULL;
    m->tri_order = NULL;
    m->lod_job = NULL;
    if (!m->idx || !m->parts || (src->nparts > 1 && !m->tri_part) || !m->ntris) {
        level_mesh_free(m);
        return NULL;
    }
    memcpy(m->idx, l->indices, sizeof *m->idx * 3 * (size_t)m->ntris);
    memcpy(m->parts, l->parts, sizeof *m->parts * src->nparts);
    if (m->tri_part)
        memset(m->tri_part, 0, sizeof *m->tri_part * (size_t)m->ntris);
    for (uint32_t p = 0; m->tri_part && p < src->nparts; p++)
        for (int t = 0; t < m->parts[p].triangle_count; t++)
            if ((uint32_t)(m->parts[p].first_triangle + t) < m->ntris)
                m->tri_part[m->parts[p].first_triangle + t] = p;
    if (!limen__mesh_bvh(m)) {
        level_mesh_free(m);
        return NULL;
    }
    return m;
}

/* The level of detail each mesh prim is traced at (limen_trace_desc.lod_pixels and
 * lod_level): the level the camera's view draws its node at, chosen as the renderer
 * chooses (limen_view_mesh_lod), or the one asked for. Prims of one asset at one level
 * share one copy. */
static limen_status tracer_levels(tracer *t, limen_scene *s, const limen_trace_desc *d,
                                  int width, int height)
{
    bool by_view = d->lod_level == 0 && d->lod_pixels > 0;
    if (d->lod_level == 0 && !by_view)
        return LIMEN_OK;
    limen_view root;
    memset(&root, 0, sizeof root);
    limen_status st = limen_camera_matrices(s, (float)width / (float)height, LIMEN_DEPTH_NO,
                                            root.view, root.proj);
    if (st)
        return st;
    t->levels = malloc(sizeof *t->levels * (size_t)(t->n > 0 ? t->n : 1));
    if (!t->levels)
        return limen__fail(s, LIMEN_ERR_NOMEM, "trace: out of memory");
    for (int i = 0; i < t->n; i++) {
        prim *p = &t->prims[i];
        if (p->shape != SHAPE_MESH || p->mesh->nlods < 2)
            continue;
        int k = d->lod_level;
        if (by_view) {
            limen_drawable it;
            limen__drawable_read(s, p->node, &it);
            k = limen_view_mesh_lod(&root, height, &it, d->lod_pixels);
        }
        if (k > (int)p->mesh->nlods - 1)
            k = (int)p->mesh->nlods - 1;
        if (k <= 0)
            continue;
        /* a baked level's texture coordinates are its own: a node's texture is drawn over
         * the level's triangles on the mesh's vertices instead (as the renderer does) */
        bool baked = !p->tex && p->mesh->lod_baked && p->mesh->lod_baked[k];
        const limen__mesh *lm = NULL;
        for (int j = 0; j < t->nlevels && !lm; j++)
            if (t->levels[j].src == p->mesh && t->levels[j].k == k && t->levels[j].baked == baked)
                lm = t->levels[j].mesh;
        if (!lm) {
            limen__mesh *made = level_mesh_make(p->mesh, k, baked);
            if (!made)
                return limen__fail(s, LIMEN_ERR_NOMEM, "trace: out of memory for level %d of "
                                   "mesh '%s'", k, p->mesh->name);
            t->levels[t->nlevels++] = (level){ p->mesh, k, baked, made };
            lm = made;
        }
        p->mesh = lm;
    }
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ intersection */

/* Entering hit of the unit box [-0.5, 0.5]^3; the entry face's unit normal. */
static bool hit_box(const double o[3], const double d[3], double tmin, double tmax, double *t,
                    double nu[3])
{
    double t0 = -INFINITY, t1 = INFINITY;
    int axis = -1;
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0) {
            if (o[a] < -0.5 || o[a] > 0.5)
                return false;
            continue;
        }
        double ta = (-0.5 - o[a]) / d[a], tb = (0.5 - o[a]) / d[a];
        if (ta > tb) {
            double tmp = ta;
            ta = tb;
            tb = tmp;
        }
        if (ta > t0) {
            t0 = ta;
            axis = a;
        }
        if (tb < t1)
            t1 = tb;
    }
    if (axis < 0 || t0 > t1 || !(t0 > tmin) || !(t0 < tmax))
        return false;
    *t = t0;
    nu[0] = nu[1] = nu[2] = 0;
    nu[axis] = d[axis] > 0 ? -1.0 : 1.0;
    return true;
}

static bool hit_sphere(const double o[3], const double d[3], double tmin, double tmax,
                       double *t, double nu[3])
{
    double a = dot3(d, d), b = dot3(o, d), c = dot3(o, o) - 1.0;
    double disc = b * b - a * c;
    if (!(disc >= 0) || !(a > 0))
        return false;
    /* the entering (smaller) root, computed without cancellation */
    double q = -(b + copysign(sqrt(disc), b));
    double t0 = q == 0 ? 0 : fmin(q / a, c / q);
    if (!(t0 > tmin) || !(t0 < tmax))
        return false;
    *t = t0;
    for (int i = 0; i < 3; i++)
        nu[i] = o[i] + t0 * d[i];
    return true;
}

static bool hit_cylinder(const double o[3], const double d[3], double tmin, double tmax,
                         double *t, double nu[3])
{
    double s0 = -INFINITY, s1 = INFINITY;  /* inside the infinite side */
    double a = d[0] * d[0] + d[2] * d[2];
    double b = o[0] * d[0] + o[2] * d[2];
    double c = o[0] * o[0] + o[2] * o[2] - 1.0;
    if (a > 0) {
        double disc = b * b - a * c;
        if (!(disc >= 0))
            return false;
        double sq = sqrt(disc);
        double q = b > 0 ? -b - sq : -b + sq;
        if (q == 0) {
            s0 = s1 = 0;
        } else {
            double r0 = q / a, r1 = c / q;
            s0 = fmin(r0, r1);
            s1 = fmax(r0, r1);
        }
    } else if (c > 0) {
        return false;
    }
    double y0 = -INFINITY, y1 = INFINITY;  /* between the caps */
    if (d[1] != 0) {
        double ta = -o[1] / d[1], tb = (1.0 - o[1]) / d[1];
        y0 = fmin(ta, tb);
        y1 = fmax(ta, tb);
    } else if (o[1] < 0 || o[1] > 1) {
        return false;
    }
    bool cap = y0 >= s0;
    double t0 = cap ? y0 : s0, t1 = fmin(s1, y1);
    if (!(t0 <= t1) || !(t0 > tmin) || !(t0 < tmax))
        return false;
    *t = t0;
    if (cap) {
        nu[0] = nu[2] = 0;
        nu[1] = d[1] > 0 ? -1.0 : 1.0;
    } else {
        nu[0] = o[0] + t0 * d[0];
        nu[1] = 0;
        nu[2] = o[2] + t0 * d[2];
    }
    return true;
}

static bool hit_flat(const double o[3], const double d[3], double tmin, double tmax, double *t,
                     double nu[3])
{
    if (d[2] == 0)
        return false;
    double th = -o[2] / d[2];
    if (!(th > tmin) || !(th < tmax))
        return false;
    double x = o[0] + th * d[0], y = o[1] + th * d[1];
    if (!(fabs(x) <= 0.5) || !(fabs(y) <= 0.5))
        return false;
    *t = th;
    nu[0] = nu[1] = 0;
    nu[2] = 1;
    return true;
}

/* How a triangle's texture coordinates change with a point moving in its plane (a move off
 * the plane counts as its projection): du/dpu into g[0..2], dv/dpu into g[3..5]. The
 * barycentric weights of a move dp are the least-squares (b1, b2) of b1 e1 + b2 e2 = dp. */
static void uv_gradient(const limen__mesh *m, const uint32_t *ix, double g[6])
{
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)m->pos[ix[1] * 3 + a] - m->pos[ix[0] * 3 + a];
        e2[a] = (double)m->pos[ix[2] * 3 + a] - m->pos[ix[0] * 3 + a];
    }
    double a11 = dot3(e1, e1), a12 = dot3(e1, e2), a22 = dot3(e2, e2);
    double det = a11 * a22 - a12 * a12;
    if (!(det > 0))
        return;
    for (int k = 0; k < 2; k++) {
        double d1 = (double)m->uv[ix[1] * 2 + k] - m->uv[ix[0] * 2 + k];
        double d2 = (double)m->uv[ix[2] * 2 + k] - m->uv[ix[0] * 2 + k];
        for (int a = 0; a < 3; a++)
            g[k * 3 + a] = (d1 * (a22 * e1[a] - a12 * e2[a]) + d2 * (a11 * e2[a] - a12 * e1[a])) /
                           det;
    }
}

/* The nearest triangle of a mesh prim (both sides; with a cut, hits behind it do not count,
 * as the renderer clips them without culling) and its unit-space normal: the face's, or the
 * vertex normals interpolated where the mesh is smooth. */
static bool hit_mesh(const prim *p, const double o[3], const double d[3], double tmin,
                     double tmax, double *t, double nu[3], double uv[UV_N])
{
    const limen__mesh *m = p->mesh;
    double cut[4], *cutp = NULL;
    if (p->has_cut) {   /* a world plane into unit space: M^T plane */
        for (int c = 0; c < 4; c++)
            cut[c] = p->m[c * 4] * p->cut[0] + p->m[c * 4 + 1] * p->cut[1] +
                     p->m[c * 4 + 2] * p->cut[2] + p->m[c * 4 + 3] * p->cut[3];
        cutp = cut;
    }
    double u, v;
    int tri = limen__mesh_intersect(m, o, d, tmin, tmax, cutp, t, &u, &v);
    if (tri < 0)
        return false;
    const uint32_t *ix = &m->idx[tri * 3];
    memset(uv, 0, sizeof(double) * UV_N);
    for (int k = 0; m->uv && k < 2; k++)
        uv[k] = (1.0 - u - v) * m->uv[ix[0] * 2 + k] + u * m->uv[ix[1] * 2 + k] +
                v * m->uv[ix[2] * 2 + k];
    if (m->uv)
        uv_gradient(m, ix, uv + 2);
    /* the material is found at shading from the triangle and the barycentric coordinates */
    uv[UV_BU] = u;
    uv[UV_BV] = v;
    uv[UV_TRI] = tri;
    if (p->smooth) {
        double w[3] = { 1.0 - u - v, u, v };
        for (int a = 0; a < 3; a++)
            nu[a] = w[0] * m->nrm[ix[0] * 3 + a] + w[1] * m->nrm[ix[1] * 3 + a] +
                    w[2] * m->nrm[ix[2] * 3 + a];
    } else {
        double e1[3], e2[3];
        for (int a = 0; a < 3; a++) {
            e1[a] = (double)m->pos[ix[1] * 3 + a] - m->pos[ix[0] * 3 + a];
            e2[a] = (double)m->pos[ix[2] * 3 + a] - m->pos[ix[0] * 3 + a];
        }
        nu[0] = e1[1] * e2[2] - e1[2] * e2[1];
        nu[1] = e1[2] * e2[0] - e1[0] * e2[2];
        nu[2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
    return true;
}

/* The search for the nearest hit of one segment. */
typedef struct search {
    const tracer *tr;
    const double *o, *d;
    double tmin_shape, tmin_surface;
    int skip;
    int best;
    double tbest, pu[3], nu[3], uv[UV_N];
} search;

/* Tests prim i against the search's segment, keeping the nearest hit; between hits at the
 * same distance, the lower prim index, so that the order prims are tested in (all of them
 * in order, or as the BVH finds them) never changes the answer. */
static void test_prim(search *q, int i)
{
    /* bounding sphere first, from the compact copy: distance of its centre from the line,
     * and t range */
    const double *sb = q->tr->spheres[i];
    const double *o = q->o, *d = q->d;
    if (i == q->skip || sb[3] < 0)
        return;
    double tbest = i < q->best ? nextafter(q->tbest, INFINITY) : q->tbest;
    double oc[3] = { sb[0] - o[0], sb[1] - o[1], sb[2] - o[2] };
    double tc = dot3(oc, d);
    double r2 = sb[3] * sb[3];
    double perp2 = dot3(oc, oc) - tc * tc;
    if (perp2 > r2 || tc - sb[3] >= tbest)
        return;
    const prim *p = &q->tr->prims[i];
    if (p->kind == LIMEN_NODE_PORTAL && dot3(p->plane, d) >= 0)
        return;     /* from behind (or edge on): empty air */
    double tmin = p->kind == LIMEN_NODE_MIRROR || p->kind == LIMEN_NODE_PORTAL ? q->tmin_surface
                                                                                : q->tmin_shape;
    if (tc + p->br <= tmin)
        return;
    double ou[3], du[3], t, n[3], uv[UV_N] = { 0 };
    limen__d_point(p->minv, o, ou);
    d_dir(p->minv, d, du);
    bool hit;
    switch (p->shape) {
    case SHAPE_BOX:
        hit = hit_box(ou, du, tmin, tbest, &t, n);
        break;
    case SHAPE_SPHERE:
        hit = hit_sphere(ou, du, tmin, tbest, &t, n);
        break;
    case SHAPE_CYLINDER:
        hit = hit_cylinder(ou, du, tmin, tbest, &t, n);
        break;
    case SHAPE_MESH:
        hit = hit_mesh(p, ou, du, tmin, tbest, &t, n, uv);
        break;
    default:
        hit = hit_flat(ou, du, tmin, tbest, &t, n);
        break;
    }
    if (!hit)
        return;
    if (p->has_cut) {
        /* entered on the cut-away side: the renderer draws nothing of it there (its back
         * faces are culled), so neither does the tracer */
        double w[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
        if (limen__d_plane_dist(p->cut, w) < 0)
            return;
    }
    q->best = i;
    q->tbest = t;
    memcpy(q->nu, n, sizeof n);
    memcpy(q->uv, uv, sizeof uv);
    for (int k = 0; k < 3; k++)
        q->pu[k] = ou[k] + t * du[k];
}

static void test_prim_bvh(void *ctx, int item, double *tmax)
{
    search *q = ctx;
    int i = q->tr->prim_of[item];
    if (i >= 0)
        test_prim(q, i);
    /* a box entered exactly at tbest may still hold a lower-indexed prim hit there */
    *tmax = q->tbest;
}

/* The nearest hit along o + t d (d a unit vector) with tmin < t, leaving out prim `skip`
 * and portals seen from behind. Returns the prim index or -1; *t, the unit-space point and
 * the unit-space normal of the hit. */
static int nearest(const tracer *tr, const double o[3], const double d[3], double tmin_shape,
                   double tmin_surface, int skip, double *t_out, double pu[3], double nu[3],
                   double uv_out[UV_N])
{
    search q = { .tr = tr, .o = o, .d = d, .tmin_shape = tmin_shape,
                 .tmin_surface = tmin_surface, .skip = skip, .best = -1, .tbest = INFINITY };
    if (tr->indexed) {
        double tmin = fmin(tmin_shape, tmin_surface);
        if (tr->rtc) {
            limen__rtc_ray(tr->rtc, o, d, tmin, INFINITY, test_prim_bvh, &q);
        } else {
            limen__bvh_ray(tr->surfaces, o, d, tmin, INFINITY, test_prim_bvh, &q);
            limen__bvh_ray(tr->shapes, o, d, tmin, q.tbest, test_prim_bvh, &q);
        }
        for (int i = tr->nbase; i < tr->n; i++)
            test_prim(&q, i);
    } else
        for (int i = 0; i < tr->n; i++)
            test_prim(&q, i);
    *t_out = q.tbest;
    memcpy(pu, q.pu, sizeof q.pu);
    memcpy(nu, q.nu, sizeof q.nu);
    memcpy(uv_out, q.uv, sizeof q.uv);
    return q.best;
}

/* ------------------------------------------------------------------ shading */

/* World normal of a hit, turned against the ray. */
static void world_normal(const prim *p, const double nu[3], const double d[3], double n[3])
{
    for (int r = 0; r < 3; r++)
        n[r] = p->nmat[r] * nu[0] + p->nmat[3 + r] * nu[1] + p->nmat[6 + r] * nu[2];
    if (!normalize3(n)) {
        n[0] = -d[0];
        n[1] = -d[1];
        n[2] = -d[2];
    }
    if (dot3(n, d) > 0) {
        n[0] = -n[0];
        n[1] = -n[1];
        n[2] = -n[2];
    }
}

/* Texture coordinates of a plane or box hit (limen.h): the unit point shifted by a half,
 * a box face taking its two other axes in order. */
static void flat_uv(const prim *p, const double pu[3], const double nu[3], double uv[2])
{
    int a = 2;
    if (p->uv == LIMEN_UV_BOX)
        a = fabs(nu[0]) > 0.5 ? 0 : fabs(nu[1]) > 0.5 ? 1 : 2;
    uv[0] = pu[(a + 1) % 3] + 0.5;
    uv[1] = pu[(a + 2) % 3] + 0.5;
}

/* The steps of a hit's texture coordinates (times repeat) to the next pixel across and up,
 * (du/dx, dv/dx, du/dy, dv/dy), from the unit-space point's steps dpu. */
static void uv_steps(const prim *p, const double nu[3], const double uv[UV_N],
                     const double dpu[2][3], double duv[4])
{
    int a = 2;
    if (p->uv == LIMEN_UV_BOX)
        a = fabs(nu[0]) > 0.5 ? 0 : fabs(nu[1]) > 0.5 ? 1 : 2;
    for (int i = 0; i < 2; i++) {
        if (p->shape == SHAPE_MESH) {
            duv[2 * i] = dot3(uv + 2, dpu[i]);
            duv[2 * i + 1] = dot3(uv + 5, dpu[i]);
        } else {
            duv[2 * i] = dpu[i][(a + 1) % 3];
            duv[2 * i + 1] = dpu[i][(a + 2) % 3];
        }
        duv[2 * i] *= p->repeat[0];
        duv[2 * i + 1] *= p->repeat[1];
    }
}

/* dpu: the unit-space point's steps to the next pixel across and up, or NULL (a lone ray:
 * the full image). */
static void shade(const tracer *tr, const prim *p, const double albedo_a[3], const double pu[3],
                  const double nu[3], const double uv_in[UV_N], const double dpu[2][3],
                  const double pw[3], const double n[3], double out[3], double *alpha)
{
    const double *albedo = albedo_a;
    double texel[3], mat[3], emissive[3] = { 0, 0, 0 };
    *alpha = 1;
    if (p->cell > 0) {
        double k = 0;
        int axes = p->flat ? 2 : 3;
        for (int i = 0; i < axes; i++)
            k += floor(pu[i] * p->scale[i] / p->cell);
        if (k - 2.0 * floor(k * 0.5) > 0.5)
            albedo = p->checker_b;
    }
    if (p->shape == SHAPE_MESH) {
        /* base x texel (the node's texture in place of the file's) x vertex colour */
        float rep[2] = { (float)p->repeat[0], (float)p->repeat[1] };
        double duv[4];
        if (dpu)
            uv_steps(p, nu, uv_in, dpu, duv);
        limen__mesh_material_at(p->mesh, p->tex, rep, p->filter, dpu ? duv : NULL,
                                (uint32_t)uv_in[UV_TRI], uv_in[UV_BU], uv_in[UV_BV], mat, alpha,
                                emissive);
        for (int k = 0; k < 3; k++)
            mat[k] *= albedo[k];
        albedo = mat;
    } else if (p->tex) {
        double uv[2] = { uv_in[0], uv_in[1] };
        flat_uv(p, pu, nu, uv);
        double duv[4];
        if (dpu)
            uv_steps(p, nu, uv_in, dpu, duv);
        limen__texture_filter(p->tex, p->filter, uv[0] * p->repeat[0], uv[1] * p->repeat[1],
                              dpu ? duv : NULL, texel);
        for (int k = 0; k < 3; k++)
            texel[k] *= albedo[k];
        albedo = texel;
    }
    double light[3] = { 0, 0, 0 };
    for (int i = 0; i < tr->nlights; i++) {
        double l[3] = { tr->lpos[i][0] - pw[0], tr->lpos[i][1] - pw[1], tr->lpos[i][2] - pw[2] };
        double w = 1.0;
        if (tr->lrange[i] > 0) {    /* the windowed falloff of limen.h's CONVENTIONS */
            double q = dot3(l, l) / (tr->lrange[i] * tr->lrange[i]);
            w = fmax(0.0, 1.0 - q * q);
            w *= w;
        }
        if (!normalize3(l))
            continue;
        double c = w * fmax(0.0, dot3(n, l));
        for (int k = 0; k < 3; k++)
            light[k] += tr->lcol[i][k] * c;
    }
    for (int k = 0; k < 3; k++) {
        double v = albedo[k] * (tr->ambient + (1.0 - tr->ambient) * light[k]);
        v = (v < 0 ? 0 : v > 1 ? 1 : v) + emissive[k];
        out[k] = v < 0 ? 0 : v > 1 ? 1 : v;
    }
}

/* ------------------------------------------------------------------ paths */

/* ------------------------------------------------------------------ ray differentials */

/* A pixel's footprint: how its ray's origin and unit direction change to the next pixel
 * across and up (0: across, 1: up), carried along the path as first-order differentials
 * (a mirror and a portal map both by their matrix, which is affine). */
typedef struct footprint {
    double o[2][3], d[2][3];
} footprint;

/* The change of normalize(v) for a change dv of v. */
static void unit_change(const double v[3], const double dv[3], double out[3])
{
    double len = sqrt(dot3(v, v)), u[3] = { v[0] / len, v[1] / len, v[2] / len };
    double c = dot3(u, dv);
    for (int k = 0; k < 3; k++)
        out[k] = (dv[k] - c * u[k]) / len;
}

/* The hit point's steps dp on a plane of normal nrm met at distance t along unit d. */
static void footprint_at(const footprint *f, const double d[3], double t, const double nrm[3],
                         double dp[2][3])
{
    double dn = dot3(d, nrm);
    for (int i = 0; i < 2; i++) {
        for (int k = 0; k < 3; k++)
            dp[i][k] = f->o[i][k] + t * f->d[i][k];
        double dt = -dot3(dp[i], nrm) / dn;     /* edge on: not finite, the coarsest level */
        for (int k = 0; k < 3; k++)
            dp[i][k] += dt * d[k];
    }
}

/* Through surface matrix x from a hit whose steps are dp, the ray's direction d (unit)
 * becoming normalize(x d). */
static void footprint_pass(footprint *f, const double x[16], const double dp[2][3],
                           const double d[3])
{
    double xd[3];
    d_dir(x, d, xd);
    for (int i = 0; i < 2; i++) {
        double xdd[3];
        d_dir(x, dp[i], f->o[i]);
        d_dir(x, f->d[i], xdd);
        unit_change(xd, xdd, f->d[i]);
    }
}

/* ------------------------------------------------------------------ paths */

/* Follows one path from o along d (any length) with hits before tmin (in units of |d|)
 * skipped on the first segment. lim: resolved limits (their depth fields). dd: how d
 * changes to the next pixel across and up (textures pick their level from it), or NULL.
 * rgb gets the colour; rec, if not NULL, where it ended. */
static void follow(const tracer *tr, const double o_in[3], const double d_in[3],
                   const double dd[2][3], double tmin0, double tmin_surface0,
                   const limen_limits *lim, double rgb[3], record *rec)
{
    double o[3], d[3], tint[3] = { 1, 1, 1 };
    memcpy(o, o_in, sizeof o);
    memcpy(d, d_in, sizeof d);
    footprint fp;
    memset(&fp, 0, sizeof fp);
    for (int i = 0; dd && i < 2; i++)
        unit_change(d_in, dd[i], fp.d[i]);
    double len = sqrt(dot3(d, d));
    double tmin = tmin0 * len, tmin_surface = tmin_surface0 * len;
    normalize3(d);
    int skip = -1, passed = 0, layers = 0;
    double travelled = 0, over[3] = { 0, 0, 0 }, cover = 1;   /* blended layers passed */
    const double *result = tr->background;
    double shaded[3];
    if (rec) {
        memset(rec, 0, sizeof *rec);
        rec->prim = -1;
    }
    for (;;) {
        double t, pu[3] = { 0, 0, 0 }, nu[3] = { 0, 0, 0 }, uv[UV_N] = { 0 };
        int hi = nearest(tr, o, d, tmin, tmin_surface, skip, &t, pu, nu, uv);
        if (rec) {
            memcpy(rec->seg_o, o, sizeof o);
            memcpy(rec->seg_d, d, sizeof d);
        }
        if (hi < 0)
            break;
        const prim *p = &tr->prims[hi];
        double pw[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
        travelled += t;
        bool surface = p->kind == LIMEN_NODE_MIRROR || p->kind == LIMEN_NODE_PORTAL;
        bool front = surface && dot3(p->plane, d) < 0;
        bool matte = !surface || (p->kind == LIMEN_NODE_MIRROR && !front);
        bool stop = !p->has_x || passed + 1 > limen__limits_depth(lim, p->max_depth);
        if (matte || stop) {
            double n[3];
            world_normal(p, nu, d, n);
            if (matte) {
                double dp[2][3], dpu[2][3];
                if (dd) {
                    footprint_at(&fp, d, t, n, dp);
                    for (int i = 0; i < 2; i++)
                        d_dir(p->minv, dp[i], dpu[i]);
                }
                double alpha;
                shade(tr, p, surface ? p->back : p->color, pu, nu, uv, dd ? dpu : NULL, pw, n,
                      shaded, &alpha);
                result = shaded;
                if (p->shape == SHAPE_MESH && layers < 64 &&
                    p->mesh->mats[p->mesh->parts[limen__tri_part(p->mesh, (uint32_t)uv[UV_TRI])]
                                     .material]
                            .alpha_mode == LIMEN_ALPHA_BLEND) {
                    /* blended: this over what lies behind, the ray going on past it */
                    for (int k = 0; k < 3; k++)
                        over[k] += cover * alpha * tint[k] * shaded[k];
                    cover *= 1.0 - alpha;
                    layers++;
                    result = tr->background;
                    memcpy(o, pw, sizeof o);
                    skip = -1;
                    tmin = 1e-9 * (1.0 + fmax(fabs(o[0]), fmax(fabs(o[1]), fabs(o[2]))));
                    tmin_surface = tmin;
                    continue;
                }
            } else {
                result = p->fill;
            }
            if (rec) {
                rec->hit = true;
                rec->prim = hi;
                rec->distance = travelled;
                memcpy(rec->point, pw, sizeof pw);
                memcpy(rec->normal, n, sizeof n);
            }
            break;
        }
        /* pass through: reflect, or leave by the partner */
        if (rec && passed < LIMEN_HIT_MAX_SURFACES)
            rec->chain[passed] = hi;
        passed++;
        if (p->kind == LIMEN_NODE_MIRROR)
            for (int k = 0; k < 3; k++)
                tint[k] *= p->tint[k];
        if (dd) {
            double dp[2][3];
            footprint_at(&fp, d, t, p->plane, dp);
            footprint_pass(&fp, p->x, dp, d);
        }
        limen__d_point(p->x, pw, o);
        d_dir(p->x, d, d);
        if (!normalize3(d))
            break;
        skip = p->exit;
        tmin = 1e-9 * (1.0 + fmax(fabs(o[0]), fmax(fabs(o[1]), fabs(o[2]))));
        tmin_surface = tmin;
    }
    if (rec) {
        rec->count = passed;
        if (!rec->hit)
            rec->distance = INFINITY;
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = over[k] + cover * tint[k] * result[k];
}

/* ------------------------------------------------------------------ public: rays */

limen_status limen_ray_cast(limen_scene *s, const float origin[3], const float dir[3],
                            const limen_limits *limits, limen_hit *out)
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!origin || !dir || !out)
        return limen__fail(s, LIMEN_ERR_ARG, "ray_cast: NULL origin, direction or output");
    if (!limen__finite3(origin))
        return limen__fail(s, LIMEN_ERR_ARG, "ray_cast: origin must be finite (got %g %g %g)",
                           origin[0], origin[1], origin[2]);
    double o[3], d[3];
    copy3f(origin, o);
    copy3f(dir, d);
    if (!limen__finite3(dir) || !(dot3(d, d) > 0))
        return limen__fail(s, LIMEN_ERR_ARG,
                           "ray_cast: direction must be finite and non-zero (got %g %g %g)",
                           dir[0], dir[1], dir[2]);
    limen_limits lim;
    limen_status st = limen__limits_resolve(s, "ray_cast", limits, &lim);
    if (st)
        return st;
    tracer tr;
    if ((st = limen__scene_check(s)))
        return st;
    st = tracer_init(&tr, s, "ray_cast");
    if (st)
        return st;
    record rec;
    double rgb[3];
    follow(&tr, o, d, NULL, 0.0, 0.0, &lim, rgb, &rec);
    memset(out, 0, sizeof *out);
    out->hit = rec.hit;
    out->distance = (float)rec.distance;
    for (int k = 0; k < 3; k++) {
        out->point[k] = (float)rec.point[k];
        out->normal[k] = (float)rec.normal[k];
        out->color[k] = (float)rgb[k];
        out->seg_origin[k] = (float)rec.seg_o[k];
        out->seg_dir[k] = (float)rec.seg_d[k];
    }
    if (rec.hit)
        out->node = limen__node_handle(s, tr.prims[rec.prim].node);
    out->surface_count = rec.count;
    for (int i = 0; i < rec.count && i < LIMEN_HIT_MAX_SURFACES; i++)
        out->surfaces[i] = limen__node_handle(s, tr.prims[rec.chain[i]].node);
    tracer_free(&tr);
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ public: images */

typedef struct job {
    const tracer *tr;
    double cam[16];             /* the camera's world matrix: eye space -> world */
    double tx, ty;              /* tan(fovy / 2) * aspect, tan(fovy / 2) */
    double znear;
    double eye[3];
    int width, height;
    limen_limits limits;        /* resolved */
    int first, step;            /* rows first, first + step, ... (PNG order) */
    unsigned char *rgb;
    int nsamples;
    const double (*samples)[2]; /* positions in the pixel, from its lower-left corner */
} job;

/* The standard 4x MSAA pattern (GL window coordinates, y up), as llvmpipe reports it. */
static const double msaa4[4][2] = {
    { 0.375, 0.125 }, { 0.875, 0.375 }, { 0.125, 0.625 }, { 0.625, 0.875 }
};
#define MAX_SAMPLES 256

/* Where a pixel's n samples lie (limen_trace_desc.samples); false if n is not allowed. */
static bool sample_positions(int n, double out[][2])
{
    if (n == 4) {
        memcpy(out, msaa4, sizeof msaa4);
        return true;
    }
    int k = (int)lround(sqrt((double)n));
    if (n < 1 || n > MAX_SAMPLES || k * k != n)
        return false;
    for (int i = 0; i < n; i++) {
        out[i][0] = (i % k + 0.5) / k;
        out[i][1] = (i / k + 0.5) / k;
    }
    return true;
}

static unsigned char to_byte(double c)
{
    c = c < 0 ? 0 : c > 1 ? 1 : c;
    return (unsigned char)lround(c * 255.0);
}

static void *trace_rows(void *arg)
{
    const job *j = arg;
    /* the rays through the next pixel across and up differ by these (a sample's footprint
     * is the pixel's, as the rasterizer's derivatives are per pixel with every sample
     * shaded) */
    double dd[2][3];
    for (int k = 0; k < 3; k++) {
        dd[0][k] = j->cam[k] * 2.0 * j->tx / j->width;
        dd[1][k] = j->cam[4 + k] * 2.0 * j->ty / j->height;
    }
    for (int row = j->first; row < j->height; row += j->step) {
        int gy = j->height - 1 - row;
        unsigned char *dst = j->rgb + (size_t)row * (size_t)j->width * 3;
        for (int x = 0; x < j->width; x++) {
            double sum[3] = { 0, 0, 0 };
            for (int si = 0; si < j->nsamples; si++) {
                double nx = (x + j->samples[si][0]) * 2.0 / j->width - 1.0;
                double ny = (gy + j->samples[si][1]) * 2.0 / j->height - 1.0;
                /* the ray through the sample, built from the lens in double: unprojecting
                 * points through a float projection lost the far point when far/near is
                 * large */
                double de[3] = { nx * j->tx, ny * j->ty, -1.0 }, d[3], rgb[3];
                for (int k = 0; k < 3; k++)
                    d[k] = j->cam[k] * de[0] + j->cam[4 + k] * de[1] + j->cam[8 + k] * de[2];
                /* from the eye: shapes count from the near plane on (the rasterizer's near
                 * clip), mirrors and portals from the eye on (the renderer draws them
                 * depth-clamped); eye-space z = -near is t = near in units of d */
                follow(j->tr, j->eye, d, dd, j->znear, 1e-12, &j->limits, rgb, NULL);
                for (int k = 0; k < 3; k++)     /* each sample clamped, as stored */
                    sum[k] += rgb[k] < 0 ? 0 : rgb[k] > 1 ? 1 : rgb[k];
            }
            for (int k = 0; k < 3; k++)
                dst[3 * x + k] = to_byte(sum[k] / j->nsamples);
        }
    }
    return NULL;
}

static int online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : (int)n;
}

limen_status limen_trace_image(limen_scene *s, const limen_trace_desc *desc, unsigned char *rgb)
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!rgb)
        return limen__fail(s, LIMEN_ERR_ARG, "trace: NULL image");
    limen_trace_desc d = desc ? *desc : (limen_trace_desc){ 0 };
    if (d.width < 0 || d.height < 0 || d.width > 16384 || d.height > 16384)
        return limen__fail(s, LIMEN_ERR_ARG, "trace: image size %dx%d out of range (1 to 16384)",
                           d.width, d.height);
    limen_limits lim;
    limen_status lst = limen__limits_resolve(s, "trace", &d.limits, &lim);
    if (lst)
        return lst;
    if (d.threads < 0)
        return limen__fail(s, LIMEN_ERR_ARG, "trace: thread count must be >= 0 (got %d)",
                           d.threads);
    if (d.lod_level < 0 || !(d.lod_pixels >= 0 || d.lod_pixels == LIMEN_LOD_FULL) ||
        !isfinite(d.lod_pixels))
        return limen__fail(s, LIMEN_ERR_ARG, "trace: lod_level must be >= 0 and lod_pixels >= 0 "
                           "or LIMEN_LOD_FULL (got %d and %g)", d.lod_level, (double)d.lod_pixels);
    double samples[MAX_SAMPLES][2];
    int nsamples = d.samples ? d.samples : 1;
    if (!sample_positions(nsamples, samples))
        return limen__fail(s, LIMEN_ERR_ARG, "trace: samples must be 1, 4 (the 4x MSAA pattern) "
                           "or a square up to 256 (a grid: 9, 16, 25, ...), got %d", d.samples);
    int width = d.width ? d.width : LIMEN_DEFAULT_WIDTH;
    int height = d.height ? d.height : LIMEN_DEFAULT_HEIGHT;
    limen_status cst = limen__scene_check(s);
    if (cst)
        return cst;
    if (!s->camera)
        return limen__fail(s, LIMEN_ERR_ARG, "scene has no camera (add s:camera{...})");
    const limen__node *cam = &s->nodes[s->camera - 1];
    /* the lens as the renderer's float projection has it (limen_perspective) */
    float aspect = (float)width / (float)height;
    double ty = tan(0.5 * (double)cam->fovy);
    job base = { .width = width, .height = height, .rgb = rgb, .tx = ty * (double)aspect,
                 .ty = ty, .znear = cam->znear, .limits = lim, .nsamples = nsamples,
                 .samples = (const double(*)[2])samples };
    limen__d_from_f(&cam->world[0][0], base.cam);
    for (int k = 0; k < 3; k++)
        base.eye[k] = base.cam[12 + k];
    limen_status st;
    tracer tr;
    if ((st = tracer_init(&tr, s, "trace")))
        return st;
    if ((st = tracer_levels(&tr, s, &d, width, height))) {
        tracer_free(&tr);
        return st;
    }
    if (!s->brute_force)
        tracer_index(&tr, s);
    base.tr = &tr;

    int nthreads = d.threads ? d.threads : online_cpus();
    if (nthreads > MAX_THREADS)
        nthreads = MAX_THREADS;
    if (nthreads > height)
        nthreads = height;
    job jobs[MAX_THREADS];
    pthread_t ids[MAX_THREADS];
    bool started[MAX_THREADS] = { false };
    for (int i = 0; i < nthreads; i++) {
        jobs[i] = base;
        jobs[i].first = i;
        jobs[i].step = nthreads;
    }
    /* thread 0's rows run on the calling thread; a thread that cannot start runs here too */
    for (int i = 1; i < nthreads; i++)
        started[i] = pthread_create(&ids[i], NULL, trace_rows, &jobs[i]) == 0;
    trace_rows(&jobs[0]);
    for (int i = 1; i < nthreads; i++) {
        if (started[i])
            pthread_join(ids[i], NULL);
        else
            trace_rows(&jobs[i]);
    }
    tracer_free(&tr);
    return LIMEN_OK;
}
