/* lod.c - which level of detail of a mesh a view draws. */
#include <math.h>

#include "limen.h"

int limen_view_mesh_lod(const limen_view *v, int height, const limen_drawable *d, float pixels)
{
    if (!v || !d || d->kind != LIMEN_NODE_MESH || !d->mesh || d->mesh->lod_count < 2 ||
        height < 1 || pixels == LIMEN_LOD_FULL || !(pixels >= 0))
        return 0;
    if (pixels == 0)
        pixels = 1;
    /* pixels per unit at distance 1, and the view's own unit (a view through scaled portals
     * scales distances) */
    double px_scale = (double)v->proj[5] * 0.5 * height;
    const float *m = v->view;
    double view_scale = sqrt((double)m[0] * m[0] + (double)m[1] * m[1] + (double)m[2] * m[2]);
    const float *c = d->centre;
    double depth = -((double)m[2] * c[0] + (double)m[6] * c[1] + (double)m[10] * c[2] + m[14]);
    double r = (double)d->radius * view_scale;
    /* the nearest depth of the bounding sphere; an eye inside its slab sees the full mesh */
    double nearest = depth - r;
    if (!(nearest > 0) || !(px_scale > 0))
        return 0;
    /* the node's largest stretch carries the mesh's local error into the world */
    const float *w = d->world;
    double stretch = 0;
    for (int a = 0; a < 3; a++)
        stretch = fmax(stretch, sqrt((double)w[a * 4] * w[a * 4] + (double)w[a * 4 + 1] * w[a * 4 + 1] +
                                     (double)w[a * 4 + 2] * w[a * 4 + 2]));
    double to_px = stretch * view_scale * px_scale / nearest;
    for (int k = d->mesh->lod_count - 1; k > 0; k--)
        if ((double)d->mesh->lods[k].error * to_px <= pixels)
            return k;
    return 0;
}
