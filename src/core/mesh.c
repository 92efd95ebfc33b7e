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

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/confine.h"
#include "core/contain.h"
#include "core/internal.h"
#include "core/mesh.h"
#include "core/texture.h"

#define LEAF_TRIS 4
#define MAX_TRIS (UINT32_MAX / 3u - 1u)
#define STACK_MAX 64
#define GLTF_DEPTH_MAX 256      /* nodes nested deeper overflow the importer's stack */

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

static void tri_box(const limen__mesh *m, uint32_t t, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        const float *p = &m->pos[m->idx[t * 3 + k] * 3];
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], p[a]);
            hi[a] = fmax(hi[a], p[a]);
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
        n->lo[a] = fmin(m->bvh[left].lo[a], m->bvh[right].lo[a]);
        n->hi[a] = fmax(m->bvh[left].hi[a], m->bvh[right].hi[a]);
    }
}

/* Nodes are claimed as they are made (at most 2 * triangles - 1), a left child in the slot
 * after its parent. */
bool limen__mesh_bvh(limen__mesh *m)
{
    m->bvh = malloc(sizeof *m->bvh * (size_t)(2 * m->ntris));
    m->tri_order = malloc(sizeof *m->tri_order * (size_t)m->ntris);
    double *centre = malloc(sizeof *centre * 3 * (size_t)m->ntris);
    if (!m->bvh || !m->tri_order || !centre) {
        free(centre);
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
    limen__tri_node *fit = realloc(m->bvh, sizeof *m->bvh * m->nbvh);
    if (fit)
        m->bvh = fit;
    m->bytes -= sizeof *m->bvh * (size_t)(2 * m->ntris - m->nbvh);
    return true;
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
    if (!m || !m->ntris)
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
    limen__texture_release(s, m->tex);
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    free(m->bvh);
    free(m->tri_order);
    free(m->lods);
    free(m->files);
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

/* Checks and copies arrays into a new asset. what names the source in messages. */
static limen_status mesh_from_arrays(limen_scene *s, const limen_mesh_data *d, const char *what,
                                     size_t max_bytes, limen__mesh **out)
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
    if (bytes > max_bytes)
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
    m->pos = malloc(sizeof(float) * 3 * nv);
    m->nrm = malloc(sizeof(float) * 3 * nv);
    m->uv = d->uvs ? malloc(sizeof(float) * 2 * nv) : NULL;
    m->idx = malloc(sizeof(uint32_t) * 3 * nt);
    if (!m->pos || !m->nrm || (d->uvs && !m->uv) || !m->idx) {
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
    /* a contained import's child hands the arrays back: the host builds the rest */
    bool child = s->load && s->load->inside;
    if (!child && (!limen__mesh_bvh(m) || !limen__mesh_lods_build(m))) {
        mesh_free(s, m);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", what);
    }
    m->serial = limen__next_serial();
    m->pub = (limen_mesh_geometry){ .id = m->serial, .vertex_count = (int)nv,
                                    .triangle_count = (int)nt, .positions = m->pos,
                                    .normals = m->nrm, .uvs = m->uv, .indices = m->idx,
                                    .lod_count = (int)m->nlods, .lods = m->lods };
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

/* The scene's triangles merged into one list, node transforms applied (assimp's
 * PreTransformVertices). */
static limen_status from_scene(limen_scene *s, const struct aiScene *sc, const char *path,
                               size_t max_bytes, limen__mesh **out)
{
    uint64_t nv = 0, nt = 0;
    bool normals = true, uvs = true;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        if (am->mPrimitiveTypes & (aiPrimitiveType_POINT | aiPrimitiveType_LINE))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: has points or lines (a mesh is made of "
                               "triangles)", path);
        nv += am->mNumVertices;
        nt += am->mNumFaces;
        normals = normals && am->mNormals;
        uvs = uvs && am->mTextureCoords[0];
    }
    if (nt == 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: no triangles in it", path);
    if (nt > MAX_TRIS || nv > MAX_TRIS)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: %llu triangles, more than a mesh holds", path,
                           (unsigned long long)nt);
    size_t bytes = limen__mesh_bytes(nv, nt, uvs);
    if (bytes > max_bytes)
        return limen__fail(s, LIMEN_ERR_NOMEM,
                           "%s: %llu triangles need %.1f MiB, more than the %.1f MiB allowed",
                           path, (unsigned long long)nt, bytes / 1048576.0,
                           max_bytes / 1048576.0);
    float *pos = malloc(sizeof(float) * 3 * nv), *nrm = normals ? malloc(sizeof(float) * 3 * nv)
                                                                : NULL;
    float *uv = uvs ? malloc(sizeof(float) * 2 * nv) : NULL;
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * nt);
    limen_status st = LIMEN_OK;
    if (!pos || (normals && !nrm) || (uvs && !uv) || !idx) {
        st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    uint32_t v0 = 0, t0 = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            uint32_t at = v0 + v;
            pos[at * 3] = am->mVertices[v].x;
            pos[at * 3 + 1] = am->mVertices[v].y;
            pos[at * 3 + 2] = am->mVertices[v].z;
            if (nrm) {
                nrm[at * 3] = am->mNormals[v].x;
                nrm[at * 3 + 1] = am->mNormals[v].y;
                nrm[at * 3 + 2] = am->mNormals[v].z;
            }
            if (uv) {
                uv[at * 2] = am->mTextureCoords[0][v].x;
                uv[at * 2 + 1] = am->mTextureCoords[0][v].y;
            }
        }
        for (unsigned f = 0; f < am->mNumFaces; f++) {
            const struct aiFace *face = &am->mFaces[f];
            if (face->mNumIndices != 3) {
                st = limen__fail(s, LIMEN_ERR_ARG, "%s: face %u has %u corners (a mesh is made "
                                 "of triangles)", path, t0 + f, face->mNumIndices);
                goto done;
            }
            for (int k = 0; k < 3; k++)
                idx[(t0 + f) * 3 + k] = v0 + face->mIndices[k];
        }
        v0 += am->mNumVertices;
        t0 += am->mNumFaces;
    }
    limen_mesh_data d = { .positions = pos, .normals = nrm, .uvs = uv, .vertex_count = (int)nv,
                          .indices = idx, .triangle_count = (int)nt };
    st = mesh_from_arrays(s, &d, path, max_bytes, out);
done:
    free(pos);
    free(nrm);
    free(uv);
    free(idx);
    return st;
}

