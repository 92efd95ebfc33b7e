/* model.c - a model file as a scene: its node hierarchy becomes limen nodes under a group
 * (names, local matrices, each node's meshes as one mesh node of parts in their materials),
 * its cameras and point lights when asked, and nodes authored as mirrors and portals (glTF
 * extras, as Blender exports an object's custom properties: "limen": {"mirror": {...}} or
 * {"portal": {...}}; or a name ending in "-mirror") become surfaces whose rectangle is fitted
 * to the node's flat mesh.
 *
 * Two steps: the file is read by the importer (core/import.c) into its block, and the block
 * into a description (`model`: the hierarchy, surfaces, cameras, lights; from_import); then
 * the description is built into the scene (build), each mesh node's triangles, materials
 * and textures made from the block by core/mesh.c. Building is all or nothing: on failure
 * every node made is destroyed. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/confine.h"
#include "core/contain.h"
#include "core/import.h"
#include "core/internal.h"
#include "core/json.h"
#include "core/mesh.h"
#include "core/model.h"
#include "core/texture.h"
#include "core/reserve.h"

#define MAX_NODES 100000        /* a file's nodes at most */
#define MAX_SURFACE_TRIS 256    /* a mirror's or portal's polygon, in triangles at most */
#define FLAT_EPS 1e-4           /* off the plane, relative to the polygon's size */
#define AI_LIGHT_POINT 2        /* assimp's aiLightSource_POINT (limen__import_light.type) */

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
    uint32_t bnode;             /* its node in the importer's block */
    float local[16];            /* column-major, relative to the parent */
    int ntris;                  /* its meshes' triangles */
    float *pos;                 /* surfaces: their vertices in the node's own frame, */
    uint32_t *idx;              /* ... and triangles */
    msurf surf;
} mnode;

typedef struct mcamera {
    int node;
    float look[3], up[3], fovy, znear, zfar;
} mcamera;

typedef struct mlight {
    int node;
    float pos[3], color[3];
    float range;                /* 0: none */
} mlight;

typedef struct model {
    limen__import *blk;         /* the importer's block (meshes are made from it) */
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
        free(m->nodes[i].idx);
    }
    free(m->nodes);
    free(m->blk);
    free(m->cams);
    free(m->lights);
    memset(m, 0, sizeof *m);
}

/* ------------------------------------------------------------------ names and extras */

static bool utf8_ok(const char *p, size_t n)
{
    const unsigned char *s = (const unsigned char *)p, *end = s + n;
    while (s < end) {
        int k = *s < 0x80 ? 0 : (*s & 0xe0) == 0xc0 ? 1 : (*s & 0xf0) == 0xe0 ? 2
                : (*s & 0xf8) == 0xf0 ? 3 : -1;
        if (k < 0 || !*s)
            return false;
        s++;
        for (int j = 0; j < k; j++, s++)
            if (s >= end || (*s & 0xc0) != 0x80)
                return false;
    }
    return true;
}

/* A name as limen keeps it (LIMEN__NAME_MAX - 1 bytes at most, cut between characters) from
 * n bytes; "" for one that is not UTF-8. */
static void copy_name(char out[LIMEN__NAME_MAX], const char *name, size_t n)
{
    out[0] = '\0';
    if (!utf8_ok(name, n))
        return;
    if (n > LIMEN__NAME_MAX - 1) {
        n = LIMEN__NAME_MAX - 1;
        while (n > 0 && ((unsigned char)name[n] & 0xc0) == 0x80)
            n--;
    }
    memcpy(out, name, n);
    out[n] = '\0';
}

static bool json_number(const limen__json *j, int i, double *out)
{
    if (i < 0 || (j->v[i].type != LIMEN__JSON_NUMBER && j->v[i].type != LIMEN__JSON_BOOL))
        return false;
    *out = j->v[i].number;
    return true;
}

/* Three numbers from 0 to 1: an array, or an object of three members (the importer writes an
 * array of the file's extras as an object whose members repeat its name). */
