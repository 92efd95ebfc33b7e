/* model.c - a model file as a scene: its node hierarchy becomes limen nodes under a group
 * (names, local matrices, each node's meshes as one mesh node), its cameras and point lights
 * when asked, and nodes authored as mirrors and portals (glTF extras, as Blender exports an
 * object's custom properties: "limen": {"mirror": {...}} or {"portal": {...}}; or a name
 * ending in "-mirror") become surfaces whose rectangle is fitted to the node's flat mesh.
 *
 * Two steps: the file is read into a description (`model`: nodes with their triangles in
 * their own frames, surfaces, cameras, lights), from assimp's aiScene here (from_assimp);
 * then the description is built into the scene (build). Only the first step knows where the
 * model came from. Building is all or nothing: on failure every node made is destroyed. */
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/model.h"

#define MAX_NODES 100000        /* a file's nodes at most */
#define MAX_SURFACE_TRIS 256    /* a mirror's or portal's polygon, in triangles at most */
#define FLAT_EPS 1e-4           /* off the plane, relative to the polygon's size */

enum { SURF_NONE, SURF_MIRROR, SURF_PORTAL };

/* What a node asks to be as a surface. */
typedef struct msurf {
    int kind;                   /* SURF_* */
    int max_depth;              /* -1: the default */
    bool has_tint;
    float tint[3];
    char partner[LIMEN__NAME_MAX];
} msurf;

typedef struct mnode {
    char name[LIMEN__NAME_MAX];
    int parent;                 /* index, -1 for a top node */
    float local[16];            /* column-major, relative to the parent */
    float *pos, *nrm, *uv;      /* its meshes' vertices together, in its own frame */
    uint32_t *idx;
    int nverts, ntris;
    bool has_nrm, has_uv, has_color;
    float color[3];             /* its first mesh's material's diffuse colour */
    msurf surf;
} mnode;

typedef struct mcamera {
    int node;
    float look[3], up[3], fovy, znear, zfar;
} mcamera;

typedef struct mlight {
    int node;
    float pos[3], color[3];
} mlight;

typedef struct model {
    mnode *nodes;
    int n;
    mcamera *cams;
    int ncams;
    mlight *lights;
    int nlights;
} model;

static void model_free(model *m)
{
    for (int i = 0; i < m->n; i++) {
        free(m->nodes[i].pos);
        free(m->nodes[i].nrm);
        free(m->nodes[i].uv);
        free(m->nodes[i].idx);
    }
    free(m->nodes);
    free(m->cams);
    free(m->lights);
    memset(m, 0, sizeof *m);
}

/* ------------------------------------------------------------------ extras (assimp) */

static bool utf8_ok(const char *p)
{
    const unsigned char *s = (const unsigned char *)p;
    while (*s) {
        int n = *s < 0x80 ? 0 : (*s & 0xe0) == 0xc0 ? 1 : (*s & 0xf0) == 0xe0 ? 2
                : (*s & 0xf8) == 0xf0 ? 3 : -1;
        if (n < 0)
            return false;
        s++;
        for (int k = 0; k < n; k++, s++)
            if ((*s & 0xc0) != 0x80)
                return false;
    }
    return true;
}

/* A name as limen keeps it (LIMEN__NAME_MAX - 1 bytes at most, cut between characters);
 * "" for one that is not UTF-8. */
static void copy_name(char out[LIMEN__NAME_MAX], const char *name)
{
    out[0] = '\0';
    if (!utf8_ok(name))
        return;
    size_t n = strlen(name);
    if (n > LIMEN__NAME_MAX - 1) {
        n = LIMEN__NAME_MAX - 1;
        while (n > 0 && ((unsigned char)name[n] & 0xc0) == 0x80)
            n--;
    }
    memcpy(out, name, n);
    out[n] = '\0';
}

static bool meta_number(const struct aiMetadataEntry *e, double *out)
{
    switch (e->mType) {
    case AI_BOOL: *out = *(const bool *)e->mData; return true;
    case AI_INT32: *out = *(const int32_t *)e->mData; return true;
    case AI_UINT64: *out = (double)*(const uint64_t *)e->mData; return true;
    case AI_FLOAT: *out = *(const float *)e->mData; return true;
    case AI_DOUBLE: *out = *(const double *)e->mData; return true;
    default: return false;
    }
}

static const struct aiMetadataEntry *meta_get(const struct aiMetadata *md, const char *key)
{
    for (unsigned i = 0; md && i < md->mNumProperties; i++)
        if (strcmp(md->mKeys[i].data, key) == 0)
            return &md->mValues[i];
    return NULL;
}

static const struct aiMetadata *meta_object(const struct aiMetadataEntry *e)
{
    return e && e->mType == AI_AIMETADATA ? e->mData : NULL;
}

/* The node's "limen" extras into *sf; false with a message in why where they are not as
 * docs say. */
