/* import.h - what a model file holds, read through assimp into one contiguous, pointer-free
 * block: a header and arrays addressed by byte offsets from the block's start, all in one
 * allocation (free() releases it). Being position-independent, the block can be made in
 * another process and sent back through a pipe as it is. It keeps the file's own structure
 * (meshes in their own frames, the node hierarchy with local matrices); core/mesh.c flattens
 * it into one mesh of parts. Not part of the public API. */
#ifndef LIMEN_CORE_IMPORT_H
#define LIMEN_CORE_IMPORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "limen.h"

#define LIMEN__IMPORT_MAGIC 0x4c4d494du     /* "LMIM" */
#define LIMEN__IMPORT_VERSION 1u
#define LIMEN__IMPORT_NONE UINT32_MAX       /* no texture, no parent, no string */

enum {
    LIMEN__IMPORT_NO_TEXTURES = 1u,         /* flags: leave the file's images unread (a node
                                             * names its own texture) */
};

/* What a vertex came with (limen__import.vertex_flags). */
enum {
    LIMEN__VERT_NORMALS = 1u,               /* every part has normals */
    LIMEN__VERT_UV0 = 2u,                   /* some part has texture coordinates set 0 */
    LIMEN__VERT_UV1 = 4u,                   /* ... set 1 */
    LIMEN__VERT_COLOURS = 8u,               /* some part has vertex colours */
};

typedef struct limen__import_vertex {
    float pos[3];               /* in its mesh's own frame (the node's matrix not applied) */
    float nrm[3];               /* the file's normal, or 0 where it has none */
    float uv[2][2];             /* texture-coordinate sets 0 and 1 (v up); 0 where absent */
    float col[4];               /* linear RGBA vertex colour; white where the file has none */
} limen__import_vertex;

/* One of the file's meshes: a triangle range in one material. */
typedef struct limen__import_part {
    uint32_t first_vertex, vertex_count;    /* its vertices (its triangles index into these,
                                             * counted from first_vertex) */
    uint32_t first_tri, tri_count;          /* its triangles in tris */
    uint32_t material;                      /* index into materials */
    uint32_t has_normals;                   /* 1: the file gave its normals */
    uint32_t name;                          /* string offset, or NONE */
} limen__import_part;

enum { LIMEN__ALPHA_OPAQUE = 0, LIMEN__ALPHA_MASK = 1, LIMEN__ALPHA_BLEND = 2 };

typedef struct limen__import_material {
    uint32_t name;              /* string offset, or NONE */
    float base[4];              /* base colour factor, linear RGBA (glTF baseColorFactor,
                                 * MTL Kd with d as alpha) */
    uint32_t base_tex;          /* index into textures, or NONE */
    uint32_t base_uv;           /* which texture-coordinate set it reads (0 or 1) */
    float base_xform[6];        /* uv' = (x[0] u + x[2] v + x[4], x[1] u + x[3] v + x[5]):
                                 * a 2x3 column-major matrix (KHR_texture_transform, MTL -o/-s) */
    uint32_t alpha_mode;        /* LIMEN__ALPHA_* */
    float alpha_cutoff;         /* mask: alpha below it is not drawn (default 0.5) */
    float emissive[3];          /* emissive factor, added after shading */
    uint32_t emissive_tex, emissive_uv;     /* texture index or NONE; its coordinate set */
    uint32_t double_sided;      /* glTF doubleSided (limen lights both sides regardless) */
    uint32_t metal_rough_tex, normal_tex, occlusion_tex;    /* listed, not shaded; or NONE */
    float metallic, roughness;  /* factors (glTF defaults 1, 1) */
    float normal_scale, occlusion_strength;
} limen__import_material;

/* A decoded image. width 0: named by the file but not found or not readable (a warning
 * says which), so the parts using it keep their colour. */
typedef struct limen__import_texture {
    uint32_t name;              /* string offset: the path or "*N" the file gave */
    uint32_t width, height;
    uint32_t has_alpha;         /* 1 when some texel's alpha is below 255 */
    uint64_t texels;            /* offset of width * height * 4 bytes RGBA8, top row first */
} limen__import_texture;

