/* kinds.c - the facts of each node kind in one table (limen_kind_info), and the extents and
 * bounding spheres every layer computes from them: the index's boxes, the straddling test's
 * and the drawables' spheres, limen_node_get_bounds, the tracer's unit spheres. A new kind
 * is a row here; its geometry (the tracer's intersection, the renderer's unit mesh,
 * collision) is written where that layer keeps the others'. */
#include <math.h>

#include "core/internal.h"
#include "core/kinds.h"
#include "core/mesh.h"

/* Unit shapes: a local box [lo, hi] stretched along axis a by dims[scale[a]] (or 1). */
static const limen_kind_info kinds[] = {
    [LIMEN_NODE_GROUP] = { .name = "group", .scale = { -1, -1, -1 } },
    [LIMEN_NODE_BOX] = { .name = "box", .size = 3, .dims = { 1, 1, 1 }, .shape = 1,
                         .unit = LIMEN_UNIT_BOX, .closed = 1, .uv = LIMEN_UV_BOX,
                         .scale = { 0, 1, 2 }, .lo = { -0.5f, -0.5f, -0.5f },
                         .hi = { 0.5f, 0.5f, 0.5f } },
    [LIMEN_NODE_SPHERE] = { .name = "sphere", .size = 1, .dims = { 0.5f, 0, 0 }, .shape = 1,
                            .unit = LIMEN_UNIT_BALL, .closed = 1, .round = 2,
                            .scale = { 0, 0, 0 }, .lo = { -1, -1, -1 }, .hi = { 1, 1, 1 } },
    [LIMEN_NODE_CYLINDER] = { .name = "cylinder", .size = 2, .dims = { 0.5f, 1, 0 }, .shape = 1,
                              .unit = LIMEN_UNIT_CYLINDER, .closed = 1, .round = 1, .axis = 1,
                              .scale = { 0, 1, 0 }, .lo = { -1, 0, -1 }, .hi = { 1, 1, 1 } },
    [LIMEN_NODE_QUAD] = { .name = "plane", .size = 2, .dims = { 1, 1, 0 }, .shape = 1,
                          .unit = LIMEN_UNIT_SQUARE, .flat = 1, .uv = LIMEN_UV_PLANE,
                          .scale = { 0, 1, -1 }, .lo = { -0.5f, -0.5f, 0 },
                          .hi = { 0.5f, 0.5f, 0 } },
    [LIMEN_NODE_MIRROR] = { .name = "mirror", .size = 2, .dims = { 1, 1, 0 }, .surface = 1,
                            .unit = LIMEN_UNIT_SQUARE, .flat = 1, .scale = { 0, 1, -1 },
                            .lo = { -0.5f, -0.5f, 0 }, .hi = { 0.5f, 0.5f, 0 } },
    [LIMEN_NODE_PORTAL] = { .name = "portal", .size = 2, .dims = { 1, 1, 0 }, .surface = 1,
                            .unit = LIMEN_UNIT_SQUARE, .flat = 1, .scale = { 0, 1, -1 },
                            .lo = { -0.5f, -0.5f, 0 }, .hi = { 0.5f, 0.5f, 0 } },
    [LIMEN_NODE_LIGHT] = { .name = "light", .light = 1, .scale = { -1, -1, -1 } },
    [LIMEN_NODE_CAMERA] = { .name = "camera", .scale = { -1, -1, -1 } },
    [LIMEN_NODE_MESH] = { .name = "mesh", .shape = 1, .uv = LIMEN_UV_MESH,
                          .scale = { -1, -1, -1 } },
};
_Static_assert(sizeof kinds / sizeof kinds[0] == LIMEN_NODE_KIND_COUNT,
               "src/core/kinds.c: one row per limen_node_kind");

const limen_kind_info *limen_kind_get(limen_node_kind k)
{
    return (unsigned)k < LIMEN_NODE_KIND_COUNT ? &kinds[k] : NULL;
}

const char *limen__kind_name(limen_node_kind k)
{
    return (unsigned)k < LIMEN_NODE_KIND_COUNT ? kinds[k].name : "node";
}

limen_status limen_kind_bounds(limen_node_kind k, const float dims[3], float lo[3], float hi[3])
{
    const limen_kind_info *ki = limen_kind_get(k);
    if (!ki || !ki->unit || !dims || !lo || !hi)
        return LIMEN_ERR_ARG;
    for (int a = 0; a < 3; a++) {
        float s = ki->scale[a] >= 0 ? dims[ki->scale[a]] : 1.0f;
        lo[a] = ki->lo[a] * s;
        hi[a] = ki->hi[a] * s;
    }
    return LIMEN_OK;
}

void limen__node_extent(const limen__node *n, double lo[3], double hi[3])
{
    float flo[3] = { 0, 0, 0 }, fhi[3] = { 0, 0, 0 };
    if (n->kind == LIMEN_NODE_MESH) {
        for (int a = 0; a < 3; a++) {
            lo[a] = n->mesh ? n->mesh->lo[a] : 0;
            hi[a] = n->mesh ? n->mesh->hi[a] : 0;
        }
        return;
    }
    limen_kind_bounds(n->kind, n->dims, flo, fhi);     /* a point where it is no shape */
    for (int a = 0; a < 3; a++) {
        lo[a] = flo[a];
        hi[a] = fhi[a];
    }
}

void limen__kind_sphere(limen_node_kind k, const double lo[3], const double hi[3],
                        double centre[3], double *radius)
{
    const limen_kind_info *ki = limen_kind_get(k);
    double h[3];
    for (int a = 0; a < 3; a++) {
        centre[a] = 0.5 * (lo[a] + hi[a]);
        h[a] = 0.5 * (hi[a] - lo[a]);
    }
    switch (ki ? ki->round : 0) {
    case 2: *radius = fmax(h[0], fmax(h[1], h[2])); break;
    case 1: {
        int a = ki->axis;
        double r = fmax(h[(a + 1) % 3], h[(a + 2) % 3]);
        *radius = sqrt(r * r + h[a] * h[a]);
        break;
    }
    default: *radius = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]); break;
    }
}