/* The name of the first material's base-colour (or diffuse) texture, or "". */
static void base_texture(const struct aiScene *sc, char *out, size_t size)
{
    out[0] = '\0';
    for (unsigned i = 0; i < sc->mNumMaterials; i++) {
        struct aiString str;
        const struct aiMaterial *mat = sc->mMaterials[i];
        if (aiGetMaterialTexture(mat, aiTextureType_BASE_COLOR, 0, &str, NULL, NULL, NULL, NULL,
                                 NULL, NULL) == aiReturn_SUCCESS ||
            aiGetMaterialTexture(mat, aiTextureType_DIFFUSE, 0, &str, NULL, NULL, NULL, NULL,
                                 NULL, NULL) == aiReturn_SUCCESS) {
            size_t len = strnlen(str.data, size - 1);
            memcpy(out, str.data, len);
            out[len] = '\0';
            return;
        }
    }
}

/* The file's base-colour texture onto m (which must have texture coordinates): embedded
 * ("*N", a PNG or JPEG inside a .glb), or a file beside the mesh file, never above it (no
 * absolute path, no ".."). */
static limen_status file_texture(limen_scene *s, const struct aiScene *sc, const char *path,
                                 size_t max_bytes, size_t *charged, limen__mesh *m)
{
    char name[512];
    *charged = 0;
    base_texture(sc, name, sizeof name);
    if (!name[0] || !m->uv)
        return LIMEN_OK;
    if (name[0] == '*') {
        unsigned k = (unsigned)atoi(name + 1);
        const struct aiTexture *at = k < sc->mNumTextures ? sc->mTextures[k] : NULL;
        if (!at || at->mHeight != 0)
            return limen__fail(s, LIMEN_ERR_IO, "%s: embedded texture %s is missing or not "
                               "PNG/JPEG", path, name);
        char what[600];
        snprintf(what, sizeof what, "%.500s: texture %s", path, name);
        limen_status st = limen__texture_decode(s, (const unsigned char *)at->pcData,
                                                at->mWidth, what, &m->tex);
        if (!st && m->tex->bytes > max_bytes) {
            limen__texture_release(s, m->tex);
            m->tex = NULL;
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: its texture needs more memory than "
                               "allowed", path);
        }
        if (!st)
            *charged = m->tex->bytes;
        return st;
    }
    for (char *c = name; *c; c++)
        if (*c == '\\')
            *c = '/';
    if (name[0] == '/' || strstr(name, ".."))
        return limen__fail(s, LIMEN_ERR_IO, "%s: its texture '%s' is not beside it", path, name);
    const char *slash = strrchr(path, '/');
    char full[1200];
    snprintf(full, sizeof full, "%.*s%s", slash ? (int)(slash - path + 1) : 0, path, name);
    return limen__texture_load(s, full, max_bytes, charged, &m->tex);
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

