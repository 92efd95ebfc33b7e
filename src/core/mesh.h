/* mesh.h - triangle mesh assets: geometry in a node's local frame, shared by every node that
 * shows it, with a bounding-volume hierarchy for the ray tracer. Not part of the public API. */
#ifndef LIMEN_CORE_MESH_H
#define LIMEN_CORE_MESH_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "limen.h"

#define LIMEN__MESH_PATH_MAX 512

/* A node of the triangle hierarchy: a box, and either two children (count == 0; the left one
 * follows the node, the right one at `index`) or `count` triangles from tri_order[index].
 * The box is in float, exactly: its sides are the float vertices' own coordinates (32 bytes
 * a node, not 56: 25 MB less at 1.6M triangles). */
typedef struct limen__tri_node {
    float lo[3], hi[3];
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
    limen__tri_node *bvh;       /* the hierarchy: made on first need, where bvh_ready says
                                 * (limen__mesh_hierarchy) */
    uint32_t *tri_order;
    uint32_t nbvh;
    atomic_bool bvh_ready;
    size_t bytes;               /* what it holds, counted against a script's memory cap */
    struct limen__texture *tex; /* the file's base-colour texture (with uvs), or NULL */
    uint64_t serial;            /* unique per asset: the renderer keys its buffers on it */
    limen_mesh_lod *lods;       /* levels of detail, lods[0] the full mesh (idx) */
    uint32_t nlods;
    struct limen__mesh **lod_baked;     /* nlods: level k as a mesh of its own with a baked
                                 * texture (core/lod_bake.h; lods[k].baked its pub), or NULL */
    limen_mesh_geometry pub;    /* what limen_drawable.mesh shows of it */
    char *files;                /* every file its import read ("a\0b\0"), for watching */
    size_t files_len;
    struct limen__lod_job *lod_job;     /* its levels being made on another thread, or NULL */
    /* materials (see limen_material) */
    float *col;                 /* nverts * 4 RGBA vertex colours, or NULL (white) */
    uint32_t nparts, nmats;
    limen_mesh_part *parts;     /* nparts ranges of idx, in triangle order */
    limen_mesh_part *lod_parts; /* nlods * nparts: each level's ranges */
    uint32_t *tri_part;         /* ntris: the part of each triangle of idx; NULL where there
                                 * is one part (limen__tri_part) */
    limen_material *mats;       /* nmats; their textures point at texs' images */
    struct limen__texture **texs;   /* nmats * 5: base, emissive, metallic-roughness, normal,
                                 * occlusion of each, or NULL */
    char *mat_names;            /* the names' storage */
    bool has_mask, has_blend;
} limen__mesh;

/* The part of m's triangle t (of idx). */
static inline uint32_t limen__tri_part(const limen__mesh *m, uint32_t t)
{
    return m->tri_part ? m->tri_part[t] : 0;
}

enum { LIMEN__MAT_BASE, LIMEN__MAT_EMISSIVE, LIMEN__MAT_MR, LIMEN__MAT_NORMAL,
       LIMEN__MAT_OCCLUSION, LIMEN__MAT_TEXTURES };

/* Whether the hit (u, v on triangle tri's vertices 1 and 2) is cut away by its part's alpha
 * mask. */
/* Each level's triangles grouped by part, and the parts' ranges in it (lod_parts, each
 * level's .parts): again whenever the levels change (limen__mesh_lods_settle). */
bool limen__mesh_lod_parts(limen__mesh *m);
bool limen__mesh_masked(const limen__mesh *m, uint32_t tri, double u, double v);
/* The material at a hit: albedo (base x texel x vertex colour; the node's texture, if not
 * NULL, in place of the base texture), alpha, and emissive. Textures are sampled with filter
 * over the footprint duv (limen__texture_filter; NULL: the full image). */
