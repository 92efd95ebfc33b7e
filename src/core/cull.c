/* cull.c - what a view can see, asked of the scene's spatial index (core/index.c): the
 * surfaces the planner tests against a view, and the shapes a renderer draws in it (kept in
 * the plan: limen_plan_things).
 *
 * A view's region is the pyramid from its eye through its scissor rectangle (widened by a
 * pixel, so that rounding never loses a pixel centre the planner's exact test would keep),
 * cut by its clip plane below the camera. The index returns every item whose box is not
 * wholly outside one of those planes: a superset of what the exact tests keep, found in
 * time that follows what the view holds rather than what the scene holds. */
#include <stdlib.h>
#include <string.h>

#include "core/dmath.h"
#include "core/index.h"
#include "core/lmath.h"
#include "core/plan.h"
#include "core/reserve.h"

/* The world planes of the view's narrowed region (kept side >= 0); returns their count. */
static int view_planes(const limen_plan *p, const limen__plan_view *v, double planes[5][4])
{
    const int *sc = v->pub.scissor;
    const double window[4] = { 2.0 * (sc[0] - 1) / p->width - 1,
                               2.0 * (sc[0] + sc[2] + 1) / p->width - 1,
                               2.0 * (sc[1] - 1) / p->height - 1,
                               2.0 * (sc[1] + sc[3] + 1) / p->height - 1 };
    /* the sides in eye space: x_ndc = (P0 x + P8 z) / -z, so x_ndc >= xl is
     * P0 x + (P8 + xl) z >= 0 */
    double eye[6][4];
    limen__frustum_planes(p->proj_d, window, p->range, eye);
    int n = 0;
    for (int i = 0; i < 4; i++) {
        /* to world: (e^T V) p, V column-major */
        double w[4], len = 0;
        for (int j = 0; j < 4; j++)
            w[j] = eye[i][0] * v->view[j * 4] + eye[i][1] * v->view[j * 4 + 1] +
                   eye[i][2] * v->view[j * 4 + 2] + eye[i][3] * v->view[j * 4 + 3];
        len = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!(len > 0) || !isfinite(len))
            continue;   /* a degenerate side: leave it out, which keeps more */
        for (int j = 0; j < 4; j++)
            planes[n][j] = w[j] / len;
        n++;
    }
    if (v->pub.depth > 0) {
        const double *c = v->clip;
        double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (len > 0 && isfinite(len)) {
            for (int j = 0; j < 4; j++)
                planes[n][j] = v->clip[j] / len;
            n++;
        }
    }
    return n;
}

/* Slack for plane tests: many times the rounding of distances at the scene's size. */
static double slack_for(const limen__bvh *b, const limen__plan_view *v)
{
    double m = fabs(v->eye[0]) + fabs(v->eye[1]) + fabs(v->eye[2]);
    if (b->nnodes)
        for (int k = 0; k < 3; k++)
            m = fmax(m, fmax(fabs(b->nodes[0].box.lo[k]), fabs(b->nodes[0].box.hi[k])));
    return 1e-9 * (1.0 + m);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int limen__plan_candidates(limen_plan *p, limen_scene *s, const limen__plan_view *v)
{
    limen__spatial *x = limen__scene_index(s);
    if (!x)
        return -1;
    const limen__bvh *b = limen__index_surfaces(x);
    double planes[5][4];
    int np = view_planes(p, v, planes), n = 0;
    if (limen__bvh_query_planes(b, (const double(*)[4])planes, np, slack_for(b, v),
                                &p->candidates, &n, &p->candidates_cap, &p->stat_index) < 0)
        return -1;
    /* node slots to the planner's surface indices, in its order */
    int m = 0;
    for (int i = 0; i < n; i++)
        if (p->surface_of[p->candidates[i]] >= 0)
            p->candidates[m++] = p->surface_of[p->candidates[i]];
    if (m > 1)
        qsort(p->candidates, (size_t)m, sizeof *p->candidates, cmp_int);
    return m;
}

int limen__plan_surface_slots(limen_scene *s, const int **out)
{
    limen__spatial *x = s->brute_force ? NULL : limen__scene_index(s);
    *out = NULL;
    return x ? limen__index_surface_slots(x, out) : s->cap;
}

int limen__plan_view_shapes(limen_plan *p, limen_scene *s, const limen__plan_view *v)
{
    limen__spatial *x = limen__scene_index(s);
    if (!x)
        return -1;
    const limen__bvh *b = limen__index_shapes(x);
    double planes[5][4];
    int np = view_planes(p, v, planes), n = 0;
    if (limen__bvh_query_planes(b, (const double(*)[4])planes, np, slack_for(b, v),
                                &p->shape_hits, &n, &p->shape_hits_cap, NULL) < 0)
        return -1;
    /* in node order, the hidden left out: where the hits are many against the slots, read
     * back from a bitmap of the slots (linear in both), else sorted (each shape is one leaf
     * of the index, so it is hit once) */
    int words = (s->cap + 63) / 64, m = 0;
    if (n > 16 && words <= 4 * n && !p->sort_hits) {
        if (!limen__reserve((void **)&p->slot_bits, &p->slot_bits_cap, words,
                            sizeof *p->slot_bits))
            return -1;
        memset(p->slot_bits, 0, sizeof *p->slot_bits * (size_t)words);
        for (int k = 0; k < n; k++)
            p->slot_bits[p->shape_hits[k] >> 6] |= 1ull << (p->shape_hits[k] & 63);
        for (int w = 0; w < words; w++)
            for (uint64_t bits = p->slot_bits[w]; bits; bits &= bits - 1) {
                int slot = w * 64 + __builtin_ctzll(bits);
                if (s->nodes[slot].visible)
                    p->shape_hits[m++] = slot;
            }
        return m;
    }
    if (n > 1)
        qsort(p->shape_hits, (size_t)n, sizeof *p->shape_hits, cmp_int);
    for (int k = 0; k < n; k++)
        if (s->nodes[p->shape_hits[k]].visible)
            p->shape_hits[m++] = p->shape_hits[k];
    return m;
}