/* ------------------------------------------------------------------ what is read */

/* The file name's extension, lower case, into ext ("" if none). */
static void extension(const char *path, char *ext, size_t size)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    ext[0] = '\0';
    if (!dot || (slash && dot < slash))
        return;
    size_t i = 0;
    for (dot++; *dot && i + 1 < size; dot++)
        ext[i++] = (char)tolower((unsigned char)*dot);
    ext[i] = '\0';
}

/* Formats a safe scene may load, decided by the extension and the content agreeing: those
 * fuzzed (make fuzz). Writes why and returns false for anything else. */
static bool allowed_format(const char *path, const unsigned char *head, size_t n,
                           uint64_t size, char *why, size_t why_size)
{
    char ext[8];
    extension(path, ext, sizeof ext);
    size_t i = 0;
    while (i < n && isspace(head[i]))
        i++;
    bool ok = false;
    if (strcmp(ext, "gltf") == 0)
        ok = i < n && head[i] == '{';
    else if (strcmp(ext, "glb") == 0)
        ok = n >= 4 && memcmp(head, "glTF", 4) == 0;
    else if (strcmp(ext, "obj") == 0)
        ok = !memchr(head, '\0', n);
    else if (strcmp(ext, "ply") == 0)
        ok = n >= 4 && memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r');
    else if (strcmp(ext, "stl") == 0) {
        uint32_t count = 0;
        if (n >= 84)
            memcpy(&count, head + 80, 4);
        ok = (n >= 5 && memcmp(head, "solid", 5) == 0 && !memchr(head, '\0', n)) ||
             (n >= 84 && size == 84 + 50 * (uint64_t)count);
    } else {
        snprintf(why, why_size, "a safe scene loads glTF (.gltf, .glb), OBJ (.obj, .mtl), PLY "
                 "(.ply) and STL (.stl) meshes, not .%s files", ext[0] ? ext : "(none)");
        return false;
    }
    if (!ok)
        snprintf(why, why_size, "its content is not a %s file (a safe scene loads glTF, OBJ, "
                 "PLY and STL meshes, each in a file of its own extension)", ext);
    return ok;
}

/* Counts a header declares, checked against the file's size before the importer sees it:
 * every element a format's header declares takes at least a byte of the file (a vertex or
 * face), so a few bytes cannot declare gigabytes. Writes why and returns
 * false if the file is refused. */