/* A node of the file's hierarchy, parents before children. */
typedef struct limen__import_node {
    uint32_t name;              /* string offset */
    uint32_t parent;            /* index into nodes, NONE for the root */
    float matrix[16];           /* local transform, column-major (limen's CONVENTIONS) */
    uint32_t first_part, part_count;    /* its parts: node_parts[first_part ...] */
    uint32_t extras;            /* string offset: its metadata (glTF extras) as a JSON object,
                                 * or NONE */
} limen__import_node;

typedef struct limen__import_camera {
    uint32_t name;              /* the node that carries it */
    float pos[3], look[3], up[3];   /* in that node's frame */
    float fovy;                 /* vertical field of view, radians */
    float znear, zfar, aspect;  /* aspect 0: not given */
} limen__import_camera;

typedef struct limen__import_light {
    uint32_t name;              /* the node that carries it */
    uint32_t type;              /* assimp's aiLightSourceType (1 directional, 2 point, 3 spot) */
    float pos[3];               /* in that node's frame */
    float colour[3];            /* diffuse colour times intensity */
    float range;                /* 0: none given */
} limen__import_light;

typedef struct limen__import {
    uint32_t magic, version;    /* LIMEN__IMPORT_MAGIC, LIMEN__IMPORT_VERSION */
    uint64_t size;              /* bytes of the whole block */
    uint32_t vertex_flags;      /* LIMEN__VERT_* */
    uint32_t nverts, ntris, nparts, nmaterials, ntextures, nnodes, nnode_parts, ncameras,
             nlights, nwarnings;
    uint32_t pad;
    uint64_t verts;             /* offsets from the block's start: limen__import_vertex[nverts] */
    uint64_t tris;              /* uint32_t[ntris * 3], each part's from 0 */
    uint64_t parts;             /* limen__import_part[nparts] */
    uint64_t materials;         /* limen__import_material[nmaterials] */
    uint64_t textures;          /* limen__import_texture[ntextures] */
    uint64_t nodes;             /* limen__import_node[nnodes] */
    uint64_t node_parts;        /* uint32_t[nnode_parts]: part indices */
    uint64_t cameras;           /* limen__import_camera[ncameras] */
    uint64_t lights;            /* limen__import_light[nlights] */
    uint64_t warnings;          /* uint32_t[nwarnings]: string offsets */
    uint64_t strings;           /* start of the strings (NUL-terminated); a string offset
                                 * counts from here */
    uint64_t strings_size;
} limen__import;

/* Reads path through assimp into a new block (*out, free() it), refusing one that would
 * hold more than max_bytes. Texture files the model names are read and decoded into it
 * (unless flags has LIMEN__IMPORT_NO_TEXTURES). Fails with a message in why (naming the
 * file) for a file that cannot be read or has no triangles; problems that leave a usable
 * model (a texture missing or misplaced, points and lines skipped) are warnings in it. */
limen_status limen__import_file(const char *path, unsigned flags, size_t max_bytes,
                                limen__import **out, char *why, size_t why_size);

/* Checks a block received from elsewhere: magic, version, every offset and count inside
 * size, every index in range, strings terminated. false if any is not. */
bool limen__import_valid(const limen__import *b, size_t size);

/* Typed views of a block's arrays. */
#define LIMEN__IMP(b, field, type) ((type *)(void *)((unsigned char *)(b) + (b)->field))
const char *limen__import_string(const limen__import *b, uint32_t off);    /* "" for NONE */

/* The way in for every file an import reads (core/confine.c): while set (by core/mesh.c, on
 * the importing thread), assimp opens files through io, and the textures a model names are
 * read through read (the whole file, at most max bytes; NULL if refused) and looked for
 * through exists. inside: the import runs in a contained child, one thread: no lock. */
struct aiFileIO;
typedef struct limen__import_files {
    struct aiFileIO *io;
    void *ctx;
    unsigned char *(*read)(void *ctx, const char *path, size_t max, size_t *len);
    bool (*exists)(void *ctx, const char *path);
    bool inside;
} limen__import_files;
extern _Thread_local const limen__import_files *limen__import_files_hook;

#endif
