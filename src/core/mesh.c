/* mesh.c - triangle mesh nodes: geometry from arrays or from a file (through assimp), checked,
 * shared between the nodes of a scene that load the same file, with a bounding-volume
 * hierarchy for the ray tracer.
 *
 * Shading follows the file: where it has normals they are interpolated across each triangle;
 * where it has none, each triangle shows its face normal, unless the node asks for smooth
 * shading, which interpolates area-weighted vertex normals (computed here once per asset). */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/cfileio.h>
#include <assimp/types.h>

#include "core/confine.h"
#include "core/contain.h"
#include "core/internal.h"
#include "core/mesh.h"
#include "core/import.h"
#include "core/pages.h"
#include "core/texture.h"

#define LEAF_TRIS 4
#define MAX_TRIS (UINT32_MAX / 3u - 1u)
#define STACK_MAX 64

size_t limen__mesh_bytes(uint64_t nverts, uint64_t ntris, bool uvs)
{
    /* indices twice: the full mesh's and, at most as many again, its coarser levels */
    uint64_t b = sizeof(limen__mesh) + nverts * (uvs ? 8u : 6u) * sizeof(float) +
                 ntris * 7u * sizeof(uint32_t) + ntris * 2u * sizeof(limen__tri_node);
    return b > SIZE_MAX ? SIZE_MAX : (size_t)b;
}

/* ------------------------------------------------------------------ the hierarchy */

typedef struct build {
    limen__mesh *m;
    double *centre;             /* per triangle */
    int axes[STACK_MAX];        /* the split axes from the root down to the node being built */
} build;

/* Whether triangle a comes before b in the order a stable sort at every split would leave
 * them in below `depth` splits: by the centre along the last split's axis, ties by the one
 * before, and so on up to the root, then by number. Splitting by this order (selected, not
 * sorted) makes the same tree as sorting did, so rays meet triangles in the same order and
 * ties at equal distances fall as before. */
static bool before(const build *bd, int depth, uint32_t a, uint32_t b)
{
    for (int k = depth - 1; k >= 0; k--) {
        double ca = bd->centre[a * 3 + bd->axes[k]], cb = bd->centre[b * 3 + bd->axes[k]];
        if (ca != cb)
            return ca < cb;
    }
    return a < b;
}

static void swap_tris(uint32_t *t, uint32_t i, uint32_t j)
{
    uint32_t x = t[i];
    t[i] = t[j];
    t[j] = x;
}

/* Puts the `rank` first of t[0, n) in that order (among themselves in any order) before the
 * rest: quickselect, median of three. */
static void select_first(const build *bd, int depth, uint32_t *t, uint32_t n, uint32_t rank)
{
    uint32_t lo = 0, hi = n;    /* the boundary lies in [lo, hi) */
    while (hi - lo > 2) {
        uint32_t mid = lo + (hi - lo) / 2, a = t[lo], b = t[mid], c = t[hi - 1], pivot;
        if (before(bd, depth, a, b))
            pivot = before(bd, depth, b, c) ? b : before(bd, depth, a, c) ? c : a;
        else
            pivot = before(bd, depth, a, c) ? a : before(bd, depth, b, c) ? c : b;
        /* [lo, i) before the pivot, (j, hi) after it; all distinct, so the pivot lands alone */
        uint32_t i = lo, j = hi - 1;
        for (;;) {
            while (before(bd, depth, t[i], pivot))
                i++;
            while (before(bd, depth, pivot, t[j]))
                j--;
            if (i >= j)
                break;
            swap_tris(t, i, j);
        }
        /* t[j] is the pivot: j of them come before it */
        if (j == rank)
            return;
        if (j < rank)
            lo = j + 1;
        else
            hi = j;
    }
    if (hi - lo == 2 && before(bd, depth, t[lo + 1], t[lo]))
        swap_tris(t, lo, lo + 1);
}

static void tri_box(const limen__mesh *m, uint32_t t, float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++) {
        const float *p = &m->pos[m->idx[t * 3 + k] * 3];
        for (int a = 0; a < 3; a++) {
            lo[a] = fminf(lo[a], p[a]);
            hi[a] = fmaxf(hi[a], p[a]);
        }
    }
}

/* Builds the node at m->bvh[at] over tri_order[first, first + count), `depth` splits below
 * the root: median split on the widest axis of the triangles' centres, a leaf's triangles in
 * the order of the split above it. Depth is log2 of the count. */
static void build_node(build *bd, uint32_t at, uint32_t first, uint32_t count, int depth)
{
    limen__mesh *m = bd->m;
    uint32_t *t = &m->tri_order[first];
    limen__tri_node *n = &m->bvh[at];
    for (int a = 0; a < 3; a++) {
        n->lo[a] = INFINITY;
        n->hi[a] = -INFINITY;
    }
    if (count <= LEAF_TRIS) {
        for (uint32_t i = 1; i < count; i++)
            for (uint32_t j = i; j > 0 && before(bd, depth, t[j], t[j - 1]); j--)
                swap_tris(t, j, j - 1);
        for (uint32_t i = 0; i < count; i++)
            tri_box(m, t[i], n->lo, n->hi);
        n->index = first;
        n->count = count;
        return;
    }
    double clo[3] = { INFINITY, INFINITY, INFINITY }, chi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < count; i++)
        for (int a = 0; a < 3; a++) {
            clo[a] = fmin(clo[a], bd->centre[t[i] * 3 + a]);
            chi[a] = fmax(chi[a], bd->centre[t[i] * 3 + a]);
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (chi[a] - clo[a] > chi[axis] - clo[axis])
            axis = a;
    bd->axes[depth] = axis;
    uint32_t half = count / 2;
    select_first(bd, depth + 1, t, count, half);
    uint32_t left = m->nbvh++;  /* == at + 1: the caller has just claimed `at` */
    build_node(bd, left, first, half, depth + 1);
    uint32_t right = m->nbvh++;
    build_node(bd, right, first + half, count - half, depth + 1);
    /* the box is its children's: the same numbers as from its triangles */
    n = &m->bvh[at];
    n->index = right;
    n->count = 0;
    for (int a = 0; a < 3; a++) {
        n->lo[a] = fminf(m->bvh[left].lo[a], m->bvh[right].lo[a]);
        n->hi[a] = fmaxf(m->bvh[left].hi[a], m->bvh[right].hi[a]);
    }
}

/* The nodes build_node makes over n and over n + 1 triangles (out[0], out[1]): the halves
 * of both are of n / 2 and n / 2 + 1 triangles, so one step a depth. */
static void bvh_nodes(uint32_t n, uint64_t out[2])
{
    if (n + 1 <= LEAF_TRIS) {
        out[0] = out[1] = 1;
        return;
    }
    uint64_t half[2];           /* over k and k + 1 */
    bvh_nodes(n / 2, half);
    bool odd = n % 2;
    out[0] = n <= LEAF_TRIS ? 1 : odd ? 1 + half[0] + half[1] : 1 + 2 * half[0];
    out[1] = odd ? 1 + 2 * half[1] : 1 + half[0] + half[1];
}

/* Nodes are claimed as they are made, a left child in the slot after its parent; as many as
 * bvh_nodes counts (not the 2 * triangles a hierarchy may have at most, which at 1.6M
 * triangles held 120 MB more while it was built). */
static bool hierarchy_make(limen__mesh *m)
{
    uint64_t nodes[2];
    bvh_nodes(m->ntris, nodes);
    m->bvh = malloc(sizeof *m->bvh * (size_t)nodes[0]);
    m->tri_order = malloc(sizeof *m->tri_order * (size_t)m->ntris);
    double *centre = malloc(sizeof *centre * 3 * (size_t)m->ntris);
    if (!m->bvh || !m->tri_order || !centre) {
        free(centre);
        free(m->bvh);
        free(m->tri_order);
        m->bvh = NULL;
        m->tri_order = NULL;
        return false;
    }
    for (uint32_t t = 0; t < m->ntris; t++) {
        m->tri_order[t] = t;
        for (int a = 0; a < 3; a++) {
            double c = 0;
            for (int k = 0; k < 3; k++)
                c += m->pos[m->idx[t * 3 + k] * 3 + a];
            centre[t * 3 + a] = c / 3.0;
        }
    }
    build bd = { .m = m, .centre = centre };
    m->nbvh = 1;
    build_node(&bd, 0, 0, m->ntris, 0);
    free(centre);
    return true;
}

