/* surface.c - mirrors and portals: their properties, pairing, planes and the matrices that
 * carry the eye through them. */
#include <string.h>

#include "core/dmath.h"
#include "core/internal.h"

#define SURFACES (LIMEN__KIND(LIMEN_NODE_MIRROR) | LIMEN__KIND(LIMEN_NODE_PORTAL))

/* The mirror or portal of handle n, for fn (a message naming fn where it is not one). */
static limen_status surface_lookup(limen_scene *s, limen_node n, const char *fn,
                                   limen__node **out)
{
    return limen__node_lookup(s, n, SURFACES, "a mirror or a portal", fn, out);
}

static limen_status set_rgb(limen_scene *s, limen_node n, const float rgb[3], const char *what,
                            size_t offset)
{
    limen__node *node;
    limen_status found = surface_lookup(s, n, what, &node);
    if (found)
        return found;
    if (!rgb || !limen__finite3(rgb))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: needs three finite numbers", what);
    for (int i = 0; i < 3; i++)
        if (rgb[i] < 0 || rgb[i] > 1)
            return limen__fail(s, LIMEN_ERR_ARG, "%s: components must be in [0, 1] (got %g)",
                               what, rgb[i]);
    memcpy((char *)node + offset, rgb, sizeof(float) * 3);
    return LIMEN_OK;
}

limen_status limen_surface_set_tint(limen_scene *s, limen_node n, const float rgb[3])
{
    return set_rgb(s, n, rgb, "tint", offsetof(limen__node, tint));
}

limen_status limen_surface_set_back(limen_scene *s, limen_node n, const float rgb[3])
{
    return set_rgb(s, n, rgb, "back", offsetof(limen__node, back));
}

limen_status limen_surface_set_fill(limen_scene *s, limen_node n, const float rgb[3])
{
    return set_rgb(s, n, rgb, "fill", offsetof(limen__node, fill));
}

limen_status limen_surface_set_max_depth(limen_scene *s, limen_node n, int max_depth)
{
    limen__node *node;
    limen_status found = surface_lookup(s, n, "max_depth", &node);
    if (found)
        return found;
    if (max_depth < 0 || max_depth > 255)
        return limen__fail(s, LIMEN_ERR_ARG, "max_depth: must be in [0, 255] (got %d)",
                           max_depth);
    node->max_depth = max_depth;    /* per end: views through this end only */
    return LIMEN_OK;
}

limen_status limen_surface_get(const limen_scene *s, limen_node n, float tint[3], float back[3],
                               float fill[3], int *max_depth)
{
    const limen__node *node;                            /* a const reader never writes */
    limen_status found = limen__node_lookup_const(s, n, SURFACES, &node);
    if (found)
        return found;
    if (tint)
        memcpy(tint, node->tint, sizeof(float) * 3);
    if (back)
        memcpy(back, node->back, sizeof(float) * 3);
    if (fill)
        memcpy(fill, node->fill, sizeof(float) * 3);
    if (max_depth)
        *max_depth = node->max_depth;
    return LIMEN_OK;
}

limen_status limen_portal_link(limen_scene *s, limen_node a, limen_node b)
{
    limen__node *na, *nb;
    limen_status found = surface_lookup(s, a, "portal_link", &na);
    if (found || (found = surface_lookup(s, b, "portal_link", &nb)))
        return found;
    if (na->kind != LIMEN_NODE_PORTAL || nb->kind != LIMEN_NODE_PORTAL)
        return limen__fail(s, LIMEN_ERR_ARG, "portal_link: '%s' is a mirror, not a portal",
                           limen__node_title(na->kind != LIMEN_NODE_PORTAL ? na : nb));
    if (na == nb)
        return limen__fail(s, LIMEN_ERR_ARG, "%s%sportal '%s' cannot be paired with itself",
                           na->label, na->label[0] ? ": " : "", limen__node_title(na));
    double ra = (double)na->dims[0] / na->dims[1], rb = (double)nb->dims[0] / nb->dims[1];
    if (fabs(ra / rb - 1.0) > 1e-3)
        return limen__fail(s, LIMEN_ERR_ARG,
                           "%s%sportals '%s' (%gx%g) and '%s' (%gx%g) differ in shape: their "
                           "width/height ratios must match",
                           na->label, na->label[0] ? ": " : "", limen__node_title(na), na->dims[0],
                           na->dims[1], limen__node_title(nb), nb->dims[0], nb->dims[1]);
    if (na->pair)
        s->nodes[na->pair - 1].pair = 0;
    if (nb->pair)
        s->nodes[nb->pair - 1].pair = 0;
    na->pair = (uint32_t)limen__index(s, nb) + 1u;
    nb->pair = (uint32_t)limen__index(s, na) + 1u;
    return LIMEN_OK;
}