static bool json_rgb(const limen__json *j, int i, float out[3])
{
    if (i < 0 || (j->v[i].type != LIMEN__JSON_ARRAY && j->v[i].type != LIMEN__JSON_OBJECT))
        return false;
    int k = 0;
    for (int c = j->v[i].child; c >= 0; c = j->v[c].next, k++) {
        double v;
        if (k >= 3 || !json_number(j, c, &v) || !(v >= 0 && v <= 1))
            return false;
        out[k] = (float)v;
    }
    return k == 3;
}

/* The node's "limen" extras (the importer's JSON) into *sf; false with a message in why where
 * they are not as limen.h says. */
static bool read_extras(const char *extras, msurf *sf, char *why, size_t size)
{
    limen__json j;
    if (!extras[0] || !limen__json_parse(&j, extras, strlen(extras), 100000)) {
        if (extras[0])
            free(j.v);
        return true;    /* none, or none readable: not ours */
    }
    bool ok = false;
    int l = limen__json_get(&j, 0, "limen");
    int mir = limen__json_get(&j, l, "mirror"), por = limen__json_get(&j, l, "portal");
    if (l < 0) {
        ok = true;
        goto done;
    }
    if (j.v[l].type != LIMEN__JSON_OBJECT) {
        snprintf(why, size, "its extras' \"limen\" is not an object");
        goto done;
    }
    if (mir >= 0 && j.v[mir].type != LIMEN__JSON_OBJECT)
        mir = -1;
    if (por >= 0 && j.v[por].type != LIMEN__JSON_OBJECT)
        por = -1;
    if ((mir >= 0) == (por >= 0)) {
        snprintf(why, size, "its extras' \"limen\" must hold one object, \"mirror\" or "
                 "\"portal\"");
        goto done;
    }
    sf->kind = mir >= 0 ? SURF_MIRROR : SURF_PORTAL;
    for (int c = j.v[mir >= 0 ? mir : por].child; c >= 0; c = j.v[c].next) {
        const limen__json_value *e = &j.v[c];
        double v;
        if (e->klen == 9 && memcmp(e->key, "max_depth", 9) == 0) {
            if (!json_number(&j, c, &v) || !(v >= 0 && v <= 255) || v != floor(v)) {
                snprintf(why, size, "max_depth must be an integer from 0 to 255");
                goto done;
            }
            sf->max_depth = (int)v;
        } else if (e->klen == 4 && memcmp(e->key, "tint", 4) == 0 && mir >= 0) {
            if (!json_rgb(&j, c, sf->tint)) {
                snprintf(why, size, "tint must be [r, g, b], each from 0 to 1");
                goto done;
            }
            sf->has_tint = true;
        } else if (e->klen == 7 && memcmp(e->key, "partner", 7) == 0 && por >= 0) {
            if (e->type != LIMEN__JSON_STRING || !e->len) {
                snprintf(why, size, "partner must be a node's name");
                goto done;
            }
            copy_name(sf->partner, e->str, e->len);
        } else {
            snprintf(why, size, "unknown %s field \"%.*s\"", mir >= 0 ? "mirror" : "portal",
                     (int)(e->klen < 40 ? e->klen : 40), e->key);
            goto done;
        }
    }
    if (por >= 0 && !sf->partner[0]) {
        snprintf(why, size, "a portal needs \"partner\": the name of the other node");
        goto done;
    }
    ok = true;
done:
    free(j.v);
    return ok;
}

/* ------------------------------------------------------------------ from the importer */

