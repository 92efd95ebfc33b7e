/* lod_weld.h - what the simplifier is given and what its levels' corners become
 * (core/lod_weld.c): a mesh welded for it, meshoptimizer's simplifiers over that, one that
 * keeps within the texture's charts (core/lod_charts.c), and each corner's choice among the
 * vertices at its position (its side of a seam in the normals or the texture). Not part of
 * the public API. */
#ifndef LIMEN_CORE_LOD_WELD_H
#define LIMEN_CORE_LOD_WELD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/mesh.h"

/* A mesh the simplifier is given: the distinct vertices of a weld (each corner's vertex
 * replaced by its weld's), their positions packed, numbered in the mesh's order. */
typedef struct limen__lod_welded {
    float *pos;                 /* per packed vertex */
    uint32_t *to;               /* per vertex of the mesh: its packed vertex, or UINT32_MAX */
    uint32_t *from;             /* per packed vertex: the mesh's */
    uint32_t *idx;              /* per corner of the mesh: its weld's vertex, packed */
    float scale;                /* the packed vertices' extent (meshopt_simplifyScale) */
    uint32_t n;
} limen__lod_welded;

/* pk over m welded by weld (per corner of m, a vertex); false when out of memory (pk
 * freed). */
bool limen__lod_pack(limen__lod_welded *pk, const limen__mesh *m, const uint32_t *weld);

/* m welded by position (meshoptimizer's shadow index buffer, the same numbers): per corner,
 * the first vertex met in the corners' order with the same position (bit for bit); false
 * when out of memory. */
bool limen__lod_shadow(const limen__mesh *m, uint32_t *shadow);
void limen__lod_welded_free(limen__lod_welded *pk);
/* meshoptimizer's simplifier (sloppy: its clustering) over pk, from src (n indices into the
 * mesh's vertices, each a vertex of the weld; NULL: the whole mesh) towards want indices
 * and target_error, into out in the mesh's vertices; returns the indices made, *err the
 * simplifier's relative error (not the sloppy one's: err may be NULL there); 0 when out of
 * memory. It only reads pk: two threads may simplify over one pk at once. */
size_t limen__lod_simplify(limen__lod_welded *pk, const uint32_t *src, size_t n, bool sloppy,
                           size_t want, float target_error, float *err, uint32_t *out);
/* The corners of a level (idx, n indices) that name a weld's vertex (shadow: per corner of
 * m, the first vertex at its position) take instead, of the vertices there, the one whose
 * normal is nearest their triangle's; false when out of memory (the corners stay). */
bool limen__lod_seam_sides(const limen__mesh *m, const uint32_t *shadow, uint32_t *idx,
                           size_t n);
/* The corners of a clustered or seam-blind level (idx, n indices, each a vertex of the
 * weld attr) take, of the vertices of attr at their position (shadow), the three of one
 * part (vpart: per vertex, its part; NULL for one part) where they can, whose texture
 * coordinates lie nearest together; false when out of memory (the corners stay). */
bool limen__lod_pick_charts(const limen__mesh *m, const uint32_t *shadow, const uint32_t *attr,
                            const uint32_t *vpart, uint32_t *idx, size_t n);

/* The texture's charts of m (its regions over which the texture is continuous): per vertex
 * of m, a number its chart's vertices share, into chart (m->nverts). Two corners are of one
 * chart where one triangle of m has both, or where attr (per corner of m, its weld by
 * position and texture coordinates) names one vertex for both. */
void limen__lod_charts(const limen__mesh *m, const uint32_t *attr, uint32_t *chart);
/* How many triangles of a level (idx, n indices into the mesh's vertices) have corners of
 * two charts (chart: limen__lod_charts'). */
size_t limen__lod_across_charts(const uint32_t *chart, const uint32_t *idx, size_t n);

/* Where the charts' edges go in the full mesh m (their seams and borders): per vertex named
 * by attr (per corner of m, its weld by position and texture coordinates), the vertices next
 * to it along its chart's edge (the edge's triangle on the left): to[first[v]] up to
 * to[first[v + 1]] (one, or none off the edges; more where edges touch). */
typedef struct limen__lod_rims {
    uint32_t *first, *to;
} limen__lod_rims;

/* r for m and attr; false when out of memory (nothing left allocated). */
bool limen__lod_rims_make(limen__lod_rims *r, const limen__mesh *m, const uint32_t *attr);
void limen__lod_rims_free(limen__lod_rims *r);
/* How far a level (idx, n indices, each a vertex of attr) moves its charts' edges: each edge
 * of a chart in the level (a triangle's edge with none back along it) replaces a path along
 * the full mesh's (r), and the texture of the chart on its left ends at the edge, not the
 * path: between them it shows texels beyond the chart's own. The largest distance of a
 * vertex of such a path from its edge (which bounds the distance of every point between
 * them from the path), INFINITY where an edge follows no such path, NAN when out of
 * memory. */
double limen__lod_rim_drift(const limen__mesh *m, const limen__lod_rims *r,
                            const uint32_t *idx, size_t n);

/* A level within the texture's charts: from src (n indices into the mesh's vertices, NULL:
 * the whole mesh), edge collapses towards want indices over m welded by position (shadow: per
 * corner of m, its weld), each triangle keeping its corners' sides of every seam of the weld
 * attr (texture coordinates, colours, parts), so none takes corners from two charts, while
 * seams and borders simplify as polylines both sides share. Into out (room for n indices) in
 * the mesh's vertices, each a vertex of attr; returns the indices made; *ok false when out of
 * memory. */
size_t limen__lod_simplify_charts(const limen__mesh *m, const uint32_t *shadow,
                                  const uint32_t *attr, const uint32_t *src, size_t n,
                                  size_t want, uint32_t *out, bool *ok);

/* The triangles to ask limen__lod_simplify_charts for, for the level after one of cur
 * triangles, where the charts allow no fewer than floor (its result asked for none) and
 * room triangles are left for the levels to come: half of cur, unless the floor would then
 * lie too close below (above 3/4 of the half: a level refused as stuck), where a step
 * between is asked for, from which the floor is a level of its own; the floor itself where
 * the two do not fit in the room. */
size_t limen__lod_charts_want(size_t cur, size_t floor, size_t room);

#define LIMEN__LOD_SPLIT_ABOVE 524288  /* a source of this many triangles or more is simplified
                                      * in blocks (on two cores); a smaller one on one */

/* A big mesh simplified in blocks (core/lod_split.c): its triangles cut into blocks of
 * about block_tris nearby ones, each simplified alone by meshoptimizer towards its share of
 * want, its border held in place, on two threads where threads. Over pos (nv
 * vertices), from in (n indices), into out (room for n); *err the simplifier's error
 * relative to the extent of pos (the largest of the blocks'), target_error likewise (FLT_MAX:
 * none). Returns the indices made; *ok false when out of memory. The same result on one
 * thread and two. */
size_t limen__lod_simplify_split(const float *pos, uint32_t nv, const uint32_t *in, size_t n,
                                 size_t want, float target_error, float *err, uint32_t *out,
                                 size_t block_tris, bool threads, bool *ok);

#endif