/* The bytes of the nodes a hierarchy over ntris triangles does not need of the 2 * ntris
 * that limen__mesh_bytes counts. */
static size_t nodes_unneeded(uint32_t ntris)
{
    uint64_t nodes[2];
    bvh_nodes(ntris, nodes);
    return sizeof(limen__tri_node) * (size_t)(2 * (uint64_t)ntris - nodes[0]);
}

bool limen__mesh_bvh(limen__mesh *m)
{
    if (!hierarchy_make(m))
        return false;
    m->bytes -= nodes_unneeded(m->ntris);
    atomic_store(&m->bvh_ready, true);
    return true;
}

/* One lock for every mesh's first hierarchy: made rarely, and by one thread at a time. */
static pthread_mutex_t hierarchy_lock = PTHREAD_MUTEX_INITIALIZER;

bool limen__mesh_hierarchy(const limen__mesh *cm)
{
    /* made once and never changed after: a cache of the mesh's, hence behind const */
    limen__mesh *m = (limen__mesh *)cm;
    if (atomic_load_explicit(&m->bvh_ready, memory_order_acquire))
        return true;
    pthread_mutex_lock(&hierarchy_lock);
    bool ok = atomic_load_explicit(&m->bvh_ready, memory_order_relaxed) ||
              hierarchy_make(m);
    if (ok)
        atomic_store_explicit(&m->bvh_ready, true, memory_order_release);
    pthread_mutex_unlock(&hierarchy_lock);
    return ok;
}

/* ------------------------------------------------------------------ intersection */

static bool slab(const limen__tri_node *n, const double o[3], const double inv[3], double tmin,
                 double tmax)
{
    for (int a = 0; a < 3; a++) {
        double t0 = (n->lo[a] - o[a]) * inv[a], t1 = (n->hi[a] - o[a]) * inv[a];
        if (t0 > t1) {
            double tmp = t0;
            t0 = t1;
            t1 = tmp;
        }
        if (isnan(t0) || isnan(t1))
            continue;   /* 0 * inf: the ray lies in the slab's boundary plane */
        tmin = fmax(tmin, t0);
        tmax = fmin(tmax, t1 * (1.0 + 4e-16));
        if (tmin > tmax)
            return false;
    }
    return true;
}

/* Möller-Trumbore in double, both sides. */
static bool hit_tri(const limen__mesh *m, uint32_t t, const double o[3], const double d[3],
                    double *tt, double *bu, double *bv)
{
    const float *p0 = &m->pos[m->idx[t * 3] * 3], *p1 = &m->pos[m->idx[t * 3 + 1] * 3],
                *p2 = &m->pos[m->idx[t * 3 + 2] * 3];
    double e1[3], e2[3], s[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)p1[a] - p0[a];
        e2[a] = (double)p2[a] - p0[a];
        s[a] = o[a] - p0[a];
    }
    double p[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                    d[0] * e2[1] - d[1] * e2[0] };
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0 || !isfinite(det))
        return false;
    double inv = 1.0 / det;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0 || u > 1)
        return false;
    double q[3] = { s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                    s[0] * e1[1] - s[1] * e1[0] };
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (v < 0 || u + v > 1)
        return false;
    *tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
    *bu = u;
    *bv = v;
    return true;
}

int limen__mesh_intersect(const limen__mesh *m, const double o[3], const double d[3],
                          double tmin, double tmax, const double *cut, double *t_out,
                          double *bu_out, double *bv_out)
{
    if (!m || !m->ntris || !limen__mesh_hierarchy(m))
        return -1;
    double inv[3] = { 1.0 / d[0], 1.0 / d[1], 1.0 / d[2] };
    uint32_t stack[STACK_MAX];
    int top = 0, best = -1;
    stack[top++] = 0;
    while (top > 0) {
        const limen__tri_node *n = &m->bvh[stack[--top]];
        if (!slab(n, o, inv, tmin, tmax))
            continue;
        if (n->count == 0) {
            if (top + 2 > STACK_MAX)
                continue;   /* depth is log2(triangles) <= 32: never */
            stack[top++] = n->index;
            stack[top++] = (uint32_t)(n - m->bvh) + 1u;
            continue;
        }
        for (uint32_t i = n->index; i < n->index + n->count; i++) {
            uint32_t tri = m->tri_order[i];
            double t, u, v;
            if (!hit_tri(m, tri, o, d, &t, &u, &v) || !(t > tmin) || !(t < tmax))
                continue;
            if (m->has_mask && limen__mesh_masked(m, tri, u, v))
                continue;
            if (cut) {
                double w[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
                if (cut[0] * w[0] + cut[1] * w[1] + cut[2] * w[2] + cut[3] < 0)
                    continue;
            }
            best = (int)tri;
            tmax = t;
            *t_out = t;
            *bu_out = u;
            *bv_out = v;
        }
    }
    return best;
}

/* ------------------------------------------------------------------ assets */

static void mesh_free(limen_scene *s, limen__mesh *m)
{
    if (!m)
        return;
    limen__mesh_lods_stop(m);
    limen__texture_release(s, m->tex);
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    free(m->bvh);
    free(m->tri_order);
    limen__mesh_lods_free(m);
    free(m->files);
    free(m->col);
    free(m->parts);
    free(m->lod_parts);
    free(m->tri_part);
    for (uint32_t i = 0; m->texs && i < m->nmats * LIMEN__MAT_TEXTURES; i++)
        limen__texture_release(s, m->texs[i]);
    free(m->texs);
    free(m->mats);
    free(m->mat_names);
    free(m);
}

/* Area-weighted vertex normals (the cross products' lengths are twice the areas). */
static void vertex_normals(limen__mesh *m)
{
    memset(m->nrm, 0, sizeof(float) * 3 * m->nverts);
    for (uint32_t t = 0; t < m->ntris; t++) {
        const uint32_t *ix = &m->idx[t * 3];
        const float *a = &m->pos[ix[0] * 3], *b = &m->pos[ix[1] * 3], *c = &m->pos[ix[2] * 3];
        vec3 e1, e2, n;
        glm_vec3_sub((float *)b, (float *)a, e1);
        glm_vec3_sub((float *)c, (float *)a, e2);
        glm_vec3_cross(e1, e2, n);
        for (int k = 0; k < 3; k++)
            glm_vec3_add(&m->nrm[ix[k] * 3], n, &m->nrm[ix[k] * 3]);
    }
    for (uint32_t v = 0; v < m->nverts; v++)
        glm_vec3_normalize(&m->nrm[v * 3]);
}

/* ------------------------------------------------------------------ parts and materials */

/* Parts must follow one another from triangle 0 to the last, each in a material given. */
static limen_status check_parts(limen_scene *s, const limen_mesh_data *d, const char *what)
{
    if (d->part_count < 0 || d->material_count < 0 || (d->part_count && !d->parts) ||
        (d->material_count && !d->materials))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: parts or materials counted but not given",
                           what);
    int next = 0;
    for (int p = 0; p < d->part_count; p++) {
        const limen_mesh_part *pt = &d->parts[p];
        if (pt->first_triangle != next || pt->triangle_count < 0 ||
            pt->triangle_count > d->triangle_count - next)
            return limen__fail(s, LIMEN_ERR_ARG, "%s: part %d covers triangles %d to %d; parts "
                               "must follow one another from triangle 0", what, p,
                               pt->first_triangle, pt->first_triangle + pt->triangle_count);
        int nmats = d->material_count ? d->material_count : 1;
        if (pt->material < 0 || pt->material >= nmats)
            return limen__fail(s, LIMEN_ERR_ARG, "%s: part %d uses material %d of %d", what, p,
                               pt->material, nmats);
        next += pt->triangle_count;
    }
    if (d->part_count && next != d->triangle_count)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: the parts cover %d of %d triangles", what,
                           next, d->triangle_count);
    for (int i = 0; i < d->material_count; i++) {
        const limen_material *mt = &d->materials[i];
        const float *f[] = { mt->base_color, mt->emissive };
        for (int k = 0; k < 7; k++)
            if (!isfinite(k < 4 ? f[0][k] : f[1][k - 4]))
                return limen__fail(s, LIMEN_ERR_ARG, "%s: material %d has a colour that is not "
                                   "finite", what, i);
        if ((unsigned)mt->alpha_mode > LIMEN_ALPHA_BLEND || !isfinite(mt->alpha_cutoff))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: material %d has an unknown alpha mode or "
                               "cutoff", what, i);
    }
    return LIMEN_OK;
}