static bool read_extras(const struct aiMetadata *md, msurf *sf, char *why, size_t size)
{
    const struct aiMetadataEntry *le = meta_get(md, "limen");
    if (!le)
        return true;
    const struct aiMetadata *l = meta_object(le);
    if (!l) {
        snprintf(why, size, "its extras' \"limen\" is not an object");
        return false;
    }
    const struct aiMetadata *mir = meta_object(meta_get(l, "mirror"));
    const struct aiMetadata *por = meta_object(meta_get(l, "portal"));
    if ((mir && por) || (!mir && !por)) {
        snprintf(why, size, "its extras' \"limen\" must hold one object, \"mirror\" or "
                 "\"portal\"");
        return false;
    }
    const struct aiMetadata *o = mir ? mir : por;
    sf->kind = mir ? SURF_MIRROR : SURF_PORTAL;
    for (unsigned i = 0; i < o->mNumProperties; i++) {
        const char *k = o->mKeys[i].data;
        const struct aiMetadataEntry *e = &o->mValues[i];
        double v;
        if (strcmp(k, "max_depth") == 0) {
            if (!meta_number(e, &v) || !(v >= 0 && v <= 255) || v != floor(v)) {
                snprintf(why, size, "max_depth must be an integer from 0 to 255");
                return false;
            }
            sf->max_depth = (int)v;
        } else if (strcmp(k, "tint") == 0 && mir) {
            const struct aiMetadata *t = meta_object(e);
            bool ok = t && t->mNumProperties == 3;
            for (unsigned c = 0; ok && c < 3; c++)
                ok = meta_number(&t->mValues[c], &v) && v >= 0 && v <= 1 &&
                     (sf->tint[c] = (float)v, true);
            if (!ok) {
                snprintf(why, size, "tint must be [r, g, b], each from 0 to 1");
                return false;
            }
            sf->has_tint = true;
        } else if (strcmp(k, "partner") == 0 && por) {
            if (e->mType != AI_AISTRING || !((const struct aiString *)e->mData)->length) {
                snprintf(why, size, "partner must be a node's name");
                return false;
            }
            copy_name(sf->partner, ((const struct aiString *)e->mData)->data);
        } else {
            snprintf(why, size, "unknown %s field \"%.40s\"", mir ? "mirror" : "portal", k);
            return false;
        }
    }
    if (por && !sf->partner[0]) {
        snprintf(why, size, "a portal needs \"partner\": the name of the other node");
        return false;
    }
    return true;
}

/* ------------------------------------------------------------------ from assimp */

/* The triangles of node an's meshes into node mn (in its own frame). */
static bool node_meshes(const struct aiScene *sc, const struct aiNode *an, mnode *mn)
{
    size_t nv = 0, nt = 0;
    bool all_nrm = true, any_uv = false;
    for (unsigned k = 0; k < an->mNumMeshes; k++) {
        if (an->mMeshes[k] >= sc->mNumMeshes)
            continue;
        const struct aiMesh *m = sc->mMeshes[an->mMeshes[k]];
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        nv += m->mNumVertices;
        for (unsigned f = 0; f < m->mNumFaces; f++)
            nt += m->mFaces[f].mNumIndices == 3;
        all_nrm &= m->mNormals != NULL;
        any_uv |= m->mTextureCoords[0] != NULL;
    }
    if (!nt)
        return true;
    if (nv > INT32_MAX / 4 || nt > INT32_MAX / 4)
        return false;
    mn->pos = malloc(sizeof(float) * 3 * nv);
    mn->nrm = all_nrm ? malloc(sizeof(float) * 3 * nv) : NULL;
    mn->uv = any_uv ? calloc(nv * 2, sizeof(float)) : NULL;
    mn->idx = malloc(sizeof(uint32_t) * 3 * nt);
    if (!mn->pos || (all_nrm && !mn->nrm) || (any_uv && !mn->uv) || !mn->idx)
        return false;
    mn->has_nrm = all_nrm;
    mn->has_uv = any_uv;
    size_t v0 = 0, t = 0;
    for (unsigned k = 0; k < an->mNumMeshes; k++) {
        if (an->mMeshes[k] >= sc->mNumMeshes)
            continue;
        const struct aiMesh *m = sc->mMeshes[an->mMeshes[k]];
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        if (!mn->has_color && m->mMaterialIndex < sc->mNumMaterials) {
            struct aiColor4D c;
            if (aiGetMaterialColor(sc->mMaterials[m->mMaterialIndex], AI_MATKEY_COLOR_DIFFUSE,
                                   &c) == aiReturn_SUCCESS) {
                const float rgb[3] = { c.r, c.g, c.b };
                for (int i = 0; i < 3; i++)
                    mn->color[i] = isfinite(rgb[i]) ? fminf(1, fmaxf(0, rgb[i])) : 1;
                mn->has_color = true;
            }
        }
        for (unsigned i = 0; i < m->mNumVertices; i++) {
            memcpy(&mn->pos[(v0 + i) * 3], &m->mVertices[i], sizeof(float) * 3);
            if (mn->nrm)
                memcpy(&mn->nrm[(v0 + i) * 3], &m->mNormals[i], sizeof(float) * 3);
            if (mn->uv && m->mTextureCoords[0]) {
                mn->uv[(v0 + i) * 2] = m->mTextureCoords[0][i].x;
                mn->uv[(v0 + i) * 2 + 1] = m->mTextureCoords[0][i].y;
            }
        }
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            if (m->mFaces[f].mNumIndices != 3)
                continue;
            for (int c = 0; c < 3; c++)
                mn->idx[t * 3 + c] = (uint32_t)(v0 + m->mFaces[f].mIndices[c]);
            t++;
        }
        v0 += m->mNumVertices;
    }
    mn->nverts = (int)nv;
    mn->ntris = (int)t;
    return true;
}