/* A surface node's triangles (in its own frame) from the block. */
static bool surface_triangles(const limen__import *b, uint32_t bn, mnode *mn)
{
    const limen__import_node *nd = &LIMEN__IMP(b, nodes, limen__import_node)[bn];
    const limen__import_part *ps = LIMEN__IMP(b, parts, limen__import_part);
    const limen__import_vertex *vs = LIMEN__IMP(b, verts, limen__import_vertex);
    const uint32_t *ts = LIMEN__IMP(b, tris, uint32_t), *np = LIMEN__IMP(b, node_parts, uint32_t);
    mn->pos = malloc(sizeof(float) * 9 * (size_t)(mn->ntris ? mn->ntris : 1));
    mn->idx = malloc(sizeof(uint32_t) * 3 * (size_t)(mn->ntris ? mn->ntris : 1));
    if (!mn->pos || !mn->idx)
        return false;
    uint32_t t = 0;
    for (uint32_t k = 0; k < nd->part_count; k++) {
        const limen__import_part *p = &ps[np[nd->first_part + k]];
        for (uint32_t i = 0; i < p->tri_count; i++, t++)
            for (int c = 0; c < 3; c++) {
                const uint32_t v = ts[(size_t)(p->first_tri + i) * 3 + c];
                memcpy(&mn->pos[(t * 3 + c) * 3], vs[p->first_vertex + v].pos, sizeof(float) * 3);
                mn->idx[t * 3 + c] = t * 3 + (uint32_t)c;
            }
    }
    return true;
}

static int node_named(const model *m, const char *name)
{
    for (int i = 0; name[0] && i < m->n; i++)
        if (strcmp(m->nodes[i].name, name) == 0)
            return i;
    return -1;
}

static bool identity(const float *f)
{
    for (int i = 0; i < 16; i++)
        if (f[i] != (i % 5 == 0 ? 1.0f : 0.0f))
            return false;
    return true;
}

static limen_status cameras_lights(limen_scene *s, const char *path, model *m)
{
    const limen__import *b = m->blk;
    const limen__import_camera *cs = LIMEN__IMP(b, cameras, limen__import_camera);
    const limen__import_light *ls = LIMEN__IMP(b, lights, limen__import_light);
    m->cams = calloc(b->ncameras + 1, sizeof *m->cams);
    m->lights = calloc(b->nlights + 1, sizeof *m->lights);
    if (!m->cams || !m->lights)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    for (uint32_t i = 0; i < b->ncameras; i++) {
        mcamera *mc = &m->cams[m->ncams];
        if ((mc->node = node_named(m, limen__import_string(b, cs[i].name))) < 0)
            continue;
        memcpy(mc->look, cs[i].look, sizeof mc->look);
        memcpy(mc->up, cs[i].up, sizeof mc->up);
        mc->fovy = cs[i].fovy;     /* a glTF's own yfov replaces it (gltf_extras) */
        mc->znear = cs[i].znear;
        mc->zfar = cs[i].zfar;
        m->ncams++;
    }
    for (uint32_t i = 0; i < b->nlights; i++) {
        mlight *ml = &m->lights[m->nlights];
        if (ls[i].type != AI_LIGHT_POINT ||
            (ml->node = node_named(m, limen__import_string(b, ls[i].name))) < 0)
            continue;
        memcpy(ml->pos, ls[i].pos, sizeof ml->pos);
        memcpy(ml->color, ls[i].colour, sizeof ml->color);
        ml->range = ls[i].range;
        m->nlights++;
    }
    return LIMEN_OK;
}

