/* collide.c - bodies that collide: spheres and capsules swept through the scene and its
 * portals (limen_sweep_sphere, limen_sweep_capsule), and nodes that collide and slide
 * (limen_node_slide).
 *
 * Every collider is cut into convex pieces: polygons (box faces, planes, mirrors, closed
 * portals, mesh triangles, and the parts of these that a portal's hole leaves), balls
 * (spheres) and capped cylinders, whose first contact with the moving body core/contact.c
 * finds exactly. A path is cut where the body's centre crosses a portal's rectangle (it goes on
 * from the partner, turned and scaled), and where it crosses an open portal's plane (the
 * holes and the partner's side, which the rule in limen.h ties to that side, change there). */
#include <stdlib.h>
#include <string.h>

#include "core/contact.h"
#include "core/dmath.h"
#include "core/index.h"
#include "core/internal.h"
#include "core/mesh.h"
#include "core/reserve.h"

#define MAXV LIMEN__PIECE_MAXV
#define MAX_CROSSINGS 64    /* portals one sweep may pass, whatever the limits say */
#define MAX_SPLITS 32       /* plane crossings that cut one segment */
#define SLIDE_ITERATIONS 5  /* collide-and-slide rounds per step */
#define FLUSH_PIECES 4096   /* pieces held at once while gathering */
#define FEW_SHAPES 32       /* a sweep's box with no more shapes is gathered in one go */
#define PLANE_EPS 1e-7      /* scene units: a centre this near a portal's plane is on it */

typedef limen__piece piece;
typedef limen__body body;

/* An open portal near a segment: its plane, side planes and matrix. */
typedef struct gate {
    int slot, partner;
    double plane[4];            /* front = +Z */
    double side[5][4];          /* the outside of its rectangle's prism: x >= w/2, ..., and
                                 * beyond the body's reach behind it */
    double pside[5][4];         /* the partner's front prism: inside = all >= 0 */
    double x[16], xinv[16];     /* into the partner, and back */
    double k;                   /* scale of x */
} gate;

typedef struct contact {
    bool hit;
    double t, point[3], normal[3];
    int node;
} contact;

typedef struct sweeper {
    limen_scene *s;
    limen__spatial *idx;
    limen_limits lim;
    int ignore;                 /* slot whose subtree does not collide, or -1 */
    int *hits;
    int nhits, hits_cap;
    piece *pc;
    int npc, pc_cap;
    bool oom;
    /* while gathering: the contacts the pieces gathered so far are tested for when there
     * are FLUSH_PIECES of them (a long sweep across a big mesh holds no more) */
    const body *fbd;
    double fta, ftb;
    const gate *fghost;
    contact *fbest;
} sweeper;


/* ------------------------------------------------------------------ pieces */

static void closest_contact(const body *bd, const piece *pcs, int npc, double t0, double t1,
                            const gate *ghost, contact *best);

static piece *piece_add(sweeper *w, int kind, int node)
{
    if (w->npc >= FLUSH_PIECES && w->fbest) {
        closest_contact(w->fbd, w->pc, w->npc, w->fta, w->ftb, w->fghost, w->fbest);
        w->npc = 0;
    }
    if (!limen__reserve((void **)&w->pc, &w->pc_cap, w->npc + 1, sizeof *w->pc)) {
        w->oom = true;
        return NULL;
    }
    piece *p = &w->pc[w->npc++];
    p->kind = kind;
    p->node = node;
    p->nv = 0;
    return p;
}

/* Keeps the part of the polygon where plane . p >= 0 (limen__d_clip3 into MAXV vertices);
 * false when nothing is left. */
static bool clip_poly(const double (*in)[3], int n, const double plane[4], double (*out)[3],
                      int *m)
{
    *m = limen__d_clip3(in, n, plane, out, MAXV - 1);
    return *m >= 3;
}

/* Adds a polygon less the holes of the gates (the prism behind each rectangle): the union
 * of its parts outside each of the prism's five sides, one piece each. */