static bool identity(const struct aiMatrix4x4 *a)
{
    const float *f = &a->a1;
    for (int i = 0; i < 16; i++)
        if (f[i] != (i % 5 == 0 ? 1.0f : 0.0f))
            return false;
    return true;
}

/* Appends node an (and below it) with parent index `parent`, depth first. */
static limen_status add_nodes(limen_scene *s, const char *path, const struct aiScene *sc,
                              const struct aiNode *an, int parent, int depth, model *m,
                              int *cap)
{
    if (depth > 1000 || m->n >= MAX_NODES)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: more than %d nodes, or nested deeper than "
                           "1000", path, MAX_NODES);
    if (m->n == *cap) {
        int nc = *cap ? *cap * 2 : 64;
        mnode *p = realloc(m->nodes, sizeof *p * (size_t)nc);
        if (!p)
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
        m->nodes = p;
        *cap = nc;
    }
    int me = m->n++;
    mnode *mn = &m->nodes[me];
    memset(mn, 0, sizeof *mn);
    mn->parent = parent;
    mn->surf.max_depth = -1;
    copy_name(mn->name, an->mName.data);
    /* assimp's rows into limen's columns */
    const float *r = &an->mTransformation.a1;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            mn->local[j * 4 + i] = r[i * 4 + j];
    for (int i = 0; i < 16; i++)
        if (!isfinite(mn->local[i]))
            return limen__fail(s, LIMEN_ERR_ARG, "%s: node '%s': its matrix is not finite",
                               path, mn->name);
    if (!node_meshes(sc, an, mn))
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: node '%s': out of memory for its meshes",
                           path, mn->name);
    char why[160] = "";
    if (!read_extras(an->mMetaData, &mn->surf, why, sizeof why))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: node '%s': %s", path, mn->name, why);
    size_t len = strlen(mn->name);
    if (mn->surf.kind == SURF_NONE && len >= 7 && strcmp(mn->name + len - 7, "-mirror") == 0)
        mn->surf.kind = SURF_MIRROR;
    for (unsigned c = 0; c < an->mNumChildren; c++) {
        limen_status st = add_nodes(s, path, sc, an->mChildren[c], me, depth + 1, m, cap);
        if (st)
            return st;
    }
    return LIMEN_OK;
}

static int node_named(const model *m, const char *name)
{
    for (int i = 0; name[0] && i < m->n; i++)
        if (strcmp(m->nodes[i].name, name) == 0)
            return i;
    return -1;
}

static limen_status cameras_lights(limen_scene *s, const char *path, const struct aiScene *sc,
                                   model *m)
{
    m->cams = calloc(sc->mNumCameras + 1, sizeof *m->cams);
    m->lights = calloc(sc->mNumLights + 1, sizeof *m->lights);
    if (!m->cams || !m->lights)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    for (unsigned i = 0; i < sc->mNumCameras; i++) {
        const struct aiCamera *c = sc->mCameras[i];
        mcamera *mc = &m->cams[m->ncams];
        if ((mc->node = node_named(m, c->mName.data)) < 0)
            continue;
        memcpy(mc->look, &c->mLookAt, sizeof mc->look);
        memcpy(mc->up, &c->mUp, sizeof mc->up);
        /* assimp gives the horizontal field of view as the vertical one times the aspect */
        mc->fovy = c->mAspect > 0 ? c->mHorizontalFOV / c->mAspect : c->mHorizontalFOV;
        mc->znear = c->mClipPlaneNear;
        mc->zfar = c->mClipPlaneFar;
        m->ncams++;
    }
    for (unsigned i = 0; i < sc->mNumLights; i++) {
        const struct aiLight *l = sc->mLights[i];
        mlight *ml = &m->lights[m->nlights];
        if (l->mType != aiLightSource_POINT || (ml->node = node_named(m, l->mName.data)) < 0)
            continue;
        memcpy(ml->pos, &l->mPosition, sizeof ml->pos);
        ml->color[0] = l->mColorDiffuse.r;
        ml->color[1] = l->mColorDiffuse.g;
        ml->color[2] = l->mColorDiffuse.b;
        m->nlights++;
    }
    return LIMEN_OK;
}

static limen_status from_assimp(limen_scene *s, const char *path, const struct aiScene *sc,
                                model *m)
{
    memset(m, 0, sizeof *m);
    int cap = 0;
    const struct aiNode *root = sc->mRootNode;
    if (!root)
        return limen__fail(s, LIMEN_ERR_IO, "%s: no nodes in it", path);
    limen_status st = LIMEN_OK;
    /* assimp's own root above a file's several top nodes is not one of the file's */
    if (root->mNumMeshes == 0 && identity(&root->mTransformation) &&
        strcmp(root->mName.data, "ROOT") == 0) {
        for (unsigned c = 0; !st && c < root->mNumChildren; c++)
            st = add_nodes(s, path, sc, root->mChildren[c], -1, 0, m, &cap);
    } else {
        st = add_nodes(s, path, sc, root, -1, 0, m, &cap);
    }
    if (!st)
        st = cameras_lights(s, path, sc, m);
    return st;
}

