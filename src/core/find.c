/* find.c - finding nodes below a node by name (limen_node_find_below) and measuring what a
 * node and those below it show (limen_node_get_bounds): what a script asks of a model it
 * loaded (core/model.c), and of any group. */
#include <math.h>
#include <string.h>

#include "core/internal.h"

static bool below(const limen_scene *s, limen_node n, limen_node root)
{
    for (int depth = 0; n.id && depth < 100000; depth++) {
        n = limen_node_get_parent(s, n);
        if (n.id == root.id)
            return true;
    }
    return false;
}

limen_status limen_node_find_below(const limen_scene *s, limen_node root, const char *name,
                                   limen_node *out)
{
    if (!s || !name || !out)
        return LIMEN_ERR_ARG;
    out->id = 0;
    if (!limen_node_valid(s, root))
        return LIMEN_ERR_HANDLE;
    const limen__node *nodes = s->nodes;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0 || strcmp(nodes[i].name, name) != 0)
            continue;
        limen_node h = limen__node_handle(s, i);
        if (below(s, h, root)) {
            *out = h;
            return LIMEN_OK;
        }
    }
    return LIMEN_ERR_HANDLE;
}

/* Grows box lo/hi by the unit box [a, b] mapped through world matrix w. */
static void grow_box(const float w[16], const float a[3], const float b[3], float lo[3],
                     float hi[3])
{
    for (int c = 0; c < 8; c++) {
        float p[3] = { c & 1 ? b[0] : a[0], c & 2 ? b[1] : a[1], c & 4 ? b[2] : a[2] };
        for (int k = 0; k < 3; k++) {
            float v = w[k] * p[0] + w[4 + k] * p[1] + w[8 + k] * p[2] + w[12 + k];
            lo[k] = fminf(lo[k], v);
            hi[k] = fmaxf(hi[k], v);
        }
    }
}

/* The local box of what node n shows; false for what shows nothing (groups, lights,
 * cameras, a mesh without triangles). */
static bool shape_box(limen_scene *s, limen_node n, float a[3], float b[3])
{
    float d[3];
    limen_node_get_dims(s, n, d);
    limen_node_kind k = limen_node_get_kind(s, n);
    if (k == LIMEN_NODE_MESH) {
        limen_mesh_info mi;
        if (limen_mesh_get(s, n, &mi) || mi.triangle_count < 1)
            return false;
        memcpy(a, mi.lo, sizeof mi.lo);
        memcpy(b, mi.hi, sizeof mi.hi);
        return true;
    }
    return limen_kind_bounds(k, d, a, b) == LIMEN_OK;
}

limen_status limen_node_get_bounds(limen_scene *s, limen_node n, float lo[3], float hi[3])
{
    if (!s || !lo || !hi)
        return LIMEN_ERR_ARG;
    if (!limen_node_valid(s, n))
        return limen__fail(s, LIMEN_ERR_HANDLE, "bounds: %s node handle",
                           n.id ? "stale or foreign" : "null");
    limen_status st = limen_scene_update(s);
    if (st)
        return st;
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    bool any = false;
    for (int k = 0; k < s->live_len; k++) {
        int i = s->live[k];
        if (i < 0)
            continue;
        limen_node h = limen__node_handle(s, i);
        float a[3], b[3], w[16];
        if ((h.id != n.id && !below(s, h, n)) || !shape_box(s, h, a, b) ||
            limen_node_world_matrix(s, h, w))
            continue;
        grow_box(w, a, b, lo, hi);
        any = true;
    }
    if (!any)
        return limen__fail(s, LIMEN_ERR_ARG, "bounds: '%s' shows nothing (no shape in it or "
                           "below it)", limen_node_get_name(s, n)[0] ? limen_node_get_name(s, n)
                                                                     : "the node");
    return LIMEN_OK;
}