static const limen_material white_material = {
    .name = "", .base_color = { 1, 1, 1, 1 }, .base_transform = { 1, 0, 0, 1, 0, 0 },
    .alpha_cutoff = 0.5f, .metallic = 1, .roughness = 1, .normal_scale = 1,
    .occlusion_strength = 1,
};

/* The colours, parts and materials of d into m (textures none); false when out of memory. */
static bool copy_materials(limen__mesh *m, const limen_mesh_data *d)
{
    uint32_t nv = m->nverts, nt = m->ntris;
    m->nparts = d->part_count ? (uint32_t)d->part_count : 1;
    m->nmats = d->material_count ? (uint32_t)d->material_count : 1;
    size_t names = 0;
    for (uint32_t i = 0; i < (uint32_t)d->material_count; i++)
        names += strlen(d->materials[i].name ? d->materials[i].name : "") + 1;
    m->col = d->colors ? malloc(sizeof(float) * 4 * nv) : NULL;
    m->parts = malloc(sizeof *m->parts * m->nparts);
    /* a part a triangle only where there are several (a 1.6M-triangle scan's 6 MB) */
    m->tri_part = m->nparts > 1 ? malloc(sizeof *m->tri_part * nt) : NULL;
    m->mats = malloc(sizeof *m->mats * m->nmats);
    m->texs = calloc((size_t)m->nmats * LIMEN__MAT_TEXTURES, sizeof *m->texs);
    m->mat_names = malloc(names + 1);
    if ((d->colors && !m->col) || !m->parts || (m->nparts > 1 && !m->tri_part) || !m->mats ||
        !m->texs ||
        !m->mat_names)
        return false;
    if (d->colors)
        memcpy(m->col, d->colors, sizeof(float) * 4 * nv);
    if (d->part_count)
        memcpy(m->parts, d->parts, sizeof *m->parts * m->nparts);
    else
        m->parts[0] = (limen_mesh_part){ 0, (int)nt, 0 };
    for (uint32_t p = 0; m->tri_part && p < m->nparts; p++)
        for (int t = 0; t < m->parts[p].triangle_count; t++)
            m->tri_part[m->parts[p].first_triangle + t] = p;
    char *at = m->mat_names;
    for (uint32_t i = 0; i < m->nmats; i++) {
        limen_material mt = d->material_count ? d->materials[i] : white_material;
        const char *name = mt.name ? mt.name : "";
        size_t len = strlen(name) + 1;
        memcpy(at, name, len);
        mt.name = at;
        at += len;
        mt.base_texture = mt.emissive_texture = NULL;
        mt.metallic_roughness_texture = mt.normal_texture = mt.occlusion_texture = NULL;
        m->mats[i] = mt;
        m->has_mask = m->has_mask || mt.alpha_mode == LIMEN_ALPHA_MASK;
        m->has_blend = m->has_blend || mt.alpha_mode == LIMEN_ALPHA_BLEND;
    }
    return true;
}

/* Each level's triangles grouped by part (stably), and the parts' ranges in it. A level's
 * triangle belongs to the part of its first corner in the full mesh: the simplifier only
 * joins vertices along edges, and a file's parts share no vertices, so a level's triangle
 * never spans two of them. */
bool limen__mesh_lod_parts(limen__mesh *m)
{
    free(m->lod_parts);
    uint32_t np = m->nparts, nl = m->nlods ? m->nlods : 1;
    m->lod_parts = malloc(sizeof *m->lod_parts * np * nl);
    uint32_t *vpart = malloc(sizeof *vpart * m->nverts);
    uint32_t *start = malloc(sizeof *start * (np + 1));
    uint32_t maxt = 0;
    for (uint32_t k = 0; k < m->nlods; k++)
        maxt = (uint32_t)m->lods[k].triangle_count > maxt ? (uint32_t)m->lods[k].triangle_count
                                                          : maxt;
    uint32_t *tmp = np > 1 ? malloc(sizeof *tmp * 3 * (size_t)(maxt ? maxt : 1)) : NULL;
    bool ok = m->lod_parts && vpart && start && (np == 1 || tmp);
    if (ok) {
        for (uint32_t t = 0; t < m->ntris; t++)
            for (int c = 0; c < 3; c++)
                vpart[m->idx[t * 3 + c]] = limen__tri_part(m, t);
        for (uint32_t k = 0; k < nl; k++) {
            limen_mesh_part *lp = &m->lod_parts[k * np];
            if (!m->nlods || m->lods[k].indices == m->idx) {
                memcpy(lp, m->parts, sizeof *lp * np);
            } else {
                uint32_t n = (uint32_t)m->lods[k].triangle_count;
                uint32_t *ix = (uint32_t *)m->lods[k].indices;
                memset(start, 0, sizeof *start * (np + 1));
                for (uint32_t t = 0; t < n; t++)
                    start[vpart[ix[t * 3]] + 1]++;
                for (uint32_t p = 0; p < np; p++) {
                    lp[p] = (limen_mesh_part){ (int)start[p], (int)start[p + 1],
                                               m->parts[p].material };
                    start[p + 1] += start[p];
                }
                if (np > 1) {
                    for (uint32_t t = 0; t < n; t++)
                        memcpy(&tmp[start[vpart[ix[t * 3]]]++ * 3], &ix[t * 3],
                               sizeof(uint32_t) * 3);
                    memcpy(ix, tmp, sizeof(uint32_t) * 3 * n);
                }
            }
            if (m->nlods)
                m->lods[k].parts = lp;
        }
    }
    free(vpart);
    free(start);
    free(tmp);
    return ok;
}

static void mat_texel(const limen__texture *t, const float repeat[2], limen_texture_filter f,
                      const double *duv, double u, double v, double c[3], double *a)
{
    if (!t)
        return;
    double x[3];
    double su = u * (repeat ? repeat[0] : 1), sv = v * (repeat ? repeat[1] : 1);
    limen__texture_filter(t, f, su, sv, duv, x);
    for (int k = 0; k < 3; k++)
        c[k] *= x[k];
    if (a)
        *a *= limen__texture_sample_alpha(t, su, sv);
}

void limen__mesh_material_at(const limen__mesh *m, const limen__texture *node_tex,
                             const float repeat[2], limen_texture_filter filter,
                             const double *duv, uint32_t tri, double u, double v,
                             double albedo[3], double *alpha, double emissive[3])
{
    const uint32_t *ix = &m->idx[tri * 3];
    double w[3] = { 1.0 - u - v, u, v }, uv[2] = { 0, 0 };
    for (int k = 0; m->uv && k < 2; k++)
        uv[k] = w[0] * m->uv[ix[0] * 2 + k] + w[1] * m->uv[ix[1] * 2 + k] +
                w[2] * m->uv[ix[2] * 2 + k];
    uint32_t mi = (uint32_t)m->parts[limen__tri_part(m, tri)].material;
    const limen_material *mt = &m->mats[mi];
    double a = mt->base_color[3];
    for (int k = 0; k < 3; k++)
        albedo[k] = mt->base_color[k];
    if (node_tex)
        mat_texel(node_tex, repeat, filter, duv, uv[0], uv[1], albedo, NULL);
    else
        mat_texel(m->texs[mi * LIMEN__MAT_TEXTURES + LIMEN__MAT_BASE], repeat, filter, duv,
                  uv[0], uv[1], albedo, &a);
    if (m->col)
        for (int k = 0; k < 4; k++) {
            double c = w[0] * m->col[ix[0] * 4 + k] + w[1] * m->col[ix[1] * 4 + k] +
                       w[2] * m->col[ix[2] * 4 + k];
            if (k < 3)
                albedo[k] *= c;
            else
                a *= c;
        }
    *alpha = a;
    for (int k = 0; k < 3; k++)
        emissive[k] = mt->emissive[k];
    mat_texel(m->texs[mi * LIMEN__MAT_TEXTURES + LIMEN__MAT_EMISSIVE], repeat, filter, duv,
              uv[0], uv[1], emissive, NULL);
}