static limen_status read_file(limen_scene *s, const char *path, model *m)
{
    struct stat stt;
    if (stat(path, &stt) != 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(stt.st_mode))
        return limen__fail(s, LIMEN_ERR_IO, "%s: not a regular file", path);
    if (stt.st_size == 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: empty file", path);
    static pthread_mutex_t importing = PTHREAD_MUTEX_INITIALIZER;
    char err[301] = "";
    pthread_mutex_lock(&importing);
    const struct aiScene *sc = aiImportFile(path, aiProcess_Triangulate |
                                                      aiProcess_JoinIdenticalVertices |
                                                      aiProcess_SortByPType |
                                                      aiProcess_ValidateDataStructure);
    if (!sc) {
        const char *e = aiGetErrorString();
        snprintf(err, sizeof err, "%s", e ? e : "");
    }
    pthread_mutex_unlock(&importing);
    if (!sc)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as a model: %s", path,
                           err[0] ? err : "unknown format");
    limen_status st = from_assimp(s, path, sc, m);
    aiReleaseImport(sc);
    if (st)
        model_free(m);
    return st;
}

/* ------------------------------------------------------------------ surfaces */

static double dot3d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3d(const double a[3], const double b[3], double out[3])
{
    double r[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0] };
    memcpy(out, r, sizeof r);
}

static bool unit3d(double v[3])
{
    double l = sqrt(dot3d(v, v));
    if (!(l > 0) || !isfinite(l))
        return false;
    for (int k = 0; k < 3; k++)
        v[k] /= l;
    return true;
}

/* The rectangle of node mn's flat polygon in its own frame: frame (columns x = width
 * direction, y = height direction, z = the front's normal, w = centre) and size. up: the
 * parent frame's +Y in the node's frame (the height runs the way nearest to it). */
static bool fit_rectangle(const mnode *mn, const double up[3], float frame[16], float size[2],
                          char *why, size_t wsize)
{
    if (mn->ntris < 1) {
        snprintf(why, wsize, "it has no triangles");
        return false;
    }
    if (mn->ntris > MAX_SURFACE_TRIS) {
        snprintf(why, wsize, "%d triangles (a flat polygon of at most %d)", mn->ntris,
                 MAX_SURFACE_TRIS);
        return false;
    }
    double n[3] = { 0, 0, 0 }, area = 0, lo[3] = { INFINITY, INFINITY, INFINITY },
           hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (int t = 0; t < mn->ntris; t++) {
        double p[3][3], e1[3], e2[3], c[3];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                p[k][a] = mn->pos[mn->idx[t * 3 + k] * 3 + a];
        for (int a = 0; a < 3; a++) {
            e1[a] = p[1][a] - p[0][a];
            e2[a] = p[2][a] - p[0][a];
            for (int k = 0; k < 3; k++) {
                lo[a] = fmin(lo[a], p[k][a]);
                hi[a] = fmax(hi[a], p[k][a]);
            }
        }
        cross3d(e1, e2, c);
        for (int a = 0; a < 3; a++)
            n[a] += c[a];
        area += sqrt(dot3d(c, c));
    }
    double diag[3] = { hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] };
    double extent = sqrt(dot3d(diag, diag));
    /* triangles turned different ways (a fold, a box) add up to less than their areas */
    if (!(sqrt(dot3d(n, n)) >= 0.999 * area) || !unit3d(n) || !(extent > 0)) {
        snprintf(why, wsize, "its triangles do not make one flat polygon facing one way");
        return false;
    }
    double p0[3] = { mn->pos[mn->idx[0] * 3], mn->pos[mn->idx[0] * 3 + 1],
                     mn->pos[mn->idx[0] * 3 + 2] };
    double h0 = dot3d(p0, n);
    for (int t = 0; t < mn->ntris * 3; t++) {
        const float *q = &mn->pos[mn->idx[t] * 3];
        double pq[3] = { q[0], q[1], q[2] };
        if (fabs(dot3d(pq, n) - h0) > FLAT_EPS * extent) {
            snprintf(why, wsize, "it is not flat (a point lies %.3g off its plane)",
                     fabs(dot3d(pq, n) - h0));
            return false;
        }
    }
    /* the rectangle of least area among those along an edge */
    double best = INFINITY, ax[3] = { 0 }, bx[3] = { 0 }, ext[4] = { 0 };
    for (int t = 0; t < mn->ntris * 3; t++) {
        const float *q0 = &mn->pos[mn->idx[t] * 3];
        const float *q1 = &mn->pos[mn->idx[t % 3 == 2 ? t - 2 : t + 1] * 3];
        double a[3] = { q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2] }, b[3];
        double along = dot3d(a, n);
        for (int k = 0; k < 3; k++)
            a[k] -= along * n[k];
        if (!unit3d(a))
            continue;
        cross3d(n, a, b);
        double e[4] = { INFINITY, -INFINITY, INFINITY, -INFINITY };
        for (int v = 0; v < mn->ntris * 3; v++) {
            const float *q = &mn->pos[mn->idx[v] * 3];
            double pq[3] = { q[0], q[1], q[2] }, da = dot3d(pq, a), db = dot3d(pq, b);
            e[0] = fmin(e[0], da);
            e[1] = fmax(e[1], da);
            e[2] = fmin(e[2], db);
            e[3] = fmax(e[3], db);
        }
        double ar = (e[1] - e[0]) * (e[3] - e[2]);
        if (ar < best * (1 - 1e-9)) {
            best = ar;
            memcpy(ax, a, sizeof ax);
            memcpy(bx, b, sizeof bx);
            memcpy(ext, e, sizeof ext);
        }
    }
    if (!(best > 0)) {
        snprintf(why, wsize, "its polygon has no area");
        return false;
    }
    double c[3];
    for (int k = 0; k < 3; k++)
        c[k] = h0 * n[k] + 0.5 * (ext[0] + ext[1]) * ax[k] + 0.5 * (ext[2] + ext[3]) * bx[k];
    double wa = ext[1] - ext[0], wb = ext[3] - ext[2];
    /* height along the axis nearer the parent's up, pointing up; width = height x normal */
    double *v = fabs(dot3d(bx, up)) >= fabs(dot3d(ax, up)) ? bx : ax;
    double height = v == bx ? wb : wa, width = v == bx ? wa : wb;
    if (dot3d(v, up) < 0)
        for (int k = 0; k < 3; k++)
            v[k] = -v[k];
    double u[3];
    cross3d(v, n, u);
    memset(frame, 0, sizeof(float) * 16);
    for (int k = 0; k < 3; k++) {
        frame[k] = (float)u[k];
        frame[4 + k] = (float)v[k];
        frame[8 + k] = (float)n[k];
        frame[12 + k] = (float)c[k];
    }
    frame[15] = 1;
    size[0] = (float)width;
    size[1] = (float)height;
    return true;
}

