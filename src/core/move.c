/* move.c - moving nodes, and carrying them through portals they pass. */
#include <string.h>

#include "core/dmath.h"
#include "core/internal.h"

#define MAX_CROSSINGS 8

/* Earliest portal whose rectangle the segment p0 -> p1 enters from the front; its index and
 * the segment parameter, or -1. */
static int first_crossing(limen_scene *s, const double p0[3], const double p1[3], double *t_out)
{
    int best = -1;
    double best_t = 2.0;
    for (int li = 0; li < s->live_len; li++) {
        int i = s->live[li];
        if (i < 0)
            continue;
        const limen__node *n = &s->nodes[i];
        if (!n->visible || n->kind != LIMEN_NODE_PORTAL || !n->pair ||
            !s->nodes[n->pair - 1].visible)
            continue;
        double plane[4];
        limen__surface_plane_d(n, plane);
        double d0 = limen__d_plane_dist(plane, p0), d1 = limen__d_plane_dist(plane, p1);
        if (!(d0 > 0 && d1 <= 0))
            continue;
        double t = d0 / (d0 - d1);
        if (t >= best_t)
            continue;
        /* inside the rectangle? look at the crossing point in the portal's frame */
        double w[16], winv[16], hit[3], local[3];
        limen__d_from_f(&n->world[0][0], w);
        if (!limen__d_inv(w, winv))
            continue;
        for (int k = 0; k < 3; k++)
            hit[k] = p0[k] + t * (p1[k] - p0[k]);
        limen__d_point(winv, hit, local);
        if (fabs(local[0]) <= 0.5 * n->dims[0] && fabs(local[1]) <= 0.5 * n->dims[1]) {
            best = i;
            best_t = t;
        }
    }
    *t_out = best_t;
    return best;
}

/* Sets the node's local transform from a world matrix (no shear: T R S). */
static limen_status set_world(limen_scene *s, limen__node *node, const double world[16])
{
    double local[16];
    memcpy(local, world, sizeof local);
    if (node->parent) {
        double pw[16], pinv[16];
        limen__d_from_f(&s->nodes[node->parent - 1].world[0][0], pw);
        if (!limen__d_inv(pw, pinv))
            return limen__fail(s, LIMEN_ERR_DEGENERATE, "move: parent of '%s' is singular",
                               limen__node_title(node));
        limen__d_mul(pinv, world, local);
    }
    double sc[3];
    for (int c = 0; c < 3; c++) {
        sc[c] = sqrt(local[c * 4] * local[c * 4] + local[c * 4 + 1] * local[c * 4 + 1] +
                     local[c * 4 + 2] * local[c * 4 + 2]);
        if (!(sc[c] > 1e-12))
            return limen__fail(s, LIMEN_ERR_DEGENERATE, "move: '%s' would collapse",
                               limen__node_title(node));
    }
    double det = local[0] * (local[5] * local[10] - local[9] * local[6]) -
                 local[4] * (local[1] * local[10] - local[9] * local[2]) +
                 local[8] * (local[1] * local[6] - local[5] * local[2]);
    if (det < 0)
        sc[2] = -sc[2];
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++)
            node->facing[c][r] = (float)(local[c * 4 + r] / sc[c]);
        node->scale[c] = (float)sc[c];
        node->pos[c] = (float)local[12 + c];
    }
    glm_vec3_zero(node->euler);
    node->explicit_local = false;
    limen__node_touch(s, node);
    return LIMEN_OK;
}

limen_status limen_node_move(limen_scene *s, limen_node n, const float d[3],
                             limen_move_result *out)
{
    if (out) {
        memset(out, 0, sizeof *out);
        out->matrix[0] = out->matrix[5] = out->matrix[10] = out->matrix[15] = 1.0f;
    }
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, "move", &node);
    if (found)
        return found;
    if (!d || !limen__finite3(d) || fabsf(d[0]) > LIMEN_MAX_MAGNITUDE ||
        fabsf(d[1]) > LIMEN_MAX_MAGNITUDE || fabsf(d[2]) > LIMEN_MAX_MAGNITUDE)
        return limen__fail(s, LIMEN_ERR_ARG, "move: displacement needs three numbers from -1e9 "
                           "to 1e9");
    limen__scene_refresh(s);
    double world[16], total[16], step[3] = { d[0], d[1], d[2] };
    limen__d_from_f(&node->world[0][0], world);
    limen__d_identity(total);
    int crossed = 0, last = -1;
    for (;;) {
        double p0[3] = { world[12], world[13], world[14] }, p1[3], t;
        for (int k = 0; k < 3; k++)
            p1[k] = p0[k] + step[k];
        int portal = crossed < MAX_CROSSINGS ? first_crossing(s, p0, p1, &t) : -1;
        if (portal < 0) {
            for (int k = 0; k < 3; k++)
                world[12 + k] = p1[k];
            break;
        }
        /* up to the portal, then through it: W' = X W, the rest of the step turned by X */
        double x[16];
        if (!limen__surface_matrix_d(s, &s->nodes[portal], x))
            return limen__fail(s, LIMEN_ERR_DEGENERATE, "move: portal '%s' is degenerate",
                               limen__node_title(&s->nodes[portal]));
        for (int k = 0; k < 3; k++)
            world[12 + k] = p0[k] + t * step[k];
        limen__d_mul(x, world, world);
        double rest[3];
        for (int k = 0; k < 3; k++)
            rest[k] = (1.0 - t) * step[k];
        for (int k = 0; k < 3; k++)
            step[k] = x[k] * rest[0] + x[4 + k] * rest[1] + x[8 + k] * rest[2];
        limen__d_mul(x, total, total);
        crossed++;
        last = portal;
    }
    limen_status st = set_world(s, node, world);
    if (st)
        return st;
    if (out) {
        out->crossed = crossed;
        out->portal = last >= 0 ? limen__node_handle(s, last) : (limen_node){ 0 };
        limen__d_to_f(total, out->matrix);
    }
    return LIMEN_OK;
}