/* The block's hierarchy into m (which takes the block). */
static limen_status from_import(limen_scene *s, const char *path, limen__import *b, model *m)
{
    memset(m, 0, sizeof *m);
    m->blk = b;
    const limen__import_node *ns = LIMEN__IMP(b, nodes, limen__import_node);
    if (b->nnodes > MAX_NODES)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: more than %d nodes", path, MAX_NODES);
    m->nodes = calloc(b->nnodes + 1, sizeof *m->nodes);
    int *of = malloc(sizeof(int) * (b->nnodes + 1));
    if (!m->nodes || !of) {
        free(of);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    }
    const limen__import_part *ps = LIMEN__IMP(b, parts, limen__import_part);
    const uint32_t *np = LIMEN__IMP(b, node_parts, uint32_t);
    limen_status st = LIMEN_OK;
    for (uint32_t i = 0; i < b->nnodes && !st; i++) {
        const limen__import_node *nd = &ns[i];
        const char *name = limen__import_string(b, nd->name);
        of[i] = -1;
        /* assimp's own root above a file's several top nodes is not one of the file's */
        if (i == 0 && nd->part_count == 0 && identity(nd->matrix) && strcmp(name, "ROOT") == 0)
            continue;
        mnode *mn = &m->nodes[m->n];
        of[i] = m->n++;
        mn->parent = nd->parent < i ? of[nd->parent] : -1;
        mn->bnode = i;
        mn->surf.max_depth = -1;
        copy_name(mn->name, name, strlen(name));
        memcpy(mn->local, nd->matrix, sizeof mn->local);
        for (int k = 0; k < 16; k++)
            if (!isfinite(mn->local[k]))
                st = limen__fail(s, LIMEN_ERR_ARG, "%s: node '%s': its matrix is not finite",
                                 path, mn->name);
        for (uint32_t k = 0; k < nd->part_count; k++)
            mn->ntris += (int)ps[np[nd->first_part + k]].tri_count;
        char why[160] = "";
        if (!st && !read_extras(limen__import_string(b, nd->extras), &mn->surf, why, sizeof why))
            st = limen__fail(s, LIMEN_ERR_ARG, "%s: node '%s': %s", path, mn->name, why);
        size_t len = strlen(mn->name);
        if (mn->surf.kind == SURF_NONE && len >= 7 && strcmp(mn->name + len - 7, "-mirror") == 0)
            mn->surf.kind = SURF_MIRROR;
        if (!st && mn->surf.kind != SURF_NONE && mn->ntris <= MAX_SURFACE_TRIS &&
            !surface_triangles(b, i, mn))
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", path);
    }
    free(of);
    if (!st)
        st = cameras_lights(s, path, m);
    return st;
}

/* ------------------------------------------------------------------ what assimp drops */

#define MAX_JSON_BYTES (64u << 20)

/* The JSON of a .gltf, or of a .glb's first chunk (limen__gltf_json), through the scene's
 * one way in (the script's folder when a script loads); NULL if the file is neither or is
 * too large. *len its length; free() it. */
static char *gltf_json(limen_scene *s, const char *path, size_t *len)
{
    char why[160];
    struct stat st;
    int fd = limen__confine_open(s->load ? s->load->box : NULL, path, &st, why, sizeof why);
    if (fd < 0)
        return NULL;    /* the importer read it a moment ago: keep what it gave */
    char *text;
    limen__gltf_json(fd, (uint64_t)st.st_size, MAX_JSON_BYTES, &text, len);
    close(fd);
    return text;
}

/* What a glTF says that assimp 5.2 does not pass on as written: KHR_lights_punctual's ranges
 * (a light on the glTF node of the same name takes its light's range), and a perspective
 * camera's yfov (assimp gives yfov x aspect as its horizontal angle, which the importer's
 * block reads as half the horizontal one). Files that are not glTF, or whose JSON cannot be
 * read here, keep what the importer gave. */