/* ------------------------------------------------------------------ building */

typedef struct builder {
    limen_scene *s;
    const char *path;
    const model *m;
    limen_node *made;           /* every node made, in order (for undoing) */
    int nmade, made_cap;
    limen_node *of;             /* per model node: its limen node (children attach here) */
    int *cam_of, *light_of;     /* per model node: the camera, light it carries (asked
                                 * for), or -1 */
    size_t bytes, max_bytes;
} builder;

/* Fails with the scene's last message prefixed by the file and what it concerns ("node
 * 'x'"), the message copied first since it is rewritten in place. */
static limen_status refail(builder *b, limen_status st, const char *what, const char *name)
{
    char msg[400];
    snprintf(msg, sizeof msg, "%s", limen_scene_error(b->s));
    return limen__fail(b->s, st, "%s: %s '%s': %s", b->path, what, name, msg);
}

static limen_status make(builder *b, limen_node_kind kind, const char *name, limen_node parent,
                         limen_node *out)
{
    if (b->nmade == b->made_cap) {
        int nc = b->made_cap ? b->made_cap * 2 : 64;
        limen_node *p = realloc(b->made, sizeof *p * (size_t)nc);
        if (!p)
            return limen__fail(b->s, LIMEN_ERR_NOMEM, "%s: out of memory", b->path);
        b->made = p;
        b->made_cap = nc;
    }
    limen_status st = limen_node_create(b->s, kind, name && name[0] ? name : NULL, out);
    if (st)
        return st;
    b->made[b->nmade++] = *out;
    return limen_node_set_parent(b->s, *out, parent);
}

static void mat_mul(const float a[16], const float b[16], float out[16])
{
    float r[16];
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 4; i++) {
            double sum = 0;
            for (int k = 0; k < 4; k++)
                sum += (double)a[k * 4 + i] * b[c * 4 + k];
            r[c * 4 + i] = (float)sum;
        }
    memcpy(out, r, sizeof r);
}

/* The parent's +Y in node mn's frame: the inverse of its local matrix's 3x3 applied to Y
 * (through the adjugate; its scale does not matter, only the direction). */
static void up_in_node(const mnode *mn, double up[3])
{
    const float *m = mn->local;
    double c0[3] = { m[0], m[1], m[2] }, c1[3] = { m[4], m[5], m[6] }, c2[3] = { m[8], m[9], m[10] };
    double r0[3], r1[3], r2[3];   /* rows of the inverse, up to the determinant */
    cross3d(c1, c2, r0);
    cross3d(c2, c0, r1);
    cross3d(c0, c1, r2);
    double det = dot3d(c0, r0);
    up[0] = r0[1] / det;
    up[1] = r1[1] / det;
    up[2] = r2[1] / det;
    if (!unit3d(up)) {
        up[0] = up[2] = 0;
        up[1] = 1;
    }
}