static void add_poly(sweeper *w, int node, const double (*v)[3], int n, const gate *const *holes,
                     int nholes)
{
    if (nholes == 0) {
        piece *p = piece_add(w, LIMEN__PIECE_POLY, node);
        if (p) {
            memcpy(p->v, v, sizeof(double) * 3 * (size_t)n);
            p->nv = n;
            limen__piece_normal(p, p->n);
        }
        return;
    }
    const gate *g = holes[0];
    const double *outs[6] = { g->plane, g->side[0], g->side[1], g->side[2], g->side[3],
                              g->side[4] };
    /* whole unless it meets the prism (as a polygon with area) */
    double a[MAXV][3], b[MAXV][3];
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    int m = n;
    bool meets = true;
    for (int i = 0; i < 6 && meets; i++) {
        double in[4] = { -outs[i][0], -outs[i][1], -outs[i][2], -outs[i][3] };
        meets = clip_poly((const double(*)[3])a, m, in, b, &m);
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
    if (!meets) {
        add_poly(w, node, v, n, holes + 1, nholes - 1);
        return;
    }
    /* the polygon less the prism, in disjoint parts: what lies outside the first side,
     * then of the rest what lies outside the second, ... (what is left is inside) */
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    m = n;
    for (int i = 0; i < 6; i++) {
        double out[MAXV][3];
        int k;
        if (clip_poly((const double(*)[3])a, m, outs[i], out, &k))
            add_poly(w, node, (const double(*)[3])out, k, holes + 1, nholes - 1);
        double in[4] = { -outs[i][0], -outs[i][1], -outs[i][2], -outs[i][3] };
        if (!clip_poly((const double(*)[3])a, m, in, b, &m))
            return;
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
}

/* Adds a polygon cut to the partner's front prism (what a ghost may touch). */
static void add_poly_ghost(sweeper *w, int node, const double (*v)[3], int n, const gate *g)
{
    double a[MAXV][3], b[MAXV][3];
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    int m = n;
    for (int i = 0; i < 5; i++) {
        if (!clip_poly((const double(*)[3])a, m, g->pside[i], b, &m))
            return;
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
    add_poly(w, node, (const double(*)[3])a, m, NULL, 0);
}

/* Adds a polygon of node `node`, first cut to the query box q (a contact lies within the
 * body's reach of its path, so inside q: the cut changes no contact, and keeps the
 * polygon's parts, and the holes it meets, few): for a ghost, cut to the partner's prism;
 * else less the holes. */
static void add_poly_in(sweeper *w, int node, const double (*v)[3], int n, const limen__box *q,
                        const gate *ghost, const gate *const *holes, int nholes)
{
    double a[MAXV][3], b[MAXV][3];
    memcpy(a, v, sizeof(double) * 3 * (size_t)n);
    int m = n;
    for (int i = 0; i < 6; i++) {
        double pl[4] = { 0, 0, 0, 0 };
        int axis = i >> 1;
        pl[axis] = i & 1 ? -1 : 1;
        pl[3] = i & 1 ? q->hi[axis] : -q->lo[axis];
        if (!clip_poly((const double(*)[3])a, m, pl, b, &m))
            return;
        memcpy(a, b, sizeof(double) * 3 * (size_t)m);
    }
    if (ghost)
        add_poly_ghost(w, node, (const double(*)[3])a, m, ghost);
    else
        add_poly(w, node, (const double(*)[3])a, m, holes, nholes);
}

static bool in_subtree(const limen_scene *s, int slot, int root)
{
    for (int guard = 0; slot >= 0 && guard < 4096; guard++) {
        if (slot == root)
            return true;
        slot = (int)s->nodes[slot].parent - 1;
    }
    return false;
}

static bool open_portal(const limen_scene *s, const limen__node *n)
{
    return n->kind == LIMEN_NODE_PORTAL && n->pair && s->nodes[n->pair - 1].visible &&
           n->dims[0] > 0 && n->dims[1] > 0;
}

/* A polygon, ball or cylinder from a node, in world space; ghost g (or NULL) keeps only
 * what lies in its partner's front prism, holes cut the others. */
static void add_node(sweeper *w, int slot, const limen__box *q, const gate *ghost,
                     const gate *const *holes, int nholes)
{
    const limen__node *n = &w->s->nodes[slot];
    double m[16];
    limen__d_from_f(&n->world[0][0], m);
    /* by the kind's unit shape, its dims as the row's scale says (core/kinds.c) */
    const limen_kind_info *ki = limen_kind_get(n->kind);
    const int *dim = ki->scale;
    switch (ki->unit) {
    case LIMEN_UNIT_BALL:
    case LIMEN_UNIT_CYLINDER: {
        bool ball = ki->unit == LIMEN_UNIT_BALL;
        double sc = 0;
        for (int c = 0; c < 3; c++)
            if (ball || c != 1)
                sc = fmax(sc, sqrt(m[c * 4] * m[c * 4] + m[c * 4 + 1] * m[c * 4 + 1] +
                                   m[c * 4 + 2] * m[c * 4 + 2]));
        double o[3] = { 0, 0, 0 }, c[3], up[3] = { m[4], m[5], m[6] }, ly = len3(up);
        limen__d_point(m, o, c);
        if (!ball && !(ly > 0))
            return;
        piece *p = piece_add(w, ball ? LIMEN__PIECE_BALL : LIMEN__PIECE_CYL, slot);
        if (!p)
            return;
        memcpy(p->c, c, sizeof c);
        p->r = n->dims[dim[0]] * sc;
        if (!ball) {
            for (int k = 0; k < 3; k++)
                p->axis[k] = up[k] / ly;
            p->h = n->dims[dim[1]] * ly;
        }
        return;
    }
    case LIMEN_UNIT_BOX: {
        static const int faces[6][4] = { { 0, 2, 6, 4 }, { 1, 5, 7, 3 }, { 0, 4, 5, 1 },
                                         { 2, 3, 7, 6 }, { 0, 1, 3, 2 }, { 4, 6, 7, 5 } };
        double c8[8][3];
        for (int i = 0; i < 8; i++) {
            double l[3] = { (i & 1 ? 0.5 : -0.5) * n->dims[dim[0]],
                            (i & 2 ? 0.5 : -0.5) * n->dims[dim[1]],
                            (i & 4 ? 0.5 : -0.5) * n->dims[dim[2]] };
            limen__d_point(m, l, c8[i]);
        }
        for (int f = 0; f < 6; f++) {
            double fv[4][3];
            for (int i = 0; i < 4; i++)
                memcpy(fv[i], c8[faces[f][i]], sizeof fv[i]);
            add_poly_in(w, slot, (const double(*)[3])fv, 4, q, ghost, holes, nholes);
        }
        return;
    }
    case LIMEN_UNIT_SQUARE: {  /* (w, h) = dims[0], dims[1], as limen__surface_corners has it */
        double fv[4][3];
        limen__surface_corners(n, fv);
        add_poly_in(w, slot, (const double(*)[3])fv, 4, q, ghost, holes, nholes);
        return;
    }
    case LIMEN_UNIT_NONE:      /* a mesh's triangles, where it has some */
    case LIMEN_UNIT_COUNT: {
        const limen__mesh *me = n->mesh;
        if (!me || !me->ntris || !limen__mesh_hierarchy(me))
            return;
        /* the query box in the mesh's frame: the local box of its eight corners */
        double inv[16], lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
        if (!limen__d_inv(m, inv))
            return;
        for (int i = 0; i < 8; i++) {
            double p[3] = { i & 1 ? q->hi[0] : q->lo[0], i & 2 ? q->hi[1] : q->lo[1],
                            i & 4 ? q->hi[2] : q->lo[2] }, l[3];
            limen__d_point(inv, p, l);
            for (int k = 0; k < 3; k++) {
                lo[k] = fmin(lo[k], l[k]);
                hi[k] = fmax(hi[k], l[k]);
            }
        }
        uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const limen__tri_node *tn = &me->bvh[stack[--top]];
            bool meets = true;
            for (int k = 0; k < 3; k++)
                if (tn->hi[k] < lo[k] || tn->lo[k] > hi[k])
                    meets = false;
            if (!meets)
                continue;
            if (tn->count == 0) {
                if (top + 2 > 64)
                    continue;
                stack[top++] = tn->index;
                stack[top++] = (uint32_t)(tn - me->bvh) + 1u;
                continue;
            }
            for (uint32_t i = tn->index; i < tn->index + tn->count; i++) {
                uint32_t tri = me->tri_order[i];
                double tv[3][3];
                for (int c = 0; c < 3; c++) {
                    const float *pf = &me->pos[3 * me->idx[3 * tri + c]];
                    double l[3] = { pf[0], pf[1], pf[2] };
                    limen__d_point(m, l, tv[c]);
                }
                add_poly_in(w, slot, (const double(*)[3])tv, 3, q, ghost, holes, nholes);
            }
        }
        return;
    }
    }
}

/* ------------------------------------------------------------------ gates */

static bool gate_make(limen_scene *s, int slot, double reach, gate *g)
{
    const limen__node *n = &s->nodes[slot], *p = &s->nodes[n->pair - 1];
    if (!limen__surface_matrix_d(s, n, g->x) || !limen__d_inv(g->x, g->xinv))
        return false;
    for (int i = 0; i < 16; i++)
        if (!isfinite(g->x[i]) || !isfinite(g->xinv[i]))
            return false;
    g->slot = slot;
    g->partner = (int)n->pair - 1;
    g->k = sqrt(g->x[0] * g->x[0] + g->x[1] * g->x[1] + g->x[2] * g->x[2]);
    limen__surface_plane_d(n, g->plane);
    /* side planes: local x = +-w/2, y = +-h/2, facing outwards, carried by the world matrix
     * (a plane transforms by the inverse transpose) */
    const limen__node *ns[2] = { n, p };
    for (int e = 0; e < 2; e++) {
        double w[16], winv[16];
        limen__d_from_f(&ns[e]->world[0][0], w);
        if (!limen__d_inv(w, winv))
            return false;
        double hx = 0.5 * ns[e]->dims[0], hy = 0.5 * ns[e]->dims[1];
        double loc[4][4] = { { 1, 0, 0, -hx }, { -1, 0, 0, -hx }, { 0, 1, 0, -hy },
                             { 0, -1, 0, -hy } };
        for (int i = 0; i < 4; i++) {
            double out[4];
            if (e == 1)     /* the partner's prism: inside, so the planes face in */
                for (int k = 0; k < 3; k++)
                    loc[i][k] = -loc[i][k];
            if (e == 1)
                loc[i][3] = -loc[i][3];
            if (!limen__d_plane(winv, loc[i], out))
                return false;
            memcpy(e == 0 ? g->side[i] : g->pside[i], out, sizeof out);
        }
    }
    limen__surface_plane_d(p, g->pside[4]);
    for (int k = 0; k < 3; k++)
        g->side[4][k] = -g->plane[k];
    g->side[4][3] = -g->plane[3] - reach;
    return true;
}

/* Where the reference point crosses the gate's rectangle from the front, on (t0, t1]. */
static bool gate_crossing(const gate *g, const limen__node *n, const double a[3],
                          const double v[3], double t0, double t1, double *t_out)
{
    double p0[3], p1[3];
    mad3(a, t0, v, p0);
    mad3(a, t1, v, p1);
    double d0 = limen__d_plane_dist(g->plane, p0), d1 = limen__d_plane_dist(g->plane, p1);
    if (!(d0 > 0 && d1 <= 0))
        return false;
    double f = d0 / (d0 - d1), t = t0 + f * (t1 - t0), hit[3], w[16], winv[16], local[3];
    mad3(p0, f, (double[3]){ p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] }, hit);
    limen__d_from_f(&n->world[0][0], w);
    if (!limen__d_inv(w, winv))
        return false;
    limen__d_point(winv, hit, local);
    if (!(fabs(local[0]) <= 0.5 * n->dims[0] && fabs(local[1]) <= 0.5 * n->dims[1]))
        return false;
    *t_out = t;
    return true;
}

/* ------------------------------------------------------------------ one segment */

static void sweep_box(const body *bd, double t0, double t1, double pad, limen__box *b)
{
    limen__box_empty(b);
    const double *ends[2] = { bd->a, bd->b };
    for (int e = 0; e < (bd->capsule ? 2 : 1); e++) {
        for (int k = 0; k < 3; k++) {
            double x0 = ends[e][k] + t0 * bd->v[k], x1 = ends[e][k] + t1 * bd->v[k];
            b->lo[k] = fmin(b->lo[k], fmin(x0, x1) - pad);
            b->hi[k] = fmax(b->hi[k], fmax(x0, x1) + pad);
        }
    }
}

static bool collides(const sweeper *w, int slot)
{
    const limen__node *n = &w->s->nodes[slot];
    return limen__alive(n) && n->visible && (w->ignore < 0 || !in_subtree(w->s, slot, w->ignore));
}

/* Pieces of the shapes and walls meeting box q: primary (holes cut by `holes`), or ghost's. */
static bool gather(sweeper *w, const limen__box *q, const gate *ghost, const gate *const *holes,
                   int nholes, int passed)
{
    w->npc = 0;
    const limen__bvh *trees[2] = { limen__index_shapes(w->idx), limen__index_surfaces(w->idx) };
    for (int tr = 0; tr < 2; tr++) {
        w->nhits = 0;
        if (limen__bvh_query_box(trees[tr], q, &w->hits, &w->nhits, &w->hits_cap, NULL) < 0)
            return false;
        for (int i = 0; i < w->nhits; i++) {
            int slot = w->hits[i];
            if (!collides(w, slot))
                continue;
            const limen__node *n = &w->s->nodes[slot];
            /* an open portal within the limits is an opening, not a wall */
            if (n->kind == LIMEN_NODE_PORTAL && open_portal(w->s, n) &&
                passed + 1 <= limen__limits_depth(&w->lim, n->max_depth))
                continue;
            add_node(w, slot, q, ghost, holes, nholes);
        }
    }
    return !w->oom;
}

/* The earliest contact with the pieces on [t0, t1]; for a ghost, a ball's or a cylinder's
 * contact counts only where it lies in the partner's front prism. */
static void closest_contact(const body *bd, const piece *pcs, int npc, double t0, double t1,
                            const gate *ghost, contact *best)
{
    for (int i = 0; i < npc; i++) {
        double t;
        if (!limen__piece_contact(bd, &pcs[i], t0, best->hit ? fmin(t1, best->t) : t1, &t))
            continue;
        if (best->hit && t >= best->t)
            continue;
        double pb[3], pk[3];
        limen__body_dist(bd, t, &pcs[i], pb, pk);
        if (ghost && pcs[i].kind != LIMEN__PIECE_POLY) {
            bool in = true;
            for (int k = 0; k < 5; k++)
                in &= limen__d_plane_dist(ghost->pside[k], pk) >= 0;
            if (!in)
                continue;
        }
        best->hit = true;
        best->t = t;
        best->node = pcs[i].node;
        memcpy(best->point, pk, sizeof pk);
        double nrm[3];
        sub3(pb, pk, nrm);
        double l = len3(nrm);
        if (l > 1e-300) {
            for (int k = 0; k < 3; k++)
                best->normal[k] = nrm[k] / l;
        } else {
            double vl = len3(bd->v);
            for (int k = 0; k < 3; k++)
                best->normal[k] = vl > 0 ? -bd->v[k] / vl : (k == 1);
        }
    }
}

static void body_ref(const body *bd, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = bd->ref_a ? bd->a[k] : 0.5 * (bd->a[k] + bd->b[k]);
}

/* How far the body reaches from its reference point. */
static double body_reach(const body *bd)
{
    return bd->r + (bd->ref_a ? 1.0 : 0.5) * dist3(bd->a, bd->b);
}

static void body_carry(const double x[16], double k, const body *in, body *out)
{
    body b = *in;
    limen__d_point(x, in->a, b.a);
    limen__d_point(x, in->b, b.b);
    vec_d(x, in->v, b.v);
    b.r = in->r * k;
    *out = b;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Sweeps the body over [t0, t1] in one room: gates are the open portals near it. */
static bool sweep_segment(sweeper *w, const body *bd, double t0, double t1, gate *gates,
                          int ngates, int passed, contact *best)
{
    double ref[3], cuts[MAX_SPLITS + 2];
    int ncuts = 0;
    body_ref(bd, ref);
    cuts[ncuts++] = t0;
    for (int i = 0; i < ngates && ncuts < MAX_SPLITS; i++) {
        /* a centre within PLANE_EPS of a plane at either end does not cross it there:
         * rounding (a body just out of a portal sits on its partner's plane) makes no
         * sliver of an interval */
        double p0[3], p1[3];
        mad3(ref, t0, bd->v, p0);
        mad3(ref, t1, bd->v, p1);
        double d0 = limen__d_plane_dist(gates[i].plane, p0);
        double d1 = limen__d_plane_dist(gates[i].plane, p1);
        if ((d0 > PLANE_EPS && d1 < -PLANE_EPS) || (d0 < -PLANE_EPS && d1 > PLANE_EPS))
            cuts[ncuts++] = t0 + (t1 - t0) * d0 / (d0 - d1);
    }
    qsort(cuts + 1, (size_t)(ncuts - 1), sizeof *cuts, cmp_double);
    cuts[ncuts++] = t1;
    double reach = body_reach(bd);
    for (int c = 0; c + 1 < ncuts; c++) {
        double ta = cuts[c], tb = cuts[c + 1], mid[3];
        if (!(tb >= ta))
            continue;
        mad3(ref, 0.5 * (ta + tb), bd->v, mid);
        const gate *front[MAX_SPLITS];
        int nfront = 0;
        for (int i = 0; i < ngates && nfront < MAX_SPLITS; i++)
            if (limen__d_plane_dist(gates[i].plane, mid) > 0)
                front[nfront++] = &gates[i];
        /* a long stretch whose box holds many shapes goes in pieces a few reaches long,
         * nearest first: the cost follows the path, not the box around it, and ends at the
         * first contact (a box of few shapes is cheaper gathered once) */
        double len = len3(bd->v) * (tb - ta), piece_len = 4 * reach;
        int nch = len > piece_len ? (int)fmin(ceil(len / piece_len), 16) : 1;
        if (nch > 1) {
            limen__box all;
            sweep_box(bd, ta, tb, reach, &all);
            w->nhits = 0;
            if (limen__bvh_query_box(limen__index_shapes(w->idx), &all, &w->hits, &w->nhits,
                                     &w->hits_cap, NULL) < 0)
                return false;
            if (w->nhits <= FEW_SHAPES)
                nch = 1;
        }
        for (int h = 0; h < nch; h++) {
            double ca = ta + (tb - ta) * h / nch;
            double cb = h + 1 == nch ? tb : ta + (tb - ta) * (h + 1) / nch;
            limen__box q;
            sweep_box(bd, ca, cb, reach, &q);
            w->fbd = bd;
            w->fta = ca;
            w->ftb = cb;
            w->fghost = NULL;
            w->fbest = best;
            bool ok = gather(w, &q, NULL, front, nfront, passed);
            w->fbest = NULL;
            if (!ok)
                return false;
            closest_contact(bd, w->pc, w->npc, ca, cb, NULL, best);
            /* the part of the body through each opening, in the partner's room */
            for (int i = 0; i < nfront; i++) {
                const gate *g = front[i];
                body gb;
                body_carry(g->x, g->k, bd, &gb);
                limen__box gq, pq;
                sweep_box(&gb, ca, cb, body_reach(&gb), &gq);
                /* only the partner's front prism, as deep as the body reaches */
                limen__node_box(&w->s->nodes[g->partner], &pq);
                double pad = reach * g->k;
                bool empty = false;
                for (int k = 0; k < 3; k++) {
                    gq.lo[k] = fmax(gq.lo[k], pq.lo[k] - pad);
                    gq.hi[k] = fmin(gq.hi[k], pq.hi[k] + pad);
                    empty |= gq.lo[k] > gq.hi[k];
                }
                if (empty)
                    continue;
                contact gc = { 0 };
                gc.t = best->hit ? best->t : INFINITY;
                double gcb = best->hit ? fmin(cb, best->t) : cb;
                w->fbd = &gb;
                w->fta = ca;
                w->ftb = gcb;
                w->fghost = g;
                w->fbest = &gc;
                bool gok = gather(w, &gq, g, NULL, 0, passed);
                w->fbest = NULL;
                if (!gok)
                    return false;
                closest_contact(&gb, w->pc, w->npc, ca, gcb, g, &gc);
                if (gc.node >= 0 && gc.hit && (!best->hit || gc.t < best->t)) {
                    best->hit = true;
                    best->t = gc.t;
                    best->node = gc.node;
                    limen__d_point(g->xinv, gc.point, best->point);
                    vec_d(g->xinv, gc.normal, best->normal);
                    double l = len3(best->normal);
                    for (int k = 0; k < 3; k++)
                        best->normal[k] /= l;
                }
            }
            if (best->hit)
                return true;
        }
    }
    return true;
}

/* ------------------------------------------------------------------ sweeps */

typedef struct sweep_out {
    contact c;
    double centre[3];           /* reference point at the end (contact or path's end) */
    double total[16];           /* portals' product */
    double r;                   /* radius at the end */
    double seg[3];              /* capsule: b - a at the end */
    int crossed, last;
} sweep_out;

static limen_status sweep_run(limen_scene *s, const char *who, body bd, int ignore,
                              const limen_limits *limits, sweep_out *out)
{
    sweeper w = { .s = s, .ignore = ignore };
    limen_status st = limen__limits_resolve(s, who, limits, &w.lim);
    if (st)
        return st;
    /* not limen__scene_check, which walks every node to check the scales of cameras and
     * surfaces: a sweep costs what its path meets (a portal whose matrix is not finite is
     * a wall, gate_make) */
    limen__scene_refresh(s);
    if (s->dirty)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", who);
    int bad = limen__scene_bad_world(s);
    if (bad >= 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: '%s': its world transform is not finite (the "
                           "scales along its parent chain multiply past what a float holds)",
                           who, limen__node_title(&s->nodes[bad]));
    w.idx = limen__scene_index(s);
    if (!w.idx)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", who);
    memset(out, 0, sizeof *out);
    limen__d_identity(out->total);
    out->last = -1;
    out->c.node = -1;
    double t0 = 0;
    gate gates[MAX_SPLITS];
    for (;;) {
        /* open portals near the rest of the path */
        int ngates = 0;
        double reach = body_reach(&bd);
        limen__box q;
        sweep_box(&bd, t0, 1, 2 * reach, &q);
        w.nhits = 0;
        if (limen__bvh_query_box(limen__index_surfaces(w.idx), &q, &w.hits, &w.nhits,
                                 &w.hits_cap, NULL) < 0) {
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", who);
            break;
        }
        int best_gate = -1;
        double tp = 1;
        double ref[3];
        body_ref(&bd, ref);
        for (int i = 0; i < w.nhits && ngates < MAX_SPLITS; i++) {
            int slot = w.hits[i];
            const limen__node *n = &s->nodes[slot];
            if (!collides(&w, slot) || !open_portal(s, n) ||
                out->crossed + 1 > limen__limits_depth(&w.lim, n->max_depth) ||
                out->crossed >= MAX_CROSSINGS)
                continue;
            if (!gate_make(s, slot, reach, &gates[ngates]))
                continue;
            double t;
            if (gate_crossing(&gates[ngates], n, ref, bd.v, t0, 1, &t) && t < tp) {
                tp = t;
                best_gate = ngates;
            }
            ngates++;
        }
        double t1 = best_gate >= 0 ? tp : 1;
        if (!sweep_segment(&w, &bd, t0, t1, gates, ngates, out->crossed, &out->c)) {
            st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", who);
            break;
        }
        if (out->c.hit || best_gate < 0)
            break;
        const gate *g = &gates[best_gate];
        body_carry(g->x, g->k, &bd, &bd);
        limen__d_mul(g->x, out->total, out->total);
        out->crossed++;
        out->last = g->slot;
        t0 = tp;
    }
    if (!st) {
        double t = out->c.hit ? out->c.t : 1, ref[3];
        body_ref(&bd, ref);
        mad3(ref, t, bd.v, out->centre);
        out->r = bd.r;
        sub3(bd.b, bd.a, out->seg);
    }
    free(w.hits);
    free(w.pc);
    return st;
}

static bool finite_in(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]) || fabsf(v[i]) > LIMEN_MAX_MAGNITUDE)
            return false;
    return true;
}

