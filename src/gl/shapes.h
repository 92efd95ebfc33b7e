/* shapes.h - unit meshes for the primitives, with levels of detail for curved ones. */
#ifndef LIMEN_SHAPES_H
#define LIMEN_SHAPES_H

#include <stdint.h>

#define LIMEN__LODS 11

typedef struct limen__vertex { float pos[3], nrm[3]; } limen__vertex;
typedef struct limen__range { uint32_t first, count; } limen__range;   /* in indices */

typedef struct limen__meshes {
    limen__vertex *verts;
    uint32_t *idx;
    uint32_t nverts, nidx;
    limen__range box;                       /* [-0.5, 0.5]^3 */
    limen__range quad;                      /* [-0.5, 0.5]^2 on z = 0, facing +Z */
    limen__range sphere[LIMEN__LODS];       /* radius 1 */
    limen__range cylinder[LIMEN__LODS];     /* radius 1, y in [0, 1], capped */
} limen__meshes;

extern const int limen__lod_segments[LIMEN__LODS];

int limen__meshes_build(limen__meshes *m);     /* 0 or -1 (out of memory) */
void limen__meshes_free(limen__meshes *m);

#endif