static limen_status build_surface(builder *b, int i, limen_node parent, limen_node *out)
{
    const mnode *mn = &b->m->nodes[i];
    char why[160];
    float frame[16], size[2], local[16];
    double up[3];
    up_in_node(mn, up);
    if (!fit_rectangle(mn, up, frame, size, why, sizeof why))
        return limen__fail(b->s, LIMEN_ERR_ARG, "%s: node '%s': a %s must be one flat "
                           "rectangle (a polygon's bounding rectangle will do): %s", b->path,
                           mn->name, mn->surf.kind == SURF_MIRROR ? "mirror" : "portal", why);
    limen_node_kind kind = mn->surf.kind == SURF_MIRROR ? LIMEN_NODE_MIRROR : LIMEN_NODE_PORTAL;
    limen_status st = make(b, kind, mn->name, parent, out);
    mat_mul(mn->local, frame, local);
    if (!st)
        st = limen_node_set_local_matrix(b->s, *out, local);
    if (!st)
        st = limen_node_set_dims(b->s, *out, (float[3]){ size[0], size[1], 0 });
    if (!st && mn->surf.max_depth >= 0)
        st = limen_surface_set_max_depth(b->s, *out, mn->surf.max_depth);
    if (!st && mn->surf.has_tint)
        st = limen_surface_set_tint(b->s, *out, mn->surf.tint);
    if (st)
        return refail(b, st, "node", mn->name);
    return LIMEN_OK;
}

/* A camera's frame in its node's: looking along `look` with `up` up from `pos`. */
static void eye_frame(const float pos[3], const float look[3], const float up[3], float out[16])
{
    double z[3] = { -look[0], -look[1], -look[2] }, u[3] = { up[0], up[1], up[2] }, x[3], y[3];
    if (!unit3d(z)) {
        z[0] = z[1] = 0;
        z[2] = 1;
    }
    cross3d(u, z, x);
    if (!unit3d(x)) {
        double alt[3] = { 0, 0, 1 };
        cross3d(fabs(z[2]) < 0.9 ? alt : (double[3]){ 1, 0, 0 }, z, x);
        unit3d(x);
    }
    cross3d(z, x, y);
    memset(out, 0, sizeof(float) * 16);
    for (int k = 0; k < 3; k++) {
        out[k] = (float)x[k];
        out[4 + k] = (float)y[k];
        out[8 + k] = (float)z[k];
        out[12 + k] = pos[k];
    }
    out[15] = 1;
}

/* A file node that carries a camera or a light (and no mesh) becomes that node. */
static limen_status build_eye_or_lamp(builder *b, int i, limen_node parent)
{
    const mnode *mn = &b->m->nodes[i];
    limen_node n;
    float frame[16], local[16];
    limen_status st;
    if (b->cam_of[i] >= 0) {
        const mcamera *c = &b->m->cams[b->cam_of[i]];
        float zn = c->znear > 0 ? c->znear : 0.1f;
        float zf = c->zfar > zn ? c->zfar : zn * 1000;
        float fovy = c->fovy > 0 && c->fovy < 3.1f ? c->fovy : 1.0f;
        eye_frame((const float[3]){ 0, 0, 0 }, c->look, c->up, frame);
        mat_mul(mn->local, frame, local);
        if ((st = make(b, LIMEN_NODE_CAMERA, mn->name, parent, &n)) ||
            (st = limen_node_set_local_matrix(b->s, n, local)) ||
            (st = limen_camera_set_lens(b->s, n, fovy, zn, zf)))
            return refail(b, st, "camera", mn->name);
        if (!limen_scene_get_camera(b->s).id && (st = limen_scene_set_camera(b->s, n)))
            return st;
    } else {
        const mlight *l = &b->m->lights[b->light_of[i]];
        float col[3];
        for (int k = 0; k < 3; k++)
            col[k] = isfinite(l->color[k]) ? fmaxf(0, fminf(l->color[k], 1e9f)) : 0;
        eye_frame(l->pos, (const float[3]){ 0, 0, -1 }, (const float[3]){ 0, 1, 0 }, frame);
        mat_mul(mn->local, frame, local);
        if ((st = make(b, LIMEN_NODE_LIGHT, mn->name, parent, &n)) ||
            (st = limen_node_set_local_matrix(b->s, n, local)) ||
            (st = limen_node_set_color(b->s, n, col)))
            return refail(b, st, "light", mn->name);
    }
    b->of[i] = n;
    return LIMEN_OK;
}