bool limen__mesh_masked(const limen__mesh *m, uint32_t tri, double u, double v)
{
    const limen_material *mt = &m->mats[m->parts[limen__tri_part(m, tri)].material];
    if (mt->alpha_mode != LIMEN_ALPHA_MASK)
        return false;
    double c[3], a, e[3];
    limen__mesh_material_at(m, NULL, NULL, LIMEN_FILTER_LINEAR, NULL, tri, u, v, c, &a, e);
    return a < mt->alpha_cutoff;
}

static limen_status mesh_textures(limen_scene *s, const limen__import *b, uint32_t only,
                                  const char *path, limen__mesh *m);

/* Checks and copies arrays into a new asset. what names the source in messages. blk: the
 * imported block the arrays come from (node `only` of it), whose textures the asset takes
 * before its levels of detail are made (a textured mesh's coarse levels are baked from
 * them), or NULL. */
static limen_status mesh_from_arrays(limen_scene *s, const limen_mesh_data *d, const char *what,
                                     size_t max_bytes, const limen__import *blk, uint32_t only,
                                     limen__mesh **out)
{
    *out = NULL;
    if (!d || !d->positions || !d->indices)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: needs positions and indices", what);
    if (d->triangle_count < 1)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: no triangles", what);
    if (d->vertex_count < 3 && d->vertex_count > 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: triangle 0 is degenerate, as is every other "
                           "(%d vertices, fewer than a triangle needs; a vertex that is not a "
                           "number is dropped)", what, d->vertex_count);
    if (d->vertex_count < 3)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: %d vertices, fewer than a triangle needs "
                           "(a vertex that is not a number is dropped)", what, d->vertex_count);
    if ((uint64_t)d->triangle_count > MAX_TRIS)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: %d triangles, more than a mesh holds", what,
                           d->triangle_count);
    size_t bytes = limen__mesh_bytes((uint64_t)d->vertex_count, (uint64_t)d->triangle_count,
                                     d->uvs != NULL);
    if (bytes > max_bytes && (s->mem_wanted = bytes))
        return limen__fail(s, LIMEN_ERR_NOMEM,
                           "%s: %d triangles need %.1f MiB, more than the %.1f MiB allowed", what,
                           d->triangle_count, bytes / 1048576.0, max_bytes / 1048576.0);
    uint32_t nv = (uint32_t)d->vertex_count, nt = (uint32_t)d->triangle_count;
    for (uint32_t i = 0; i < nv * 3; i++)
        if (!isfinite(d->positions[i]) || (d->normals && !isfinite(d->normals[i])))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: vertex %u has a %s that is not finite",
                               what, i / 3, isfinite(d->positions[i]) ? "normal" : "position");
    for (uint32_t i = 0; d->uvs && i < nv * 2; i++)
        if (!isfinite(d->uvs[i]))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: vertex %u has a texture coordinate that "
                               "is not finite", what, i / 2);
    for (uint32_t i = 0; i < nt * 3; i++)
        if (d->indices[i] >= nv)
            return limen__fail(s, LIMEN_ERR_ARG,
                               "%s: triangle %u uses vertex %u, out of range (%u vertices)",
                               what, i / 3, d->indices[i], nv);
    for (uint32_t i = 0; d->colors && i < nv * 4; i++)
        if (!isfinite(d->colors[i]))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: vertex %u has a colour that is not finite",
                               what, i / 4);
    limen_status pst = check_parts(s, d, what);
    if (pst)
        return pst;
    uint32_t flat = 0;      /* triangles with no area, before the first that has one */
    while (flat < nt) {
        const uint32_t *ix = &d->indices[flat * 3];
        const float *a = &d->positions[ix[0] * 3], *b = &d->positions[ix[1] * 3],
                    *c = &d->positions[ix[2] * 3];
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)b[k] - a[k];
            e2[k] = (double)c[k] - a[k];
        }
        if (e1[1] * e2[2] - e1[2] * e2[1] != 0 || e1[2] * e2[0] - e1[0] * e2[2] != 0 ||
            e1[0] * e2[1] - e1[1] * e2[0] != 0)
            break;
        flat++;
    }
    if (flat == nt)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: triangle 0 is degenerate (its corners meet or "
                           "lie on a line) and so is every other: no triangle has an area", what);
    limen__mesh *m = calloc(1, sizeof *m);
    if (!m)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", what);
    m->nverts = nv;
    m->ntris = nt;
    m->bytes = bytes;
    m->pos = limen__malloc_populated(sizeof(float) * 3 * nv);
    m->nrm = limen__malloc_populated(sizeof(float) * 3 * nv);
    m->uv = d->uvs ? limen__malloc_populated(sizeof(float) * 2 * nv) : NULL;
    m->idx = limen__malloc_populated(sizeof(uint32_t) * 3 * nt);
    if (!m->pos || !m->nrm || (d->uvs && !m->uv) || !m->idx || !copy_materials(m, d)) {
        mesh_free(s, m);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", what);
    }
    memcpy(m->pos, d->positions, sizeof(float) * 3 * nv);
    memcpy(m->idx, d->indices, sizeof(uint32_t) * 3 * nt);
    if (d->uvs)
        memcpy(m->uv, d->uvs, sizeof(float) * 2 * nv);
    if (d->normals) {
        memcpy(m->nrm, d->normals, sizeof(float) * 3 * nv);
        m->file_normals = true;
    } else {
        vertex_normals(m);
    }
    for (int a = 0; a < 3; a++) {
        m->lo[a] = INFINITY;
        m->hi[a] = -INFINITY;
    }
    for (uint32_t v = 0; v < nv; v++)
        for (int a = 0; a < 3; a++) {
            m->lo[a] = fmin(m->lo[a], m->pos[v * 3 + a]);
            m->hi[a] = fmax(m->hi[a], m->pos[v * 3 + a]);
        }
    /* the hierarchy is made when first needed (limen__mesh_hierarchy), counted now */
    m->bytes -= nodes_unneeded(nt);
    snprintf(m->name, sizeof m->name, "%s", what);
    limen_status tst = blk ? mesh_textures(s, blk, only, what, m) : LIMEN_OK;
    if (tst) {
        mesh_free(s, m);
        return tst;
    }
    if (!limen__mesh_lods_start(m) || !limen__mesh_lod_parts(m)) {
        mesh_free(s, m);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", what);
    }
    m->bytes += sizeof(float) * 4 * (d->colors ? nv : 0) + sizeof(uint32_t) * nt +
                sizeof(limen_mesh_part) * m->nparts * (m->nlods + 1) +
                sizeof(limen_material) * m->nmats;
    m->serial = limen__next_serial();
    m->pub = (limen_mesh_geometry){ .id = m->serial, .vertex_count = (int)nv,
                                    .triangle_count = (int)nt, .positions = m->pos,
                                    .normals = m->nrm, .uvs = m->uv, .indices = m->idx,
                                    .lod_count = (int)m->nlods, .lods = m->lods,
                                    .colors = m->col, .part_count = (int)m->nparts,
                                    .parts = m->parts, .material_count = (int)m->nmats,
                                    .materials = m->mats, .has_blend = m->has_blend };
    snprintf(m->name, sizeof m->name, "%s", what);
    *out = m;
    return LIMEN_OK;
}

static limen_status keep(limen_scene *s, limen__mesh *m, const char *what)
{
    if (limen__assets_add(&s->meshes, &s->nmeshes, &s->mesh_cap, m))
        return LIMEN_OK;
    mesh_free(s, m);
    return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", what);
}

void limen__mesh_release(limen_scene *s, limen__mesh *m)
{
    if (!m || --m->refs > 0)
        return;
    limen__assets_remove(s->meshes, &s->nmeshes, m);
    mesh_free(s, m);
}