static void fill_result(limen_scene *s, const sweep_out *o, limen_sweep_result *out)
{
    memset(out, 0, sizeof *out);
    out->hit = o->c.hit;
    out->fraction = o->c.hit ? (float)o->c.t : 1.0f;
    for (int k = 0; k < 3; k++) {
        out->centre[k] = (float)o->centre[k];
        out->point[k] = o->c.hit ? (float)o->c.point[k] : 0;
        out->normal[k] = o->c.hit ? (float)o->c.normal[k] : 0;
        out->segment[k] = (float)o->seg[k];
    }
    out->node = o->c.hit && o->c.node >= 0 ? limen__node_handle(s, o->c.node) : (limen_node){ 0 };
    out->portals = o->crossed;
    out->portal = o->last >= 0 ? limen__node_handle(s, o->last) : (limen_node){ 0 };
    limen__d_to_f(o->total, out->matrix);
    out->radius = (float)o->r;
}

static limen_status check_opts(limen_scene *s, const char *who, const limen_sweep_opts *opts,
                               int *ignore)
{
    *ignore = -1;
    if (opts && opts->ignore.id) {
        if (!limen__node_get(s, opts->ignore))
            return limen__fail(s, LIMEN_ERR_HANDLE, "%s: ignore: stale node handle", who);
        *ignore = limen__node_get_index(opts->ignore);
    }
    return LIMEN_OK;
}