static limen_status build_node(builder *b, int i)
{
    const mnode *mn = &b->m->nodes[i];
    limen_node parent = mn->parent < 0 ? b->of[b->m->n] : b->of[mn->parent], n;
    limen_status st;
    if (mn->surf.kind != SURF_NONE) {
        if ((st = build_surface(b, i, parent, &n)))
            return st;
        /* its children hang from its own frame, not the rectangle's */
        b->of[i] = n;
        bool children = false;
        for (int k = i + 1; k < b->m->n && !children; k++)
            children = b->m->nodes[k].parent == i;
        if (children) {
            if ((st = make(b, LIMEN_NODE_GROUP, NULL, parent, &b->of[i])) ||
                (st = limen_node_set_local_matrix(b->s, b->of[i], mn->local)))
                return st;
        }
        return LIMEN_OK;
    }
    bool mesh = mn->ntris > 0;
    if (!mesh && (b->cam_of[i] >= 0 || b->light_of[i] >= 0))
        return build_eye_or_lamp(b, i, parent);
    if ((st = make(b, mesh ? LIMEN_NODE_MESH : LIMEN_NODE_GROUP, mn->name, parent, &n)) ||
        (st = limen_node_set_local_matrix(b->s, n, mn->local)))
        return st;
    b->of[i] = n;
    if (!mesh)
        return LIMEN_OK;
    limen_mesh_data d = { .positions = mn->pos, .normals = mn->has_nrm ? mn->nrm : NULL,
                          .uvs = mn->has_uv ? mn->uv : NULL, .vertex_count = mn->nverts,
                          .indices = mn->idx, .triangle_count = mn->ntris };
    if ((st = limen_mesh_set_triangles(b->s, n, &d)))
        return refail(b, st, "node", mn->name);
    if (mn->has_color && (st = limen_node_set_color(b->s, n, mn->color)))
        return st;
    limen_mesh_info info;
    if (!limen_mesh_get(b->s, n, &info))
        b->bytes += info.bytes;
    if (b->bytes > b->max_bytes)
        return limen__fail(b->s, LIMEN_ERR_NOMEM, "%s: its meshes need %.1f MiB, more than the "
                           "%.1f MiB allowed", b->path, b->bytes / 1048576.0,
                           b->max_bytes / 1048576.0);
    return LIMEN_OK;
}

/* Portal pairs: each names the other. */
static limen_status link_portals(builder *b)
{
    const model *m = b->m;
    for (int i = 0; i < m->n; i++) {
        const mnode *mn = &m->nodes[i];
        if (mn->surf.kind != SURF_PORTAL)
            continue;
        int j = node_named(m, mn->surf.partner);
        if (j < 0 || j == i)
            return limen__fail(b->s, LIMEN_ERR_ARG, "%s: portal '%s': its partner '%s' is not "
                               "a node of the file", b->path, mn->name, mn->surf.partner);
        if (m->nodes[j].surf.kind != SURF_PORTAL || strcmp(m->nodes[j].surf.partner, mn->name))
            return limen__fail(b->s, LIMEN_ERR_ARG, "%s: portal '%s': its partner '%s' does not "
                               "name it back as a portal's partner", b->path, mn->name,
                               mn->surf.partner);
        if (j < i)
            continue;
        /* the surface is the first node made for each (build_surface) */
        limen_node a = { 0 }, c = { 0 };
        for (int k = 0; k < b->nmade; k++) {
            const char *nm = limen_node_get_name(b->s, b->made[k]);
            limen_node_kind kd = limen_node_get_kind(b->s, b->made[k]);
            if (kd == LIMEN_NODE_PORTAL && nm && !a.id && strcmp(nm, mn->name) == 0)
                a = b->made[k];
            else if (kd == LIMEN_NODE_PORTAL && nm && !c.id && strcmp(nm, m->nodes[j].name) == 0)
                c = b->made[k];
        }
        limen_status st = limen_portal_link(b->s, a, c);
        if (st)
            return refail(b, st, "portal", mn->name);
    }
    return LIMEN_OK;
}

static limen_status build(limen_scene *s, limen_node group, const char *path, const model *m,
                          const limen_model_desc *d, size_t max_bytes, size_t *charged)
{
    builder b = { .s = s, .path = path, .m = m, .max_bytes = max_bytes };
    b.of = calloc((size_t)m->n + 1, sizeof *b.of);
    b.cam_of = malloc(sizeof(int) * ((size_t)m->n + 1));
    b.light_of = malloc(sizeof(int) * ((size_t)m->n + 1));
    if (!b.of || !b.cam_of || !b.light_of) {
        free(b.of);
        free(b.cam_of);
        free(b.light_of);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    }
    b.of[m->n] = group;
    for (int i = 0; i < m->n; i++)
        b.cam_of[i] = b.light_of[i] = -1;
    for (int i = 0; d->cameras && i < m->ncams; i++)
        if (b.cam_of[m->cams[i].node] < 0)
            b.cam_of[m->cams[i].node] = i;
    for (int i = 0; d->lights && i < m->nlights; i++)
        if (b.cam_of[m->lights[i].node] < 0 && b.light_of[m->lights[i].node] < 0)
            b.light_of[m->lights[i].node] = i;
    limen_status st = LIMEN_OK;
    for (int i = 0; !st && i < m->n; i++)
        st = build_node(&b, i);
    if (!st)
        st = link_portals(&b);
    if (st) {
        char msg[512];
        snprintf(msg, sizeof msg, "%s", limen_scene_error(s));
        for (int k = b.nmade - 1; k >= 0; k--)
            limen_node_destroy(s, b.made[k]);
        limen__fail(s, st, "%s", msg);
    } else {
        *charged = b.bytes;
    }
    free(b.made);
    free(b.of);
    free(b.cam_of);
    free(b.light_of);
    return st;
}

/* ------------------------------------------------------------------ API */