static bool header_ok(const unsigned char *data, size_t size, char *why, size_t why_size)
{
    char head[4096 + 1];
    size_t n = size < sizeof head - 1 ? size : sizeof head - 1;
    memcpy(head, data, n);
    head[n] = '\0';
    for (size_t i = 0; i < n; i++)
        if (head[i] == '\0')
            head[i] = ' ';
    uint64_t declared = 0;
    if (n >= 3 && memcmp(head, "ply", 3) == 0) {
        /* assimp 5.2 loops for ever on a header that never ends or ends "end_headerX" */
        char *end = strstr(head, "end_header");
        if (!end || (end[10] != '\n' && end[10] != '\r')) {
            snprintf(why, why_size, "a PLY header with no end_header line in its first 4 KiB");
            return false;
        }
        *end = '\0';
        /* words apart by any white space ("element\tvertex 9" is a declaration too) */
        for (char *line = head; line && *line;) {
            char *next = strpbrk(line, "\r\n");
            if (next)
                *next++ = '\0';
            char word[16], name[32];
            unsigned long long count = 0;
            if (sscanf(line, "%15s %31s %llu", word, name, &count) == 3 &&
                strcmp(word, "element") == 0)
                declared += count > size ? size + 1 : count;
            line = next;
        }
    } else if (n >= 3 && memcmp(head, "OFF", 3) == 0) {
        unsigned long long nv = 0, nf = 0;
        char *p = head + 3;
        while (*p && *p != '\n')
            p++;
        /* OFF, then (after comments) the vertex and face counts */
        while (*p) {
            while (isspace((unsigned char)*p))
                p++;
            if (*p != '#')
                break;
            while (*p && *p != '\n')
                p++;
        }
        if (sscanf(head + 3, "%llu %llu", &nv, &nf) == 2 || sscanf(p, "%llu %llu", &nv, &nf) == 2)
            declared = (nv > size ? size + 1 : nv) + (nf > size ? size + 1 : nf);
    }
    if (declared > size) {
        snprintf(why, why_size, "its header declares more elements than the file has bytes "
                 "(%llu)", (unsigned long long)size);
        return false;
    }
    return true;
}

/* ------------------------------------------------------------------ importing */

#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | \
                      aiProcess_PreTransformVertices | aiProcess_SortByPType | \
                      aiProcess_ValidateDataStructure)

/* Imports path in this process: geometry and texture into *out, the files read into files. */
static limen_status import_here(limen_scene *s, const char *path, size_t max_bytes,
                                limen__mesh **out, limen__block *files)
{
    *out = NULL;
    io_ctx c = { .io = { io_open, io_close, NULL }, .s = s };
    c.io.UserData = (aiUserData)&c;
    /* assimp's C interface keeps the last error in one string for the whole process: an
     * import and the reading of its error go together, one thread at a time, so that
     * scenes on different threads stay independent (limen.h, THREADS) */
    static pthread_mutex_t importing = PTHREAD_MUTEX_INITIALIZER;
    /* a contained import's child has one thread, and the lock as some other thread of the
     * host may have held it when the child was forked: it takes none */
    bool lock = !(s->load && s->load->inside);
    char err[301] = "";
    if (lock)
        pthread_mutex_lock(&importing);
    const struct aiScene *sc = aiImportFileEx(path, IMPORT_FLAGS, &c.io);
    if (!sc) {
        const char *e = aiGetErrorString();
        snprintf(err, sizeof err, "%s", e ? e : "");
    }
    if (lock)
        pthread_mutex_unlock(&importing);
    limen_status st = LIMEN_OK;
    if (!sc) {
        size_t pl = strlen(path);
        if (c.why[0] && strncmp(c.why, path, pl) == 0 && c.why[pl] == ':')
            st = limen__fail(s, LIMEN_ERR_IO, "%s", c.why);
        else if (c.why[0])
            st = limen__fail(s, LIMEN_ERR_IO, "%s: %s", path, c.why);
        else if (strstr(err, "bad_alloc"))
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: the importer ran out of memory reading it "
                             "(%.1f MiB left)", path, max_bytes / 1048576.0);
        else
            st = limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as a mesh: %s", path,
                             err[0] ? err : "unknown format");
        limen__block_free(&c.files);
        return st;
    }
    if (sc->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        st = limen__fail(s, LIMEN_ERR_IO, "%s: incomplete (no meshes in it)", path);
    else
        st = from_scene(s, sc, path, max_bytes, out);
    size_t tex_bytes = 0;
    if (!st && (st = file_texture(s, sc, path, max_bytes - (*out)->bytes, &tex_bytes, *out))) {
        mesh_free(s, *out);
        *out = NULL;
    }
    if (!st)
        (*out)->bytes += tex_bytes;
    aiReleaseImport(sc);
    if (st)
        limen__block_free(&c.files);
    else
        *files = c.files;
    return st;
}