limen_node limen_portal_get_partner(const limen_scene *s, limen_node portal)
{
    const limen__node *node;
    if (limen__node_lookup_const(s, portal, LIMEN__KIND(LIMEN_NODE_PORTAL), &node) || !node->pair)
        return (limen_node){ 0 };
    return limen__node_handle(s, (int)node->pair - 1);
}

/* ------------------------------------------------------------------ geometry */

void limen__surface_plane_d(const limen__node *n, double plane[4])
{
    double w[16], winv[16];
    limen__d_from_f(&n->world[0][0], w);
    const double local[4] = { 0, 0, 1, 0 };
    if (!limen__d_inv(w, winv) || !limen__d_plane(winv, local, plane)) {
        plane[0] = plane[1] = plane[3] = 0;
        plane[2] = 1;
        return;
    }
}

void limen__surface_corners(const limen__node *n, double corners[4][3])
{
    double w[16];
    limen__d_from_f(&n->world[0][0], w);
    const double hx = 0.5 * n->dims[0], hy = 0.5 * n->dims[1];
    const double local[4][3] = { { -hx, -hy, 0 }, { hx, -hy, 0 }, { hx, hy, 0 }, { -hx, hy, 0 } };
    for (int i = 0; i < 4; i++)
        limen__d_point(w, local[i], corners[i]);
}

bool limen__surface_matrix_d(limen_scene *s, const limen__node *n, double x[16])
{
    if (n->kind == LIMEN_NODE_MIRROR) {
        /* The reflection about the world plane: I - 2 n n^T, translation -2 d n. Built from
         * the plane rather than as W F W^-1 so that it stays a true reflection under any
         * parent transform. */
        double p[4];
        limen__surface_plane_d(n, p);
        limen__d_identity(x);
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++)
                x[c * 4 + r] -= 2.0 * p[r] * p[c];
        for (int r = 0; r < 3; r++)
            x[12 + r] = -2.0 * p[3] * p[r];
        return true;
    }
    if (n->kind != LIMEN_NODE_PORTAL || !n->pair)
        return false;
    const limen__node *b = &s->nodes[n->pair - 1];
    /* X = W_B * R_y(180) * S(k) * W_A^-1, k = width_B / width_A */
    double wa[16], wb[16], wainv[16], m[16];
    limen__d_from_f(&n->world[0][0], wa);
    limen__d_from_f(&b->world[0][0], wb);
    if (!limen__d_inv(wa, wainv))
        return false;
    double k = (double)b->dims[0] / (double)n->dims[0];
    limen__d_identity(m);
    m[0] = -k;
    m[5] = k;
    m[10] = -k;
    limen__d_mul(wb, m, m);
    limen__d_mul(m, wainv, x);
    return true;
}

limen_status limen_surface_matrix(limen_scene *s, limen_node n, float m[16])
{
    limen__node *node;
    limen_status found = surface_lookup(s, n, "surface_matrix", &node);
    if (found)
        return found;
    if (!m)
        return LIMEN_ERR_ARG;
    limen__scene_refresh(s);
    double x[16];
    if (!limen__surface_matrix_d(s, node, x))
        return limen__fail(s, LIMEN_ERR_DEGENERATE, "surface_matrix: portal '%s' is %s",
                           limen__node_title(node), node->pair ? "degenerate" : "not paired");
    limen__d_to_f(x, m);
    return LIMEN_OK;
}