void limen__mesh_material_at(const limen__mesh *m, const struct limen__texture *node_tex,
                             const float repeat[2], limen_texture_filter filter,
                             const double *duv, uint32_t tri, double u, double v,
                             double albedo[3], double *alpha, double emissive[3]);

/* Bytes a mesh of this size may hold (geometry, levels of detail, hierarchy and
 * bookkeeping): an upper bound, known before any of it is made. */
size_t limen__mesh_bytes(uint64_t nverts, uint64_t ntris, bool uvs);
/* Builds m's triangle hierarchy (bvh, tri_order, nbvh) over idx; false when out of memory.
 * Uses pos, idx, ntris; lowers bytes by the nodes it did not need. For a mesh of its own
 * (a level's), not a scene's asset, whose hierarchy limen__mesh_hierarchy makes. */
bool limen__mesh_bvh(limen__mesh *m);
/* A scene's mesh gets its hierarchy when something first needs it (a ray, a collision; not
 * the measuring of its levels, which makes its own), not when it is loaded: the first
 * frame of a big mesh does not wait for it. Makes it where it is not made yet, once, from
 * any thread (the others wait); false when out of memory (nothing then is made). Its bytes
 * are counted from the start. */
bool limen__mesh_hierarchy(const limen__mesh *m);
/* Tests only: whether mesh node n's hierarchy is made (false for a node without a mesh). */
bool limen__mesh_hierarchy_made(limen_scene *s, limen_node n);
/* Builds m's levels of detail (lods, nlods; core/lod.c) from pos and idx, and sets bytes to
 * what they hold; false when out of memory. */
bool limen__mesh_lods_build(limen__mesh *m);

/* ---- levels made on another thread (core/lod.c) */
#define LIMEN__LOD_ASYNC_TRIS 100000    /* a mesh this big makes its levels on another thread */
/* As limen__mesh_lods_build, but for a mesh of at least LIMEN__LOD_ASYNC_TRIS triangles
 * whose levels are not in the cache: m gets the full mesh alone as its one level, and a
 * thread makes the rest (reading m's geometry, which must not change, and measuring them
 * against a hierarchy of its own, given back when done), which limen__mesh_lods_settle
 * hands over. Before m->pub is made. */
bool limen__mesh_lods_start(limen__mesh *m);
/* Where m's levels are made (waiting for them where wait), gives them to m, with a new
 * serial and m->pub to match; true where it did. On the scene's thread. */
bool limen__mesh_lods_settle(limen__mesh *m, bool wait);
/* limen__mesh_lods_settle for every mesh of s: the scene's refresh calls it (wait false). */
void limen__meshes_settle(limen_scene *s, bool wait);
/* A frame is being prepared (limen_drawables_build, which every renderer's frame calls, a
 * game's own too): the level builds of s's meshes that were there at the one before begin
 * (that frame is drawn by now). Each waits for it (at most a few seconds) so that a big
 * mesh's first frame is drawn first. */
void limen__meshes_framed(limen_scene *s);
/* Frees m's levels (lods, and the baked levels' meshes). */
void limen__mesh_lods_free(limen__mesh *m);
/* Stops m's build, if any, and waits for its thread (before m is freed). */
void limen__mesh_lods_stop(limen__mesh *m);
/* Tests only: the size from which levels are made on another thread (default
 * LIMEN__LOD_ASYNC_TRIS); not for use while meshes are being made. */
void limen__lod_set_async_above(uint32_t triangles);
/* Tests only: whether a level's pieces are bounded on threads beside the one making the
 * levels (default true) or in turn on it, which gives the same bounds; not for use while
 * meshes are being made. */
void limen__lod_set_measure_threads(bool on);
/* Tests only: the size from which a mesh's next level is simplified beside this one, where
 * both sources are taken whole (default LIMEN__LOD_SPLIT_ABOVE); and how many levels so
 * made were kept, in all. Not for use while meshes are being made. */