typedef struct importing {
    limen_scene *s;
    const char *path;
    size_t max_bytes;
} importing;

static void put_string(limen__block *b, const char *str, size_t len)
{
    uint32_t n = (uint32_t)len;
    limen__block_put(b, &n, sizeof n);
    limen__block_put(b, str, len);
}

/* In the child: the import, handed back as [counts][flags][arrays][texture][files]. */
static int import_child(void *arg, limen__block *out, char *why, size_t why_size)
{
    importing *im = arg;
    limen_scene *s = im->s;
    s->load->inside = true;
    limen__mesh *m;
    limen__block files = { 0 };
    limen_status st = import_here(s, im->path, im->max_bytes, &m, &files);
    if (st) {
        snprintf(why, why_size, "%s", s->err);
        return (int)st;
    }
    uint32_t head[2] = { m->nverts, m->ntris };
    uint8_t flags = (m->file_normals ? 1 : 0) | (m->uv ? 2 : 0) | (m->tex ? 4 : 0);
    limen__block_put(out, head, sizeof head);
    limen__block_put(out, &flags, 1);
    limen__block_put(out, m->pos, sizeof(float) * 3 * m->nverts);
    if (m->file_normals)
        limen__block_put(out, m->nrm, sizeof(float) * 3 * m->nverts);
    if (m->uv)
        limen__block_put(out, m->uv, sizeof(float) * 2 * m->nverts);
    limen__block_put(out, m->idx, sizeof(uint32_t) * 3 * m->ntris);
    if (m->tex) {
        const limen__texture *t = m->tex;
        put_string(out, t->key, strlen(t->key));
        put_string(out, t->name, strlen(t->name));
        int32_t wh[2] = { t->w, t->h };
        limen__block_put(out, wh, sizeof wh);
        limen__block_put(out, t->rgb, (size_t)t->w * (size_t)t->h * 3);
    }
    put_string(out, (const char *)files.data, files.len);
    return 0;
}

static const char *get_string(limen__block *b, char *out, size_t size)
{
    uint32_t n;
    const char *p;
    if (!limen__block_get(b, &n, sizeof n) || n >= size || !(p = limen__block_take(b, n)))
        return NULL;
    memcpy(out, p, n);
    out[n] = '\0';
    return out;
}