void limen__meshes_destroy(limen_scene *s)
{
    for (int i = 0; i < s->nmeshes; i++)
        mesh_free(s, s->meshes[i]);
    free(s->meshes);
    s->meshes = NULL;
    s->nmeshes = s->mesh_cap = 0;
    limen_scene_clear_warnings(s);
}

static void attach(limen_scene *s, limen__node *node, limen__mesh *m)
{
    m->refs++;
    limen__mesh_release(s, node->mesh);
    node->mesh = m;
    s->dirty = true;
    limen__node_touch(s, node);     /* its bounds changed */
}

/* ------------------------------------------------------------------ files */

/* The file's meshes where its nodes place them, merged into one list of parts, one per
 * material used (assimp's PreTransformVertices, done here so that the block keeps the
 * hierarchy). Each part's texture coordinates are its base texture's set with its transform
 * applied. */
typedef struct flat {
    float *pos, *nrm, *uv, *col;
    uint32_t *idx;
    limen_mesh_part *parts;
    limen_material *mats;
    uint32_t nv, nt, np;
} flat;

static void flat_free(flat *f)
{
    free(f->pos);
    free(f->nrm);
    free(f->uv);
    free(f->col);
    free(f->idx);
    free(f->parts);
    free(f->mats);
}

/* The world matrices of the block's nodes (parents come first). */
static float *node_worlds(const limen__import *b)
{
    const limen__import_node *ns = LIMEN__IMP(b, nodes, limen__import_node);
    float *w = malloc(sizeof(float) * 16 * (b->nnodes ? b->nnodes : 1));
    for (uint32_t i = 0; w && i < b->nnodes; i++) {
        /* cglm wants its matrices aligned: work on copies */
        mat4 parent, local, out;
        memcpy(local, ns[i].matrix, sizeof local);
        if (ns[i].parent == LIMEN__IMPORT_NONE) {
            glm_mat4_copy(local, out);
        } else {
            memcpy(parent, &w[ns[i].parent * 16], sizeof parent);
            glm_mat4_mul(parent, local, out);
        }
        memcpy(&w[i * 16], out, sizeof out);
    }
    return w;
}

/* only: one node's parts in its own frame (a model's node: core/model.c), or
 * LIMEN__IMPORT_NONE for every node's where the file places them. */
static limen_status flatten(limen_scene *s, const limen__import *b, uint32_t only,
                           const char *path, flat *f)
{
    memset(f, 0, sizeof *f);
    const limen__import_node *ns = LIMEN__IMP(b, nodes, limen__import_node);
    const limen__import_part *ps = LIMEN__IMP(b, parts, limen__import_part);
    const limen__import_material *ms = LIMEN__IMP(b, materials, limen__import_material);
    const limen__import_vertex *vs = LIMEN__IMP(b, verts, limen__import_vertex);
    const uint32_t *ts = LIMEN__IMP(b, tris, uint32_t), *np = LIMEN__IMP(b, node_parts, uint32_t);
    uint64_t nv = 0, nt = 0;
    for (uint32_t n = 0; n < b->nnodes; n++)
        for (uint32_t k = 0; k < ns[n].part_count && (only == LIMEN__IMPORT_NONE || n == only);
             k++) {
            const limen__import_part *p = &ps[np[ns[n].first_part + k]];
            if (p->tri_count) {
                nv += p->vertex_count;
                nt += p->tri_count;
            }
        }
    if (nt == 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: no triangles in it (points and lines are "
                           "skipped)", path);
    if (nt > MAX_TRIS || nv > MAX_TRIS)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: %llu triangles, more than a mesh holds", path,
                           (unsigned long long)nt);
    float *world = node_worlds(b);
    /* each written through, vertex by vertex, triangle by triangle */
    f->pos = limen__malloc_populated(sizeof(float) * 3 * nv);
    f->nrm = limen__malloc_populated(sizeof(float) * 3 * nv);
    f->uv = limen__malloc_populated(sizeof(float) * 2 * nv);
    f->col = limen__malloc_populated(sizeof(float) * 4 * nv);
    f->idx = limen__malloc_populated(sizeof(uint32_t) * 3 * nt);
    f->parts = malloc(sizeof *f->parts * b->nmaterials);
    f->mats = malloc(sizeof *f->mats * b->nmaterials);
    if (!world || !f->pos || !f->nrm || !f->uv || !f->col || !f->idx || !f->parts || !f->mats) {
        free(world);
        flat_free(f);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    }
    bool normals = true;
    for (uint32_t mi = 0; mi < b->nmaterials; mi++) {
        const limen__import_material *mt = &ms[mi];
        uint32_t first = f->nt;
        for (uint32_t n = 0; n < b->nnodes; n++) {
            if (only != LIMEN__IMPORT_NONE && n != only)
                continue;
            static const float own[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
            const float *w = only == LIMEN__IMPORT_NONE ? &world[n * 16] : own;
            mat4 wm;
            mat3 nm;
            memcpy(wm, w, sizeof wm);
            glm_mat4_pick3(wm, nm);
            glm_mat3_inv(nm, nm);
            glm_mat3_transpose(nm);
            bool flip = glm_mat4_det(wm) < 0;
            for (uint32_t k = 0; k < ns[n].part_count; k++) {
                const limen__import_part *p = &ps[np[ns[n].first_part + k]];
                if (p->material != mi || !p->tri_count)
                    continue;
                normals = normals && p->has_normals;
                uint32_t v0 = f->nv;
                for (uint32_t v = 0; v < p->vertex_count; v++) {
                    const limen__import_vertex *iv = &vs[p->first_vertex + v];
                    vec4 q = { iv->pos[0], iv->pos[1], iv->pos[2], 1 };
                    vec4 r;
                    glm_mat4_mulv(wm, q, r);
                    memcpy(&f->pos[f->nv * 3], r, sizeof(float) * 3);
                    vec3 nn, n0 = { iv->nrm[0], iv->nrm[1], iv->nrm[2] };
                    glm_mat3_mulv(nm, n0, nn);
                    glm_vec3_normalize(nn);
                    memcpy(&f->nrm[f->nv * 3], nn, sizeof nn);
                    const float *uv = iv->uv[mt->base_uv], *x = mt->base_xform;
                    f->uv[f->nv * 2] = x[0] * uv[0] + x[2] * uv[1] + x[4];
                    f->uv[f->nv * 2 + 1] = x[1] * uv[0] + x[3] * uv[1] + x[5];
                    memcpy(&f->col[f->nv * 4], iv->col, sizeof(float) * 4);
                    f->nv++;
                }
                for (uint32_t t = 0; t < p->tri_count; t++, f->nt++) {
                    const uint32_t *tri = &ts[(size_t)(p->first_tri + t) * 3];
                    f->idx[f->nt * 3] = v0 + tri[0];
                    f->idx[f->nt * 3 + 1] = v0 + (flip ? tri[2] : tri[1]);
                    f->idx[f->nt * 3 + 2] = v0 + (flip ? tri[1] : tri[2]);
                }
            }
        }
        if (f->nt == first)
            continue;
        f->mats[f->np] = (limen_material){
            .name = limen__import_string(b, mt->name),
            .base_color = { mt->base[0], mt->base[1], mt->base[2], mt->base[3] },
            .base_texcoord = (int)mt->base_uv, .alpha_mode = (limen_alpha_mode)mt->alpha_mode,
            .alpha_cutoff = mt->alpha_cutoff,
            .emissive = { mt->emissive[0], mt->emissive[1], mt->emissive[2] },
            .double_sided = (int)mt->double_sided, .metallic = mt->metallic,
            .roughness = mt->roughness, .normal_scale = mt->normal_scale,
            .occlusion_strength = mt->occlusion_strength,
        };
        memcpy(f->mats[f->np].base_transform, mt->base_xform, sizeof mt->base_xform);
        f->parts[f->np] = (limen_mesh_part){ (int)first, (int)(f->nt - first), (int)f->np };
        f->np++;
    }
    free(world);
    if (!normals) {
        free(f->nrm);
        f->nrm = NULL;
    }
    return LIMEN_OK;
}

/* The block's material index of the flattened mesh's material k (the k-th used; by node
 * `only`, or by any node where it is LIMEN__IMPORT_NONE). */
static uint32_t used_material(const limen__import *b, uint32_t only, uint32_t k)
{
    const limen__import_node *ns = LIMEN__IMP(b, nodes, limen__import_node);
    const limen__import_part *ps = LIMEN__IMP(b, parts, limen__import_part);
    const uint32_t *np = LIMEN__IMP(b, node_parts, uint32_t);
    for (uint32_t mi = 0; mi < b->nmaterials; mi++) {
        bool used = false;
        for (uint32_t n = 0; n < b->nnodes && !used; n++)
            for (uint32_t j = 0; j < ns[n].part_count && !used &&
                                 (only == LIMEN__IMPORT_NONE || n == only); j++) {
                const limen__import_part *p = &ps[np[ns[n].first_part + j]];
                used = p->material == mi && p->tri_count;
            }
        if (used && k-- == 0)
            return mi;
    }
    return 0;
}

/* The block's textures onto the mesh's materials (each decoded image made once). */
static limen_status mesh_textures(limen_scene *s, const limen__import *b, uint32_t only,
                                  const char *path, limen__mesh *m)
{
    const limen__import_material *ms = LIMEN__IMP(b, materials, limen__import_material);
    const limen__import_texture *ts = LIMEN__IMP(b, textures, limen__import_texture);
    limen__texture **made = calloc(b->ntextures ? b->ntextures : 1, sizeof *made);
    if (!made)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    limen_status st = LIMEN_OK;
    for (uint32_t k = 0; k < m->nmats && !st; k++) {
        const limen__import_material *mt = &ms[used_material(b, only, k)];
        uint32_t which[LIMEN__MAT_TEXTURES] = { mt->base_tex, mt->emissive_tex,
                                                mt->metal_rough_tex, mt->normal_tex,
                                                mt->occlusion_tex };
        for (int j = 0; j < LIMEN__MAT_TEXTURES && !st; j++) {
            uint32_t ti = which[j];
            if (ti == LIMEN__IMPORT_NONE || !ts[ti].width)
                continue;
            if (!made[ti]) {
                char what[700];
                snprintf(what, sizeof what, "%.300s: texture %.300s", path,
                         limen__import_string(b, ts[ti].name));
                st = limen__texture_from_rgba(s, (const unsigned char *)b + ts[ti].texels,
                                              (int)ts[ti].width, (int)ts[ti].height, what,
                                              &made[ti]);
                if (st)
                    break;
                m->bytes += made[ti]->bytes;
            } else {
                made[ti]->refs++;
            }
            m->texs[k * LIMEN__MAT_TEXTURES + j] = made[ti];
            const limen_image *img = &made[ti]->pub;
            limen_material *pm = &m->mats[k];
            if (j == LIMEN__MAT_BASE)
                pm->base_texture = img;
            else if (j == LIMEN__MAT_EMISSIVE)
                pm->emissive_texture = img;
            else if (j == LIMEN__MAT_MR)
                pm->metallic_roughness_texture = img;
            else if (j == LIMEN__MAT_NORMAL)
                pm->normal_texture = img;
            else
                pm->occlusion_texture = img;
        }
    }
    /* each image's first reference is the one made with it */
    free(made);
    if (!m->tex && m->nmats && m->texs[LIMEN__MAT_BASE]) {
        m->tex = m->texs[LIMEN__MAT_BASE];
        m->tex->refs++;
    }
    return st;
}

/* The block's warnings into the scene's list, as "file: warning: text". */
void limen__mesh_keep_warnings(limen_scene *s, const limen__import *b, const char *path)
{
    const uint32_t *ws = LIMEN__IMP(b, warnings, uint32_t);
    for (uint32_t i = 0; i < b->nwarnings; i++) {
        char **w = realloc(s->warnings, sizeof *w * (size_t)(s->nwarnings + 1));
        if (!w)
            return;
        s->warnings = w;
        const char *text = limen__import_string(b, ws[i]);
        size_t len = strlen(path) + strlen(text) + 16;
        char *line = malloc(len);
        if (!line)
            return;
        snprintf(line, len, "%s: warning: %s", path, text);
        s->warnings[s->nwarnings++] = line;
    }
}

/* ------------------------------------------------------------------ the importer's way in */

/* assimp opens every file it reads (the mesh file, an OBJ's mtllib, a glTF's buffers)
 * through these callbacks (aiFileIO), so through the scene's one way in
 * (core/confine.c): beneath the scene's folder in safe mode, never blocking, the bytes
 * counted. Each file is read whole on opening; reads and seeks are then in memory. */

typedef struct io_file {
    struct aiFile f;
    unsigned char *data;
    size_t len, at;
} io_file;

typedef struct io_ctx {
    struct aiFileIO io;
    limen_scene *s;
    char why[LIMEN__ERR_MAX];   /* the first file that could not be opened, and why */
    limen__block files;         /* the paths read, each ended by a NUL */
} io_ctx;

static size_t io_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    io_file *x = (io_file *)f->UserData;
    if (size == 0 || x->at >= x->len)
        return 0;
    size_t n = (x->len - x->at) / size;
    n = n < count ? n : count;
    memcpy(buf, x->data + x->at, n * size);
    x->at += n * size;
    return n;
}

