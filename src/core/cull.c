/* cull.c - what a view can see, asked of the scene's spatial index (core/index.c): the
 * surfaces the planner tests against a view, and the shapes a renderer draws in it.
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
#include "core/plan.h"

/* The world planes of the view's narrowed region (kept side >= 0); returns their count. */
static int view_planes(const limen_plan *p, const limen__pview *v, double planes[5][4])
{
    const double P0 = p->proj_d[0], P8 = p->proj_d[8], P5 = p->proj_d[5], P9 = p->proj_d[9];
    const int *sc = v->pub.scissor;
    double xl = 2.0 * (sc[0] - 1) / p->width - 1, xr = 2.0 * (sc[0] + sc[2] + 1) / p->width - 1;
    double yb = 2.0 * (sc[1] - 1) / p->height - 1, yt = 2.0 * (sc[1] + sc[3] + 1) / p->height - 1;
    /* eye space: x_ndc = (P0 x + P8 z) / -z, so x_ndc >= xl is P0 x + (P8 + xl) z >= 0 */
    const double eye[4][4] = { { P0, 0, P8 + xl, 0 }, { -P0, 0, -(P8 + xr), 0 },
                               { 0, P5, P9 + yb, 0 }, { 0, -P5, -(P9 + yt), 0 } };
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
static double slack_for(const limen__bvh *b, const limen__pview *v)
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

int limen__plan_candidates(limen_plan *p, limen_scene *s, const limen__pview *v)
{
    limen__spatial *x = limen__scene_index(s);
    if (!x)
        return -1;
    const limen__bvh *b = limen__index_surfaces(x);
    double planes[5][4];
    int np = view_planes(p, v, planes), n = 0;
    if (limen__bvh_query_planes(b, (const double(*)[4])planes, np, slack_for(b, v), &p->cand,
                                &n, &p->cand_cap, &p->stat_index) < 0)
        return -1;
    /* node slots to the planner's surface indices, in its order */
    int m = 0;
    for (int i = 0; i < n; i++)
        if (p->surf_of[p->cand[i]] >= 0)
            p->cand[m++] = p->surf_of[p->cand[i]];
    if (m > 1)
        qsort(p->cand, (size_t)m, sizeof *p->cand, cmp_int);
    return m;
}

int limen__plan_surface_slots(limen_scene *s, const int **out)
{
    limen__spatial *x = s->brute_force ? NULL : limen__scene_index(s);
    *out = NULL;
    return x ? limen__index_surface_slots(x, out) : s->cap;
}

/* The shapes of the index whose boxes meet view v's region, as node slots in *hits (grown
 * as needed); their count, or -1 when out of memory. */
static int query_shapes(const limen_plan *p, limen__spatial *x, const limen__pview *v,
                        int **hits, int *cap)
{
    const limen__bvh *b = limen__index_shapes(x);
    double planes[5][4];
    int np = view_planes(p, v, planes), n = 0;
    if (limen__bvh_query_planes(b, (const double(*)[4])planes, np, slack_for(b, v), hits, &n,
                                cap, NULL) < 0)
        return -1;
    return n;
}

int limen__plan_view_shapes(limen_plan *p, limen_scene *s, const limen__pview *v)
{
    limen__spatial *x = limen__scene_index(s);
    return x ? query_shapes(p, x, v, &p->shape_hits, &p->shape_hits_cap) : -1;
}

int limen_plan_view_things(const limen_plan *p, limen_scene *s, int i, limen_node *out, int max)
{
    if (!p || !s || i < 0 || i >= p->count || max < 0 || (max > 0 && !out)) {
        if (s)
            limen__fail(s, LIMEN_ERR_ARG, "plan_view_things: no view %d, or no buffer", i);
        return -1;
    }
    limen__spatial *x = limen__scene_index(s);
    if (!x) {
        limen__fail(s, LIMEN_ERR_NOMEM, "plan_view_things: out of memory");
        return -1;
    }
    const limen__pview *v = &p->pv[p->dfs_to_bfs[i]];
    int cap = 0, *hits = NULL;
    int n = query_shapes(p, x, v, &hits, &cap);
    if (n < 0) {
        free(hits);
        limen__fail(s, LIMEN_ERR_NOMEM, "plan_view_things: out of memory");
        return -1;
    }
    if (n > 1)
        qsort(hits, (size_t)n, sizeof *hits, cmp_int);
    int m = 0;
    for (int k = 0; k < n; k++) {
        if (!s->nodes[hits[k]].visible)
            continue;
        if (m < max)
            out[m] = limen__node_handle(s, hits[k]);
        m++;
    }
    free(hits);
    return m;
}