limen_status limen__model_load(limen_scene *s, limen_node group, const char *path,
                               const limen_model_desc *desc, size_t max_bytes, size_t *charged)
{
    *charged = 0;
    if (!s)
        return LIMEN_ERR_ARG;
    if (!path || !path[0])
        return limen__fail(s, LIMEN_ERR_ARG, "model_load: no file name");
    if (limen_node_get_kind(s, group) != LIMEN_NODE_GROUP || !limen_node_valid(s, group))
        return limen__fail(s, LIMEN_ERR_HANDLE, "model_load: the node to hold the model must "
                           "be a live group");
    limen_model_desc d = desc ? *desc : (limen_model_desc){ 0 };
    model m;
    limen_status st = read_file(s, path, &m);
    if (st)
        return st;
    st = build(s, group, path, &m, &d, max_bytes, charged);
    model_free(&m);
    return st;
}

limen_status limen_model_load(limen_scene *s, limen_node group, const char *path,
                              const limen_model_desc *desc)
{
    size_t charged;
    return limen__model_load(s, group, path, desc, SIZE_MAX, &charged);
}

/* ------------------------------------------------------------------ finding and measuring */

static bool below(const limen_scene *s, limen_node n, limen_node root)
{
    for (int depth = 0; n.id && depth < 100000; depth++) {
        n = limen_node_get_parent(s, n);
        if (n.id == root.id)
            return true;
    }
    return false;
}

limen_status limen_node_find_below(const limen_scene *s, limen_node root, const char *name,
                                   limen_node *out)
{
    if (!s || !name || !out)
        return LIMEN_ERR_ARG;
    out->id = 0;
    if (!limen_node_valid(s, root))
        return LIMEN_ERR_HANDLE;
    const limen__node *nodes = s->nodes;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0 || strcmp(nodes[i].name, name) != 0)
            continue;
        limen_node h = limen__node_handle(s, i);
        if (below(s, h, root)) {
            *out = h;
            return LIMEN_OK;
        }
    }
    return LIMEN_ERR_HANDLE;
}

/* Grows box lo/hi by the unit box [a, b] mapped through world matrix w. */
static void grow_box(const float w[16], const float a[3], const float b[3], float lo[3],
                     float hi[3])
{
    for (int c = 0; c < 8; c++) {
        float p[3] = { c & 1 ? b[0] : a[0], c & 2 ? b[1] : a[1], c & 4 ? b[2] : a[2] };
        for (int k = 0; k < 3; k++) {
            float v = w[k] * p[0] + w[4 + k] * p[1] + w[8 + k] * p[2] + w[12 + k];
            lo[k] = fminf(lo[k], v);
            hi[k] = fmaxf(hi[k], v);
        }
    }
}

/* The local box of what node n shows; false for what shows nothing (groups, lights,
 * cameras, a mesh without triangles). */
static bool shape_box(limen_scene *s, limen_node n, float a[3], float b[3])
{
    float d[3];
    limen_node_get_dims(s, n, d);
    switch (limen_node_get_kind(s, n)) {
    case LIMEN_NODE_BOX:
        for (int k = 0; k < 3; k++)
            b[k] = -(a[k] = -0.5f * d[k]);
        return true;
    case LIMEN_NODE_SPHERE:
        for (int k = 0; k < 3; k++)
            b[k] = -(a[k] = -d[0]);
        return true;
    case LIMEN_NODE_CYLINDER:
        memcpy(a, (float[3]){ -d[0], 0, -d[0] }, sizeof(float) * 3);
        memcpy(b, (float[3]){ d[0], d[1], d[0] }, sizeof(float) * 3);
        return true;
    case LIMEN_NODE_QUAD:
    case LIMEN_NODE_MIRROR:
    case LIMEN_NODE_PORTAL:
        memcpy(a, (float[3]){ -0.5f * d[0], -0.5f * d[1], 0 }, sizeof(float) * 3);
        memcpy(b, (float[3]){ 0.5f * d[0], 0.5f * d[1], 0 }, sizeof(float) * 3);
        return true;
    case LIMEN_NODE_MESH: {
        limen_mesh_info mi;
        if (limen_mesh_get(s, n, &mi) || mi.triangle_count < 1)
            return false;
        memcpy(a, mi.lo, sizeof mi.lo);
        memcpy(b, mi.hi, sizeof mi.hi);
        return true;
    }
    default:
        return false;
    }
}

limen_status limen_node_get_bounds(limen_scene *s, limen_node n, float lo[3], float hi[3])
{
    if (!s || !lo || !hi)
        return LIMEN_ERR_ARG;
    if (!limen_node_valid(s, n))
        return limen__fail(s, LIMEN_ERR_HANDLE, "bounds: %s node handle",
                           n.id ? "stale or foreign" : "null");
    limen_status st = limen_scene_update(s);
    if (st)
        return st;
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    bool any = false;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0)
            continue;
        limen_node h = limen__node_handle(s, i);
        float a[3], b[3], w[16];
        if ((h.id != n.id && !below(s, h, n)) || !shape_box(s, h, a, b) ||
            limen_node_world_matrix(s, h, w))
            continue;
        grow_box(w, a, b, lo, hi);
        any = true;
    }
    if (!any)
        return limen__fail(s, LIMEN_ERR_ARG, "bounds: '%s' shows nothing (no shape in it or "
                           "below it)", limen_node_get_name(s, n)[0] ? limen_node_get_name(s, n)
                                                                     : "the node");
    return LIMEN_OK;
}
