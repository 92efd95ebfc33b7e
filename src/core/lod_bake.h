/* lod_bake.h - a textured mesh's coarse levels of detail with a texture of their own
 * (core/lod_bake.c). Not part of the public API. */
#ifndef LIMEN_CORE_LOD_BAKE_H
#define LIMEN_CORE_LOD_BAKE_H

#include <stdbool.h>
#include <stdint.h>

#include "core/lod_target.h"
#include "core/mesh.h"

#define LIMEN__BAKE_MAX_TRIS 65536      /* a level baked has at most this many triangles */

/* Whether m's coarse levels may be baked: it has texture coordinates and some material a
 * base or emissive texture of its own, and every material is opaque (a baked level has one
 * opaque material). */
bool limen__lod_bakeable(const limen__mesh *m);

/* Level (ntris triangles idx over m's vertices, error geo against m's surface) as a mesh of
 * its own: each triangle in a square of a new texture (a multiple of 4 texels a side, the
 * fewest that space its texels on it within a quarter of geo where the texture's size
 * allows: core/lod_bake.c), every texel the colour (albedo, as the material shades it;
 * emission in a second texture where some material emits) of the full surface at the point
 * nearest to the texel's point on the level, sampled in the full image. full: m's surface with its hierarchy
 * (core/lod_target.h); shadow: per corner of m (m->idx), the vertex at its position that
 * the weld by position keeps (a level's corner takes the normal of the vertex there facing
 * most as its triangle). Its one material's base colour is white, its textures the baked
 * ones; normals from m. *reach: how far, in m's units, the colour a point of the level
 * shows may come from: geo plus how far apart on the level lie the texels the renderer
 * blends there (the level's error; the same for the same geometry and geo). NULL when out
 * of memory. */
limen__mesh *limen__lod_bake(const limen__mesh *m, const limen__lod_target *full,
                             const uint32_t *shadow, const uint32_t *idx, uint32_t ntris,
                             double geo, double *reach);

/* Frees a baked level (its arrays and textures). */
void limen__lod_baked_free(limen__mesh *b);

#endif
