/* straddle.c - closed shapes passing through a portal. Such a shape is drawn twice: itself,
 * cut at the entry portal's plane, and a copy carried by the portal matrix, cut at the
 * partner's plane, so that what has gone in shows coming out. The planner, the renderer and
 * the ray tracer all take the list from here. */
#include <stdlib.h>

#include "core/dmath.h"
#include "core/index.h"
#include "core/internal.h"
#include "core/kinds.h"
#include "core/mesh.h"

void limen__node_bounds(const limen__node *n, double centre[3], double *radius)
{
    double lo[3], hi[3], local[3], r;
    limen__node_extent(n, lo, hi);
    limen__kind_sphere(n->kind, lo, hi, local, &r);
    double w[16];
    limen__d_from_f(&n->world[0][0], w);
    limen__d_point(w, local, centre);
    double stretch = 0;
    for (int c = 0; c < 3; c++)
        stretch = fmax(stretch, sqrt(w[c * 4] * w[c * 4] + w[c * 4 + 1] * w[c * 4 + 1] +
                                     w[c * 4 + 2] * w[c * 4 + 2]));
    *radius = r * stretch;
}

/* Does closed shape n pass through portal a? Its bounding sphere must cross a's plane, with
 * its centre over a's rectangle, and be small enough to fit through. */
static bool straddles(const limen__node *n, const limen__node *a)
{
    double c[3], r, plane[4];
    limen__node_bounds(n, c, &r);
    limen__surface_plane_d(a, plane);
    if (!(fabs(limen__d_plane_dist(plane, c)) < r))
        return false;
    double w[16], winv[16], local[3];
    limen__d_from_f(&a->world[0][0], w);
    if (!limen__d_inv(w, winv))
        return false;
    limen__d_point(winv, c, local);
    double hw = 0.5 * a->dims[0], hh = 0.5 * a->dims[1];
    double sx = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    return fabs(local[0]) <= hw && fabs(local[1]) <= hh && r <= sx * sqrt(hw * hw + hh * hh);
}

/* A shape with a volume (not flat; a mesh once it has triangles). */
static bool closed_shape(const limen__node *n)
{
    const limen_kind_info *ki = limen_kind_get(n->kind);
    return limen__alive(n) && n->visible && ki->shape && !ki->flat &&
           (ki->unit || n->mesh);
}

static bool open_portal(const limen_scene *s, const limen__node *a)
{
    return limen__alive(a) && a->visible && a->kind == LIMEN_NODE_PORTAL && a->pair &&
           s->nodes[a->pair - 1].visible;
}

/* Every shape against every portal: what the index must reproduce (tests compare). */
static int find_all_pairs(limen_scene *s, int *portal_of)
{
    int count = 0;
    for (int i = 0; i < s->cap; i++) {
        if (!closed_shape(&s->nodes[i]))
            continue;
        for (int j = 0; j < s->cap; j++) {
            if (!open_portal(s, &s->nodes[j]))
                continue;
            s->straddle_tests++;
            if (!straddles(&s->nodes[i], &s->nodes[j]))
                continue;
            portal_of[i] = j;
            count++;
            break;
        }
    }
    return count;
}

int limen__find_straddlers(limen_scene *s, int *portal_of)
{
    limen__scene_refresh(s);
    for (int i = 0; i < s->cap; i++)
        portal_of[i] = -1;
    limen__spatial *x = s->brute_force ? NULL : limen__scene_index(s);
    if (!x)
        return find_all_pairs(s, portal_of);
    /* A shape passing through a portal has its bounding sphere meet the portal's rectangle,
     * so its box meets the rectangle's box: ask the index, portal by portal in slot order,
     * so that a shape through two portals takes the first, as the scan above does. */
    const int *portals;
    int nportals = limen__index_portals(x, &portals), count = 0, *hits = NULL, cap = 0;
    for (int pi = 0; pi < nportals; pi++) {
        const limen__node *a = &s->nodes[portals[pi]];
        if (!open_portal(s, a))
            continue;
        limen__box q;
        limen__node_box(a, &q);
        int n = 0;
        if (limen__bvh_query_box(limen__index_shapes(x), &q, &hits, &n, &cap, NULL) < 0) {
            free(hits);
            for (int i = 0; i < s->cap; i++)
                portal_of[i] = -1;
            return find_all_pairs(s, portal_of);
        }
        for (int k = 0; k < n; k++) {
            int i = hits[k];
            if (portal_of[i] >= 0 || !closed_shape(&s->nodes[i]))
                continue;
            s->straddle_tests++;
            if (!straddles(&s->nodes[i], a))
                continue;
            portal_of[i] = portals[pi];
            count++;
        }
    }
    free(hits);
    return count;
}
