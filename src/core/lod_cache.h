/* lod_cache.h - levels of detail kept between runs (core/lod_cache.c), keyed by the mesh's
 * content, in the user's cache folder. Not part of the public API. */
#ifndef LIMEN_CORE_LOD_CACHE_H
#define LIMEN_CORE_LOD_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/mesh.h"

/* What the levels of a mesh are made from, hashed: its counts, positions, indices, normals,
 * texture coordinates, vertex colours and parts, and the version of the levels' making
 * (version). */
typedef struct limen__lod_key {
    uint64_t h[2];
} limen__lod_key;

void limen__lod_cache_key(const limen__mesh *m, uint32_t version, limen__lod_key *key);

/* Where entries live, read from the environment once (on the scene's thread: a thread that
 * makes levels is given it, and reads no environment): $LIMEN_CACHE_DIR, else
 * $XDG_CACHE_HOME/limen, else $HOME/.cache/limen; `on` false where the cache is off
 * (LIMEN_CACHE=off, 0 or no) or no folder is known; the size limit from $LIMEN_CACHE_MB
 * (megabytes, fractions allowed; default 256). */
typedef struct limen__lod_where {
    bool on;
    char dir[4096];
    uint64_t limit;             /* bytes */
} limen__lod_where;

void limen__lod_cache_where(limen__lod_where *w);

/* The levels stored under key for a mesh of nverts vertices and ntris triangles: *nlods
 * levels (at most max_levels, the first the full mesh: indices NULL), their triangle counts
 * and errors in lods, and the coarse levels' indices one after another in a block (*block,
 * malloc'd, the caller frees it; the indices from `room` bytes on, suitably aligned where
 * room is a multiple of 8), each checked (counts falling, every index
 * below nverts, errors finite and growing, the whole entry's checksum). False where there
 * is none, or it is not whole and valid (it is then ignored, and the next store replaces
 * it), or memory is out. *baked: the levels stored as baked (bit k: level k; their textures
 * are not stored, but made again from the mesh: core/lod_bake.h). */
bool limen__lod_cache_load(const limen__lod_where *w, const limen__lod_key *key,
                           uint32_t nverts, uint32_t ntris,
                           limen_mesh_lod *lods, uint32_t max_levels, uint32_t *nlods,
                           uint32_t *baked, size_t room, unsigned char **block);

/* Stores nlods levels (lods[k].indices for k >= 1; baked: which are baked, bit k level k)
 * under key in w, written whole or not at all, then trims the folder to w's size limit, the
 * entries used least recently first. Failures are silent: the cache is an aid, never a
 * requirement. */
void limen__lod_cache_store(const limen__lod_where *w, const limen__lod_key *key,
                            uint32_t nverts, uint32_t ntris, const limen_mesh_lod *lods,
                            uint32_t nlods, uint32_t baked);

/* An entry's checksum, of its bytes before the last 8 (which hold it); for tests that make
 * entries whole but wrong. */
uint64_t limen__lod_cache_checksum(const void *data, size_t len);

#endif