void limen__lod_set_beside_above(uint32_t triangles);
uint64_t limen__lod_beside_kept(void);
/* Tests only: the size of a level from which the level two after it is simplified from it
 * (default LIMEN__LOD_NEAR_SOURCE: see source_of in core/lod.c). Not for use while meshes
 * are being made. */
#define LIMEN__LOD_NEAR_SOURCE 100000
void limen__lod_set_near_source(uint32_t triangles);

/* Loads path (or finds it already loaded in the scene), refusing one that would hold more
 * than max_bytes; *charged gets the bytes newly held (0 when shared). On failure the message
 * names the file. The node must be a mesh. */
limen_status limen__mesh_load(limen_scene *s, limen_node n, const char *path, size_t max_bytes,
                              size_t *charged);
struct limen__import;
struct limen__block;
/* Imports a model file into a block (core/import.h) through the scene's one way in: read
 * through its folder and limits, the safe formats only when a script loads safely, headers
 * and glTF node counts checked against max_bytes before the importer runs, the import itself
 * contained in a child process where the load is safe. *files: the files the import read
 * (for hot reload); free both. The failure is the scene's message, naming the file. */
limen_status limen__mesh_import(limen_scene *s, const char *path, unsigned flags,
                                size_t max_bytes, struct limen__import **blk,
                                struct limen__block *files);
/* Node `node` of an imported block (its parts in its own frame, with their materials and
 * textures) as the mesh of mesh node n; refuses one holding more than max_bytes. *charged:
 * the bytes it holds. */
limen_status limen__mesh_from_import(limen_scene *s, limen_node n, const struct limen__import *b,
                                     uint32_t node, const char *path, size_t max_bytes,
                                     size_t *charged);
/* The block's warnings into the scene's list, as "file: warning: text". */
void limen__mesh_keep_warnings(limen_scene *s, const struct limen__import *b, const char *path);
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

/* mesh_look.c: opens path through the scene's way in and refuses it, before the importer
 * runs, where the read budget cannot hold the file, a safe scene may not load its format, its
 * header declares more than the file holds, or what it declares (a PLY's or OFF's faces, a
 * binary STL's triangles, a glTF's nodes, an OBJ's faces or an ASCII STL's facets counted in
 * one pass) needs more than max_bytes as a mesh: without reading more than the format needs
 * to say how large it is, and never holding the whole file beside a glTF's JSON. Sets
 * s->mem_wanted where more memory would allow it. *counted gets the triangles counted and
 * *needed the bytes they need as a mesh (limen__mesh_bytes) where the file's content was
 * read (0 where none were: a small OBJ or ASCII STL is not scanned, a glTF whose JSON cannot
 * be read within a quarter of max_bytes is not known); either may be NULL. */
limen_status limen__mesh_look(limen_scene *s, const char *path, size_t max_bytes,
                              uint64_t *counted, size_t *needed);

/* gltf_cost.c: the JSON of the glTF file open at fd (size bytes): a .glb's first chunk,
 * read alone (not the binary chunk after it), where it is a JSON chunk within the file, else
 * the whole file (a .gltf is its JSON). Returns 1 with *json (malloc'd: *len bytes and a NUL
 * after them); 0 where there is none of at most max bytes (a .glb whose first chunk is not
 * its JSON); -1 where it could not be read (errno; ENOMEM where no memory held it). */
int limen__gltf_json(int fd, uint64_t size, size_t max, char **json, size_t *len);

/* gltf_cost.c: what a glTF file places once imported, from its JSON (limen__gltf_json):
 * vertices and triangles of its meshes times the node instances that use them, and how
 * deep its nodes nest (INT32_MAX: a cycle). Returns 0 where the JSON cannot be read within
 * a quarter of max_bytes (the importer then says why). */
int limen__gltf_cost(const unsigned char *data, size_t len, size_t max_bytes, uint64_t *verts,
                     uint64_t *tris, int *depth);

#endif