limen_status limen_sweep_sphere(limen_scene *s, const float from[3], const float to[3],
                                float radius, const limen_sweep_opts *opts,
                                limen_sweep_result *out)
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!from || !to || !out)
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_sphere: NULL argument");
    if (!finite_in(from, 3) || !finite_in(to, 3))
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_sphere: from and to need three numbers "
                           "from -1e9 to 1e9");
    if (!(radius >= LIMEN_MIN_SIZE && radius <= LIMEN_MAX_MAGNITUDE))
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_sphere: radius must be a positive number "
                           "from 1e-9 to 1e9 (got %g)", (double)radius);
    int ignore;
    limen_status st = check_opts(s, "sweep_sphere", opts, &ignore);
    if (st)
        return st;
    body bd = { .r = radius };
    for (int k = 0; k < 3; k++) {
        bd.a[k] = bd.b[k] = from[k];
        bd.v[k] = (double)to[k] - from[k];
    }
    sweep_out o;
    st = sweep_run(s, "sweep_sphere", bd, ignore, opts ? &opts->limits : NULL, &o);
    if (st)
        return st;
    fill_result(s, &o, out);
    return LIMEN_OK;
}

limen_status limen_sweep_capsule(limen_scene *s, const float a[3], const float b[3],
                                 float radius, const float d[3], const limen_sweep_opts *opts,
                                 limen_sweep_result *out)
{
    if (!s)
        return LIMEN_ERR_ARG;
    if (!a || !b || !d || !out)
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_capsule: NULL argument");
    if (!finite_in(a, 3) || !finite_in(b, 3) || !finite_in(d, 3))
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_capsule: a, b and the displacement need "
                           "three numbers from -1e9 to 1e9");
    if (!(radius >= LIMEN_MIN_SIZE && radius <= LIMEN_MAX_MAGNITUDE))
        return limen__fail(s, LIMEN_ERR_ARG, "sweep_capsule: radius must be a positive number "
                           "from 1e-9 to 1e9 (got %g)", (double)radius);
    int ignore;
    limen_status st = check_opts(s, "sweep_capsule", opts, &ignore);
    if (st)
        return st;
    body bd = { .r = radius, .capsule = true };
    for (int k = 0; k < 3; k++) {
        bd.a[k] = a[k];
        bd.b[k] = b[k];
        bd.v[k] = d[k];
    }
    sweep_out o;
    st = sweep_run(s, "sweep_capsule", bd, ignore, opts ? &opts->limits : NULL, &o);
    if (st)
        return st;
    fill_result(s, &o, out);
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ sliding */