static size_t io_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    return 0;
}

static size_t io_tell(struct aiFile *f)
{
    return ((io_file *)f->UserData)->at;
}

static size_t io_size(struct aiFile *f)
{
    return ((io_file *)f->UserData)->len;
}

static enum aiReturn io_seek(struct aiFile *f, size_t off, enum aiOrigin origin)
{
    io_file *x = (io_file *)f->UserData;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? x->at : x->len;
    if (off > x->len || base > x->len - off)
        return aiReturn_FAILURE;
    x->at = base + off;
    return aiReturn_SUCCESS;
}

static void io_flush(struct aiFile *f)
{
}

static bool io_listed(const limen__block *b, const char *path)
{
    for (size_t at = 0; at < b->len; at += strlen((const char *)b->data + at) + 1)
        if (strcmp((const char *)b->data + at, path) == 0)
            return true;
    return false;
}

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode)
{
    io_ctx *c = (io_ctx *)io->UserData;
    if (!path || strpbrk(mode, "wa+"))
        return NULL;
    io_file *x = calloc(1, sizeof *x);
    struct stat st;
    if (!x || limen__file_read(c->s, path, &x->data, &x->len, &st)) {
        if (!c->why[0])
            snprintf(c->why, sizeof c->why, "%s", x ? c->s->err : "out of memory");
        free(x);
        return NULL;
    }
    if (!io_listed(&c->files, path))
        limen__block_put(&c->files, path, strlen(path) + 1);
    x->f = (struct aiFile){ .ReadProc = io_read, .WriteProc = io_write, .TellProc = io_tell,
                            .FileSizeProc = io_size, .SeekProc = io_seek, .FlushProc = io_flush,
                            .UserData = (aiUserData)x };
    return &x->f;
}

static void io_close(struct aiFileIO *io, struct aiFile *f)
{
    io_ctx *c = (io_ctx *)io->UserData;
    io_file *x = (io_file *)f->UserData;
    if (c->s->load)
        c->s->load->read_bytes -= x->len < c->s->load->read_bytes ? x->len
                                                                    : c->s->load->read_bytes;
    free(x->data);
    free(x);
}

/* ------------------------------------------------------------------ importing */

/* The hooks import.c reads every file through (core/import.h): assimp's through io, the
 * textures a model names through read and exists, all on the scene's one way in. */
static unsigned char *hook_read(void *ctx, const char *path, size_t max, size_t *len)
{
    io_ctx *c = ctx;
    unsigned char *data;
    struct stat st;
    size_t keep = 0;
    limen__load *ld = c->s->load;
    if (ld) {       /* a texture is held no longer than the import */
        keep = ld->max_bytes;
        ld->max_bytes = max < keep ? max + ld->read_bytes : keep;
    }
    limen_status rc = limen__file_read(c->s, path, &data, len, &st);
    if (ld) {
        ld->max_bytes = keep;
        if (!rc)
            ld->read_bytes -= *len;
    }
    if (rc)
        return NULL;
    if (!io_listed(&c->files, path))
        limen__block_put(&c->files, path, strlen(path) + 1);
    return data;
}