static void gltf_extras(limen_scene *s, const char *path, model *m)
{
    size_t len = 0;
    char *text = m->nlights || m->ncams ? gltf_json(s, path, &len) : NULL;
    limen__json j;
    if (!text || !limen__json_parse(&j, text, len, 4 * 1024 * 1024)) {
        if (text)
            free(j.v);
        free(text);
        return;
    }
    int lights = limen__json_get(&j, limen__json_get(&j, limen__json_get(&j, 0, "extensions"),
                                                    "KHR_lights_punctual"), "lights");
    int nodes = limen__json_get(&j, 0, "nodes"), cams = limen__json_get(&j, 0, "cameras");
    /* along the siblings: limen__json_at walks from the first each time, which over a file
     * of many nodes would take their count squared */
    int first = limen__json_at(&j, nodes, 0);
    for (int nd = first; nd >= 0; nd = j.v[nd].next) {
        int name = limen__json_get(&j, nd, "name"), ci = limen__json_get(&j, nd, "camera");
        int yfov = ci >= 0 && j.v[ci].type == LIMEN__JSON_NUMBER && j.v[ci].number >= 0 &&
                           j.v[ci].number <= 1e6
                       ? limen__json_get(&j, limen__json_get(&j, limen__json_at(&j, cams,
                                                                                (int)j.v[ci].number),
                                                             "perspective"), "yfov")
                       : -1;
        for (int i = 0; name >= 0 && yfov >= 0 && j.v[yfov].type == LIMEN__JSON_NUMBER &&
                        i < m->ncams; i++)
            if (limen__json_is(&j, name, m->nodes[m->cams[i].node].name))
                m->cams[i].fovy = (float)j.v[yfov].number;
        int li = limen__json_get(&j, limen__json_get(&j, limen__json_get(&j, nd, "extensions"),
                                                    "KHR_lights_punctual"), "light");
        if (name < 0 || li < 0 || j.v[li].type != LIMEN__JSON_NUMBER || j.v[li].number < 0 ||
            j.v[li].number > 1e6)
            continue;
        int range = limen__json_get(&j, limen__json_at(&j, lights, (int)j.v[li].number), "range");
        if (range < 0 || j.v[range].type != LIMEN__JSON_NUMBER)
            continue;
        for (int i = 0; i < m->nlights; i++)
            if (limen__json_is(&j, name, m->nodes[m->lights[i].node].name))
                m->lights[i].range = (float)j.v[range].number;
    }
    free(j.v);
    free(text);
}

static limen_status read_file(limen_scene *s, const char *path, size_t max_bytes, model *m)
{
    limen__import *blk;
    memset(m, 0, sizeof *m);
    limen__block files;
    limen_status st = limen__mesh_import(s, path, 0, max_bytes, &blk, &files);
    if (st)
        return st;
    limen__block_free(&files);
    st = from_import(s, path, blk, m);
    if (!st)
        gltf_extras(s, path, m);
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
    bool keyed;                 /* a mesh carries the file's key */
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
    if (!limen__reserve((void **)&b->made, &b->made_cap, b->nmade + 1, sizeof *b->made))
        return limen__fail(b->s, LIMEN_ERR_NOMEM, "%s: out of memory", b->path);
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
            (st = limen_node_set_color(b->s, n, col)) ||
            (l->range > 0 && (st = limen_light_set_range(b->s, n, l->range))))
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
    /* its parts in their materials, with their textures, from the importer's block */
    size_t charged = 0;
    if (b->bytes >= b->max_bytes ||
        (st = limen__mesh_from_import(b->s, n, b->m->blk, mn->bnode, b->path,
                                      b->max_bytes - b->bytes, &charged)))
        return refail(b, st ? st : LIMEN_ERR_NOMEM, "node", mn->name);
    b->bytes += charged;
    /* the first mesh carries the file's key, so that limen_scene_get_file lists the model
     * (limen view reloads the script when it changes); its own key never matches a
     * limen_mesh_load's, so it is never shared by one */
    if (!b->keyed) {
        limen__node *nd;
        limen__node_lookup(b->s, n, 0, NULL, "model", &nd);     /* made above: it is there */
        struct stat stt;
        char key[LIMEN__FILE_KEY];
        if (nd && nd->mesh && !limen__file_key(b->s, b->path, key, &stt) &&
            strlen(key) + 8 < sizeof nd->mesh->key) {
            snprintf(nd->mesh->key, sizeof nd->mesh->key, "%s#model", key);
            b->keyed = true;
        }
    }
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
    limen_status st = read_file(s, path, max_bytes, &m);
    if (st)
        return st;
    st = build(s, group, path, &m, &d, max_bytes, charged);
    if (!st)
        limen__mesh_keep_warnings(s, m.blk, path);
    model_free(&m);
    return st;
}

limen_status limen_model_load(limen_scene *s, limen_node group, const char *path,
                              const limen_model_desc *desc)
{
    size_t charged;
    return limen__model_load(s, group, path, desc, SIZE_MAX, &charged);
}
