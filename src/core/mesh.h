/* mesh.h - triangle mesh assets: geometry in a node's local frame, shared by every node that
 * shows it, with a bounding-volume hierarchy for the ray tracer. Not part of the public API. */
#ifndef LIMEN_CORE_MESH_H
#define LIMEN_CORE_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "limen.h"

#define LIMEN__MESH_PATH_MAX 512

/* A node of the triangle hierarchy: a box, and either two children (count == 0; the left one
 * follows the node, the right one at `index`) or `count` triangles from tri_order[index]. */
typedef struct limen__tri_node {
    double lo[3], hi[3];
    uint32_t index, count;
} limen__tri_node;

struct limen__texture;

typedef struct limen__mesh {
    int refs;                   /* nodes using it */
    char key[4160];             /* limen__file_key (core/texture.h: 4160), or "" for arrays */
    char name[LIMEN__MESH_PATH_MAX];     /* the path as given, for messages */
    uint32_t nverts, ntris;
    float *pos;                 /* nverts * 3 */
    float *nrm;                 /* nverts * 3: the file's normals, else area-weighted ones */
    float *uv;                  /* nverts * 2, or NULL */
    uint32_t *idx;              /* ntris * 3, counter-clockwise from the front */
    bool file_normals;          /* nrm came with the data: smooth shading always */
    double lo[3], hi[3];        /* local bounds */
    limen__tri_node *bvh;
    uint32_t *tri_order;
    uint32_t nbvh;
    size_t bytes;               /* what it holds, counted against a script's memory cap */
    struct limen__texture *tex; /* the file's base-colour texture (with uvs), or NULL */
    uint64_t serial;            /* unique per asset: the renderer keys its buffers on it */
    limen_mesh_lod *lods;       /* levels of detail, lods[0] the full mesh (idx) */
    uint32_t nlods;
    limen_mesh_geometry pub;    /* what limen_drawable.mesh shows of it */
    char *files;                /* every file its import read ("a\0b\0"), for watching */
    size_t files_len;
} limen__mesh;

/* Bytes a mesh of this size may hold (geometry, levels of detail, hierarchy and
 * bookkeeping): an upper bound, known before any of it is made. */
size_t limen__mesh_bytes(uint64_t nverts, uint64_t ntris, bool uvs);
/* Builds m's triangle hierarchy (bvh, tri_order, nbvh) over idx; false when out of memory.
 * Uses pos, idx, ntris; lowers bytes by the nodes it did not need. */
bool limen__mesh_bvh(limen__mesh *m);
/* Builds m's levels of detail (lods, nlods; core/lod.c) from pos and idx with the hierarchy
 * made, and sets bytes to what they hold; false when out of memory. */
bool limen__mesh_lods_build(limen__mesh *m);

/* Loads path (or finds it already loaded in the scene), refusing one that would hold more
 * than max_bytes; *charged gets the bytes newly held (0 when shared). On failure the message
 * names the file. The node must be a mesh. */
limen_status limen__mesh_load(limen_scene *s, limen_node n, const char *path, size_t max_bytes,
                              size_t *charged);
/* Gives back a node's reference (the asset goes with its last). */
void limen__mesh_release(limen_scene *s, limen__mesh *m);
/* Frees every asset of a scene (at its destruction). */
void limen__meshes_destroy(limen_scene *s);

/* Nearest triangle hit by o + t d (local frame) with tmin < t < tmax, skipping hits on the
 * back of `cut` (a local plane, NULL for none). Returns the triangle or -1; *t, and the
 * barycentric coordinates (u, v) of the hit on vertices 1 and 2. */
int limen__mesh_intersect(const limen__mesh *m, const double o[3], const double d[3],
                          double tmin, double tmax, const double *cut, double *t, double *bu,
                          double *bv);

/* gltf_cost.c: what a glTF (.gltf text or .glb) file places once imported, from its JSON:
 * vertices and triangles of its meshes times the node instances that use them, and how
 * deep its nodes nest (INT32_MAX: a cycle). Returns 0 where the JSON cannot be read within
 * a quarter of max_bytes (the importer then says why). */
int limen__gltf_cost(const unsigned char *data, size_t len, size_t max_bytes, uint64_t *verts,
                     uint64_t *tris, int *depth);

#endif