/* The child's answer into *out, checked as any arrays are. */
static limen_status unpack(limen_scene *s, limen__block *b, const char *path, size_t max_bytes,
                           limen__mesh **out)
{
    uint32_t head[2];
    uint8_t flags = 0;
    const void *pos = NULL, *nrm = NULL, *uv = NULL, *idx = NULL;
    bool ok = limen__block_get(b, head, sizeof head) && limen__block_get(b, &flags, 1) &&
              head[0] <= MAX_TRIS && head[1] <= MAX_TRIS &&
              (pos = limen__block_take(b, sizeof(float) * 3 * (size_t)head[0])) &&
              (!(flags & 1) || (nrm = limen__block_take(b, sizeof(float) * 3 * (size_t)head[0]))) &&
              (!(flags & 2) || (uv = limen__block_take(b, sizeof(float) * 2 * (size_t)head[0]))) &&
              (idx = limen__block_take(b, sizeof(uint32_t) * 3 * (size_t)head[1]));
    if (!ok)
        return limen__fail(s, LIMEN_ERR_IO, "the importer handed back a broken answer reading %s",
                           path);
    /* the block's bytes are not aligned for floats: copies */
    size_t nv = head[0], nt = head[1];
    float *p = malloc(sizeof(float) * 3 * nv + 1), *n = nrm ? malloc(sizeof(float) * 3 * nv) : NULL;
    float *u = uv ? malloc(sizeof(float) * 2 * nv) : NULL;
    uint32_t *ix = malloc(sizeof(uint32_t) * 3 * nt + 1);
    limen_status st = LIMEN_OK;
    if (!p || !ix || (nrm && !n) || (uv && !u)) {
        st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    memcpy(p, pos, sizeof(float) * 3 * nv);
    memcpy(ix, idx, sizeof(uint32_t) * 3 * nt);
    if (n)
        memcpy(n, nrm, sizeof(float) * 3 * nv);
    if (u)
        memcpy(u, uv, sizeof(float) * 2 * nv);
    limen_mesh_data d = { .positions = p, .normals = n, .uvs = u, .vertex_count = (int)nv,
                          .indices = ix, .triangle_count = (int)nt };
    if ((st = mesh_from_arrays(s, &d, path, max_bytes, out)))
        goto done;
    limen__mesh *m = *out;
    if (flags & 4) {
        char key[LIMEN__FILE_KEY], name[512];
        int32_t wh[2];
        const unsigned char *rgb = NULL;
        unsigned char *copy = NULL;
        if (get_string(b, key, sizeof key) && get_string(b, name, sizeof name) &&
            limen__block_get(b, wh, sizeof wh) && wh[0] > 0 && wh[1] > 0 && wh[0] <= 16384 &&
            wh[1] <= 16384)
            rgb = limen__block_take(b, (size_t)wh[0] * (size_t)wh[1] * 3);
        if (rgb && (copy = malloc((size_t)wh[0] * (size_t)wh[1] * 3)))
            memcpy(copy, rgb, (size_t)wh[0] * (size_t)wh[1] * 3);
        size_t charged = 0;
        st = !rgb ? limen__fail(s, LIMEN_ERR_IO, "the importer handed back a broken texture "
                                "reading %s", path)
             : !copy ? limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path)
             : limen__texture_adopt(s, key, name, copy, wh[0], wh[1], &charged, &m->tex);
        if (!st && charged > max_bytes - (m->bytes < max_bytes ? m->bytes : max_bytes))
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: its texture needs more memory than "
                             "allowed", path);
        m->bytes += charged;
    }
    uint32_t flen;
    const char *fl;
    if (!st && limen__block_get(b, &flen, sizeof flen) && (fl = limen__block_take(b, flen)) &&
        flen && fl[flen - 1] == '\0' && (m->files = malloc(flen))) {
        memcpy(m->files, fl, flen);
        m->files_len = flen;
    }
    if (st) {
        mesh_free(s, m);
        *out = NULL;
    }
done:
    free(p);
    free(n);
    free(u);
    free(ix);
    return st;
}

/* Imports path in a child under what the script has left (core/contain.c). */
static limen_status import_contained(limen_scene *s, const char *path, size_t max_bytes,
                                     limen__mesh **out)
{
    limen__load *ld = s->load;
    importing im = { s, path, max_bytes };
    limen__contain_limits lim = { max_bytes, ld->cpu_left };
    limen__block b;
    char why[LIMEN__ERR_MAX];
    double cpu;
    int rc = limen__contain_run(import_child, &im, &lim, &b, why, sizeof why, &cpu);
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
    limen_status st = unpack(s, &b, path, max_bytes, out);
    limen__block_free(&b);
    return st;
}

static limen_status load_file(limen_scene *s, const char *path, size_t max_bytes,
                              limen__mesh **out)
{
    *out = NULL;
    unsigned char *data;
    size_t len;
    struct stat st_file;
    limen_status st = limen__file_read(s, path, &data, &len, &st_file);
    if (st)
        return st;
    char why[300] = "";
    bool ok = (!s->load || !s->load->safe ||
               allowed_format(path, data, len < 4096 ? len : 4096, len, why, sizeof why)) &&
              header_ok(data, len, why, sizeof why);
    /* glTF: what its nodes place, before the importer copies a mesh into each of them */
    uint64_t gv = 0, gt = 0;
    int depth = 0;
    size_t i = 0;
    while (i < len && isspace(data[i]))
        i++;
    bool gltf = ok && ((i < len && data[i] == '{') || (len >= 4 && memcmp(data, "glTF", 4) == 0));
    if (gltf && limen__gltf_cost(data, len, max_bytes, &gv, &gt, &depth)) {
        size_t need = limen__mesh_bytes(gv, gt, true);
        if (depth > GLTF_DEPTH_MAX) {
            ok = false;
            snprintf(why, sizeof why, "its nodes nest %s%d deep (%d at most)",
                     depth == INT32_MAX ? "in a cycle, endlessly " : "",
                     depth == INT32_MAX ? 0 : depth, GLTF_DEPTH_MAX);
            if (depth == INT32_MAX)
                snprintf(why, sizeof why, "its nodes form a cycle");
        } else if (need > max_bytes) {
            free(data);
            if (s->load)
                s->load->read_bytes -= len;
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: its nodes place %llu triangles, which "
                               "need %.1f MiB, more than the %.1f MiB allowed", path,
                               (unsigned long long)gt, need / 1048576.0, max_bytes / 1048576.0);
        }
    }
    free(data);
    if (s->load)
        s->load->read_bytes -= len;
    if (!ok)
        return limen__fail(s, LIMEN_ERR_IO, "%s: %s", path, why);
    /* the importer holds at least the file's bytes while it reads */
    if ((uint64_t)len > max_bytes)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: a file of %.1f MiB, more than the %.1f MiB "
                           "allowed", path, len / 1048576.0, max_bytes / 1048576.0);
    if (limen__load_contained(s))
        return import_contained(s, path, max_bytes, out);
    limen__block files = { 0 };
    if ((st = import_here(s, path, max_bytes, out, &files)))
        return st;
    (*out)->files = (char *)files.data;
    (*out)->files_len = files.len;
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ API */