static bool hook_exists(void *ctx, const char *path)
{
    io_ctx *c = ctx;
    char why[160];
    struct stat st;
    int fd = limen__confine_open(c->s->load ? c->s->load->box : NULL, path, &st, why, sizeof why);
    if (fd >= 0)
        close(fd);
    return fd >= 0;
}

/* Imports path in this process into a block (core/import.h), every file through the scene's
 * way in; the files read into files. */
static limen_status import_here(limen_scene *s, const char *path, unsigned flags,
                                size_t max_bytes, limen__import **blk, limen__block *files)
{
    *blk = NULL;
    io_ctx c = { .io = { io_open, io_close, NULL }, .s = s };
    c.io.UserData = (aiUserData)&c;
    limen__import_files hooks = { .io = &c.io, .ctx = &c, .read = hook_read,
                                  .exists = hook_exists,
                                  .inside = s->load && s->load->inside };
    char ierr[700];
    limen__import_files_hook = &hooks;
    limen_status st = limen__import_file(path, flags, max_bytes, blk, ierr, sizeof ierr);
    limen__import_files_hook = NULL;
    if (st) {
        size_t pl = strlen(path);
        if (c.why[0] && strncmp(c.why, path, pl) == 0 && c.why[pl] == ':')
            st = limen__fail(s, LIMEN_ERR_IO, "%s", c.why);
        else if (c.why[0] && strstr(ierr, "cannot read it as a mesh"))
            st = limen__fail(s, LIMEN_ERR_IO, "%s: %s", path, c.why);
        else if (strstr(ierr, "bad_alloc"))
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: the importer ran out of memory reading it "
                             "(%.1f MiB left)", path, max_bytes / 1048576.0);
        else
            st = limen__fail(s, st, "%s", ierr);
        limen__block_free(&c.files);
        return st;
    }
    *files = c.files;
    return LIMEN_OK;
}

/* In the worker: the job is [flags][max_bytes][the load's max_bytes, read_bytes][safe, box][the
 * folder's prefix, NUL][path, NUL], the folder's descriptor beside it (-1: no folder). The
 * import runs for a scene of the worker's own that holds only that load; the answer is [the
 * block][the files read, each ended by a NUL]. */
static int import_job(limen__block *job, int fd, limen__block *out, char *why, size_t why_size)
{
    uint32_t flags;
    uint64_t mb[3];
    uint8_t safe[2];
    const char *prefix, *path;
    if (!limen__block_get(job, &flags, sizeof flags) || !limen__block_get(job, mb, sizeof mb) ||
        !limen__block_get(job, safe, 2) || safe[1] > 2 || job->len == 0 || job->data[job->len - 1] != '\0') {
        snprintf(why, why_size, "a broken job");
        return LIMEN_ERR_IO;
    }
    prefix = (const char *)job->data + job->at;
    path = prefix + strlen(prefix) + 1;
    if ((const unsigned char *)path >= job->data + job->len) {
        snprintf(why, why_size, "a broken job");
        return LIMEN_ERR_IO;
    }
    /* no box, one that is off (any path), or on: beneath fd (-1: the folder could not
     * open, nothing opens) */
    limen__confine box = { .on = safe[1] == 2, .dir = safe[1] == 2 ? fd : -1 };
    snprintf(box.prefix, sizeof box.prefix, "%s", prefix);
    limen__load ld = { .box = safe[1] ? &box : NULL, .safe = safe[0], .max_bytes = mb[1],
                       .read_bytes = mb[2], .inside = true };
    limen_scene *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(why, why_size, "out of memory");
        return LIMEN_ERR_NOMEM;
    }
    s->load = &ld;
    limen__import *blk;
    limen__block files = { 0 };
    limen_status st = import_here(s, path, flags, mb[0], &blk, &files);
    if (st) {
        snprintf(why, why_size, "%s", s->err);
        free(s);
        return (int)st;
    }
    for (int i = 0; i < s->nwarnings; i++)
        free(s->warnings[i]);
    free(s->warnings);
    free(s);
    /* the block itself becomes the answer (no copy), the files read after it */
    *out = (limen__block){ .data = (unsigned char *)blk, .len = (size_t)blk->size,
                           .cap = (size_t)blk->size };
    limen__block_put(out, files.data, files.len);
    limen__block_free(&files);
    return 0;
}

/* Imports path in a child under what the script has left (core/contain.c): the block comes
 * back through a pipe and is checked as anything from elsewhere (limen__import_valid). */
static limen_status import_contained(limen_scene *s, const char *path, unsigned flags,
                                     size_t max_bytes, limen__import **blk,
                                     limen__block *files)
{
    *blk = NULL;
    limen__load *ld = s->load;
    limen__block job = { 0 };
    uint32_t jflags = flags;
    uint64_t mb[3] = { max_bytes, ld->max_bytes, ld->read_bytes };
    uint8_t safe[2] = { ld->safe, !ld->box ? 0 : ld->box->on ? 2 : 1 };
    const char *prefix = ld->box ? ld->box->prefix : "";
    limen__block_put(&job, &jflags, sizeof jflags);
    limen__block_put(&job, mb, sizeof mb);
    limen__block_put(&job, safe, 2);
    limen__block_put(&job, prefix, strlen(prefix) + 1);
    limen__block_put(&job, path, strlen(path) + 1);
    if (job.failed) {
        limen__block_free(&job);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    }
    /* the block holds each vertex whole (64 bytes) for the moment it takes to flatten it:
     * a few times what the mesh will hold, in the host only while this call lasts */
    limen__contain_limits lim = { max_bytes, ld->cpu_left,
                                  max_bytes < SIZE_MAX / 8 ? max_bytes * 6 + (1u << 20) : 0 };
    limen__block b;
    char why[LIMEN__ERR_MAX];
    double cpu;
    int rc = limen__contain_job(import_job, &job, ld->box && ld->box->on ? ld->box->dir : -1,
                                &lim, &b, why, sizeof why, &cpu);
    limen__block_free(&job);
    ld->cpu_spent += cpu;
    ld->cpu_left = ld->cpu_left > 0 ? (ld->cpu_left > cpu ? ld->cpu_left - cpu : 1e-9) : 0;
    switch (rc) {
    case LIMEN__CONTAIN_OK:
        break;
    case LIMEN__CONTAIN_FAILED:
        return limen__fail(s, (limen_status)limen__contain_code(), "%s", why);
    case LIMEN__CONTAIN_CRASHED:
        return limen__fail(s, LIMEN_ERR_IO, "the importer crashed reading %s (%s; it may have "
                           "run out of the %.1f MiB left)", path, why, max_bytes / 1048576.0);
    case LIMEN__CONTAIN_TIME:
        return limen__fail(s, LIMEN_ERR_IO, "the importer ran out of time reading %s (%.1f s of "
                           "processor time left)", path, lim.cpu_seconds);
    case LIMEN__CONTAIN_MEMORY:
        return limen__fail(s, LIMEN_ERR_NOMEM, "the importer handed back more than the %.1f MiB "
                           "left reading %s", max_bytes / 1048576.0, path);
    default:
        return limen__fail(s, LIMEN_ERR_IO, "%s: %s", path, why);
    }
    /* the answer is one malloc'd buffer: the block in place (aligned as malloc aligns),
     * checked before anything reads it, then the files */
    limen__import *got = (limen__import *)b.data;
    limen_status st = LIMEN_OK;
    if (b.len < sizeof *got || got->size > b.len || !limen__import_valid(got, (size_t)got->size))
        st = limen__fail(s, LIMEN_ERR_IO, "the importer handed back a broken block reading %s",
                         path);
    if (!st) {
        size_t flen = b.len - (size_t)got->size;
        const char *fl = (const char *)b.data + got->size;
        if (flen && fl[flen - 1] == '\0')
            limen__block_put(files, fl, flen);
        *blk = got;     /* the buffer is the block's: free(*blk) releases it */
        return LIMEN_OK;
    }
    limen__block_free(&b);
    return st;
}

static limen_status mesh_from_block(limen_scene *s, const limen__import *blk, uint32_t only,
                                    const char *path, size_t max_bytes, limen__mesh **out);