static limen_status slide(limen_scene *s, limen_node n, const float d[3], float radius,
                          const float *seg, limen_slide_result *out)
{
    if (out) {
        memset(out, 0, sizeof *out);
        out->matrix[0] = out->matrix[5] = out->matrix[10] = out->matrix[15] = 1.0f;
    }
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, "slide", &node);
    if (found)
        return found;
    if (!d || !finite_in(d, 3))
        return limen__fail(s, LIMEN_ERR_ARG, "slide: displacement needs three numbers from "
                           "-1e9 to 1e9");
    if (!(radius >= LIMEN_MIN_SIZE && radius <= LIMEN_MAX_MAGNITUDE))
        return limen__fail(s, LIMEN_ERR_ARG, "slide: radius must be a positive number from "
                           "1e-9 to 1e9 (got %g)", (double)radius);
    if (seg && !finite_in(seg, 3))
        return limen__fail(s, LIMEN_ERR_ARG, "slide: the capsule's segment needs three numbers "
                           "from -1e9 to 1e9");
    double axis[3] = { seg ? seg[0] : 0, seg ? seg[1] : 0, seg ? seg[2] : 0 };
    double rest[3] = { d[0], d[1], d[2] }, total[16], moved[3] = { 0, 0, 0 }, r = radius;
    limen__d_identity(total);
    int contacts = 0, crossed = 0;
    limen_node last = { 0 };
    double lastn[3] = { 0, 0, 0 };
    int slot = limen__node_get_index(n);
    for (int it = 0; it < SLIDE_ITERATIONS; it++) {
        double len = len3(rest);
        if (!(len > 1e-12 * fmax(1.0, r)))
            break;
        limen__scene_refresh(s);
        body bd = { .r = r, .capsule = seg != NULL, .ref_a = true };
        for (int k = 0; k < 3; k++) {
            bd.a[k] = node->world[3][k];
            bd.b[k] = bd.a[k] + axis[k];
            bd.v[k] = rest[k];
        }
        sweep_out o;
        limen_status st = sweep_run(s, "slide", bd, slot, NULL, &o);
        if (st)
            return st;
        double f = o.c.hit ? o.c.t : 1;
        double skin = 1e-4 * r;
        if (o.c.hit) {
            /* stop short by a skin, measured along the normal, so the next round starts
             * clear of what it touched */
            double vn[3];
            vec_d(o.total, rest, vn);
            double along = -dot3(vn, o.c.normal);
            f = along > 0 ? fmax(0, f - skin / along) : f;
        }
        float step[3] = { (float)(f * rest[0]), (float)(f * rest[1]), (float)(f * rest[2]) };
        limen_move_result mr;
        st = limen_node_move(s, n, step, &mr);
        if (st)
            return st;
        double inv[16], m[16];
        limen__d_from_f(mr.matrix, m);
        /* displacement made, in the frame where the slide began */
        if (!limen__d_inv(total, inv))
            limen__d_identity(inv);
        double sd[3] = { step[0], step[1], step[2] }, back[3];
        vec_d(inv, sd, back);
        for (int k = 0; k < 3; k++)
            moved[k] += back[k];
        if (mr.crossed) {
            crossed += mr.crossed;
            last = mr.portal;
            limen__d_mul(m, total, total);
            r *= sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            vec_d(m, axis, axis);
        }
        double left[3];
        for (int k = 0; k < 3; k++)
            left[k] = (1 - f) * rest[k];
        vec_d(m, left, rest);
        if (!o.c.hit)
            break;
        contacts++;
        if (mr.crossed != o.crossed)
            continue;       /* stopped short of the portal the contact lies beyond */
        memcpy(lastn, o.c.normal, sizeof lastn);
        /* slide: the rest of the motion less its part into the contact plane */
        double into = dot3(rest, o.c.normal);
        if (into < 0)
            mad3(rest, -into, o.c.normal, rest);
    }
    if (out) {
        for (int k = 0; k < 3; k++) {
            out->moved[k] = (float)moved[k];
            out->normal[k] = (float)lastn[k];
        }
        out->contacts = contacts;
        out->crossed = crossed;
        out->portal = last;
        limen__d_to_f(total, out->matrix);
        out->radius = (float)r;
        for (int k = 0; k < 3; k++)
            out->segment[k] = (float)axis[k];
    }
    return LIMEN_OK;
}

limen_status limen_node_slide(limen_scene *s, limen_node n, const float d[3], float radius,
                              limen_slide_result *out)
{
    return slide(s, n, d, radius, NULL, out);
}

limen_status limen_node_slide_capsule(limen_scene *s, limen_node n, const float d[3],
                                      float radius, const float segment[3],
                                      limen_slide_result *out)
{
    if (s && !segment)
        return limen__fail(s, LIMEN_ERR_ARG, "slide: NULL segment");
    return slide(s, n, d, radius, segment, out);
}
