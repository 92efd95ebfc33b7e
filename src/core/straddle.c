/* straddle.c - closed shapes passing through a portal. Such a shape is drawn twice: itself,
 * cut at the entry portal's plane, and a copy carried by the portal matrix, cut at the
 * partner's plane, so that what has gone in shows coming out. The planner, the renderer and
 * the ray tracer all take the list from here. */
#include "core/dmath.h"
#include "core/internal.h"
#include "core/mesh.h"

void limen__node_bounds(const limen__node *n, double centre[3], double *radius)
{
    double local[3] = { 0, 0, 0 }, r;
    switch (n->kind) {
    case LIMEN_NODE_BOX:
        r = 0.5 * sqrt((double)n->dims[0] * n->dims[0] + (double)n->dims[1] * n->dims[1] +
                       (double)n->dims[2] * n->dims[2]);
        break;
    case LIMEN_NODE_SPHERE: r = n->dims[0]; break;
    case LIMEN_NODE_CYLINDER:
        local[1] = 0.5 * n->dims[1];
        r = sqrt((double)n->dims[0] * n->dims[0] + local[1] * local[1]);
        break;
    case LIMEN_NODE_MESH: {
        double h2 = 0;
        for (int a = 0; n->mesh && a < 3; a++) {
            local[a] = 0.5 * (n->mesh->lo[a] + n->mesh->hi[a]);
            h2 += 0.25 * (n->mesh->hi[a] - n->mesh->lo[a]) * (n->mesh->hi[a] - n->mesh->lo[a]);
        }
        r = sqrt(h2);
        break;
    }
    default: r = 0.5 * sqrt((double)n->dims[0] * n->dims[0] + (double)n->dims[1] * n->dims[1]);
    }
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

int limen__find_straddlers(limen_scene *s, int *portal_of)
{
    limen__scene_refresh(s);
    int count = 0;
    for (int i = 0; i < s->cap; i++) {
        portal_of[i] = -1;
        const limen__node *n = &s->nodes[i];
        if (!limen__alive(n) || !n->visible ||
            (n->kind != LIMEN_NODE_BOX && n->kind != LIMEN_NODE_SPHERE &&
             n->kind != LIMEN_NODE_CYLINDER && !(n->kind == LIMEN_NODE_MESH && n->mesh)))
            continue;
        for (int j = 0; j < s->cap; j++) {
            const limen__node *a = &s->nodes[j];
            if (!limen__alive(a) || !a->visible || a->kind != LIMEN_NODE_PORTAL || !a->pair ||
                !s->nodes[a->pair - 1].visible || !straddles(n, a))
                continue;
            portal_of[i] = j;
            count++;
            break;
        }
    }
    return count;
}