static limen__node *mesh_node(limen_scene *s, limen_node n, const char *fn)
{
    limen__node *node = limen__node_get(s, n);
    if (!node) {
        limen__fail(s, LIMEN_ERR_HANDLE, "%s: %s node handle", fn,
                    n.id ? "stale or foreign" : "null");
        return NULL;
    }
    if (node->kind != LIMEN_NODE_MESH) {
        limen__fail(s, LIMEN_ERR_HANDLE, "%s: '%s' is not a mesh", fn, limen__node_title(node));
        return NULL;
    }
    return node;
}

limen_status limen__mesh_load(limen_scene *s, limen_node n, const char *path, size_t max_bytes,
                              size_t *charged)
{
    *charged = 0;
    if (!s)
        return LIMEN_ERR_ARG;
    limen__node *node = mesh_node(s, n, "mesh_load");
    if (!node)
        return LIMEN_ERR_HANDLE;
    if (!path || !path[0])
        return limen__fail(s, LIMEN_ERR_ARG, "mesh_load: no file name");
    char key[LIMEN__FILE_KEY];
    struct stat st_key;
    limen_status st = limen__file_key(s, path, key, &st_key);
    if (st)
        return st;
    for (int i = 0; i < s->nmeshes; i++) {
        limen__mesh *m = s->meshes[i];
        if (strcmp(m->key, key) == 0) {
            attach(s, node, m);
            return LIMEN_OK;
        }
    }
    limen__mesh *m;
    st = load_file(s, path, max_bytes, &m);
    if (st)
        return st;
    snprintf(m->key, sizeof m->key, "%s", key);
    if ((st = keep(s, m, path)))
        return st;
    attach(s, node, m);
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
    limen__node *node = mesh_node(s, n, "mesh_set_triangles");
    if (!node)
        return LIMEN_ERR_HANDLE;
    limen__mesh *m;
    limen_status st = mesh_from_arrays(s, data, "mesh_set_triangles", SIZE_MAX, &m);
    if (!st)
        st = keep(s, m, "mesh_set_triangles");
    if (st)
        return st;
    attach(s, node, m);
    return LIMEN_OK;
}

limen_status limen_mesh_set_smooth(limen_scene *s, limen_node n, int smooth)
{
    limen__node *node = mesh_node(s, n, "mesh_set_smooth");
    if (!node)
        return s ? LIMEN_ERR_HANDLE : LIMEN_ERR_ARG;
    node->smooth = smooth != 0;
    return LIMEN_OK;
}

limen_status limen_mesh_get(const limen_scene *s, limen_node n, limen_mesh_info *out)
{
    limen__node *node = mesh_node((limen_scene *)s, n, "mesh_get");
    if (!node)
        return s ? LIMEN_ERR_HANDLE : LIMEN_ERR_ARG;
    if (!out)
        return limen__fail((limen_scene *)s, LIMEN_ERR_ARG, "mesh_get: NULL output");
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