limen_status limen__mesh_import(limen_scene *s, const char *path, unsigned flags,
                                size_t max_bytes, limen__import **blk, limen__block *files)
{
    *blk = NULL;
    *files = (limen__block){ 0 };
    /* refused from what the file declares, before the importer reads it */
    limen_status st = limen__mesh_look(s, path, max_bytes, NULL, NULL);
    if (st)
        return st;
    return limen__load_contained(s) ? import_contained(s, path, flags, max_bytes, blk, files)
                                    : import_here(s, path, flags, max_bytes, blk, files);
}

static limen_status load_file(limen_scene *s, const char *path, unsigned flags,
                              size_t max_bytes, limen__mesh **out)
{
    *out = NULL;
    limen__import *blk;
    limen__block files;
    limen_status st = limen__mesh_import(s, path, flags, max_bytes, &blk, &files);
    if (st)
        return st;
    st = mesh_from_block(s, blk, LIMEN__IMPORT_NONE, path, max_bytes, out);
    if (!st) {
        limen__mesh_keep_warnings(s, blk, path);
        (*out)->files = (char *)files.data;
        (*out)->files_len = files.len;
    } else {
        limen__block_free(&files);
    }
    uint64_t moved = blk->size;
    free(blk);
    /* the file's bytes, the import's block and the flattened copy (several times what the
     * mesh holds) are gone: after a big load their pages go back */
    limen__heap_give_back(moved);
    return st;
}

/* The block's meshes (every node's, or node only's: flatten) as a new mesh with its
 * materials' textures, refused where it would hold more than max_bytes. */
static limen_status mesh_from_block(limen_scene *s, const limen__import *blk, uint32_t only,
                                    const char *path, size_t max_bytes, limen__mesh **out)
{
    *out = NULL;
    flat fl;
    limen_status st;
    if (!(st = flatten(s, blk, only, path, &fl))) {
        limen_mesh_data d = { .positions = fl.pos, .normals = fl.nrm, .uvs = fl.uv,
                              .vertex_count = (int)fl.nv, .indices = fl.idx,
                              .triangle_count = (int)fl.nt,
                              .colors = (blk->vertex_flags & LIMEN__VERT_COLOURS) ? fl.col : NULL,
                              .part_count = (int)fl.np, .parts = fl.parts,
                              .material_count = (int)fl.np, .materials = fl.mats };
        if (!(blk->vertex_flags & LIMEN__VERT_UV0))
            d.uvs = NULL;
        st = mesh_from_arrays(s, &d, path, max_bytes, blk, only, out);
        flat_free(&fl);
    }
    if (!st && (*out)->bytes > max_bytes) {
        s->mem_wanted = (*out)->bytes;
        mesh_free(s, *out);
        *out = NULL;
        st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: needs more than the %.1f MiB allowed", path,
                         max_bytes / 1048576.0);
    }
    return st;
}

/* ------------------------------------------------------------------ API */

/* The mesh node of handle n, for a call named fn that edits it (limen__node_lookup). */
static limen_status mesh_node(limen_scene *s, limen_node n, const char *fn, limen__node **out)
{
    return limen__node_lookup(s, n, LIMEN__KIND(LIMEN_NODE_MESH), "a mesh", fn, out);
}

limen_status limen__mesh_load(limen_scene *s, limen_node n, const char *path, size_t max_bytes,
                              size_t *charged)
{
    *charged = 0;
    if (!s)
        return LIMEN_ERR_ARG;
    limen__node *node;
    limen_status found = mesh_node(s, n, "mesh_load", &node);
    if (found)
        return found;
    if (!path || !path[0])
        return limen__fail(s, LIMEN_ERR_ARG, "mesh_load: no file name");
    char key[LIMEN__FILE_KEY];
    struct stat st_key;
    limen_status st = limen__file_key(s, path, key, &st_key);
    if (st)
        return st;
    /* a node with a texture of its own never shows the file's: they are not read */
    unsigned flags = node->texture ? LIMEN__IMPORT_NO_TEXTURES : 0;
    if (flags && strlen(key) + 8 < sizeof key)
        strcat(key, "#notex");
    for (int i = 0; i < s->nmeshes; i++) {
        limen__mesh *m = s->meshes[i];
        if (strcmp(m->key, key) == 0) {
            attach(s, node, m);
            return LIMEN_OK;
        }
    }
    limen__mesh *m;
    st = load_file(s, path, flags, max_bytes, &m);
    if (st)
        return st;
    snprintf(m->key, sizeof m->key, "%s", key);
    if ((st = keep(s, m, path)))
        return st;
    attach(s, node, m);
    *charged = m->bytes;
    return LIMEN_OK;
}

limen_status limen__mesh_from_import(limen_scene *s, limen_node n, const limen__import *b,
                                     uint32_t node, const char *path, size_t max_bytes,
                                     size_t *charged)
{
    *charged = 0;
    limen__node *nd;
    limen_status found = mesh_node(s, n, "model", &nd);
    if (found)
        return found;
    limen__mesh *m;
    limen_status st = mesh_from_block(s, b, node, path, max_bytes, &m);
    if (!st)
        st = keep(s, m, path);
    if (st)
        return st;
    attach(s, nd, m);
    *charged = m->bytes;
    return LIMEN_OK;
}

limen_status limen_mesh_load(limen_scene *s, limen_node n, const char *path)
{
    size_t charged;
    return limen__mesh_load(s, n, path, SIZE_MAX, &charged);
}

limen_status limen_mesh_set_triangles(limen_scene *s, limen_node n, const limen_mesh_data *data)
{
    if (!s)
        return LIMEN_ERR_ARG;
    limen__node *node;
    limen_status found = mesh_node(s, n, "mesh_set_triangles", &node);
    if (found)
        return found;
    limen__mesh *m;
    limen_status st = mesh_from_arrays(s, data, "mesh_set_triangles", SIZE_MAX, NULL, 0, &m);
    if (!st)
        st = keep(s, m, "mesh_set_triangles");
    if (st)
        return st;
    attach(s, node, m);
    return LIMEN_OK;
}

bool limen__mesh_hierarchy_made(limen_scene *s, limen_node n)
{
    limen__node *node;
    return s && !mesh_node(s, n, "mesh_hierarchy_made", &node) && node->mesh &&
           atomic_load(&node->mesh->bvh_ready);
}

limen_status limen_mesh_set_smooth(limen_scene *s, limen_node n, int smooth)
{
    limen__node *node;
    limen_status found = mesh_node(s, n, "mesh_set_smooth", &node);
    if (found)
        return found;
    node->smooth = smooth != 0;
    return LIMEN_OK;
}

limen_status limen_mesh_get(const limen_scene *s, limen_node n, limen_mesh_info *out)
{
    /* a const reader: the status alone, no message (see limen_scene_error) */
    const limen__node *node;
    limen_status found = limen__node_lookup_const(s, n, LIMEN__KIND(LIMEN_NODE_MESH), &node);
    if (found)
        return found;
    if (!out)
        return LIMEN_ERR_ARG;
    memset(out, 0, sizeof *out);
    out->smooth = node->smooth;
    const limen__mesh *m = node->mesh;
    if (!m)
        return LIMEN_OK;
    out->vertex_count = (int)m->nverts;
    out->triangle_count = (int)m->ntris;
    out->has_normals = m->file_normals;
    out->has_uvs = m->uv != NULL;
    for (int a = 0; a < 3; a++) {
        out->lo[a] = (float)m->lo[a];
        out->hi[a] = (float)m->hi[a];
    }
    out->shared_by = m->refs;
    out->lod_count = (int)m->nlods;
    out->bytes = m->bytes;
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ warnings */

int limen_scene_warning_count(const limen_scene *s)
{
    return s ? s->nwarnings : 0;
}

const char *limen_scene_warning(const limen_scene *s, int i)
{
    return s && i >= 0 && i < s->nwarnings ? s->warnings[i] : NULL;
}

void limen_scene_clear_warnings(limen_scene *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->nwarnings; i++)
        free(s->warnings[i]);
    free(s->warnings);
    s->warnings = NULL;
    s->nwarnings = 0;
}
