/* lod_charts.c - levels of detail within a texture's charts (limen__lod_simplify_charts,
 * declared in core/lod_weld.h): where meshoptimizer is stuck on a textured mesh's seams,
 * core/lod.c makes the coarse levels here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/lod_target.h"
#include "core/lod_weld.h"

/* The simplifier that keeps to the texture's charts (limen__lod_simplify_charts): edge
 * collapses over the mesh welded by position, each moving a vertex onto a neighbour (no new
 * positions: a level's corners stay the mesh's vertices, each with its own coordinates).
 * Each triangle keeps its corners' vertices of the weld attr (position, texture
 * coordinates, colour, part), so where a collapse moves a corner, the corner takes the
 * vertex of the weld at the new position on its own side of any seam: the one that a
 * triangle on the collapsed edge, on that side, names there. A collapse is refused where a
 * side has no such triangle (a corner where three charts or more meet: no neighbour lies on
 * all of them), so no triangle ever takes corners from two charts. A vertex on a seam or a
 * border (two such edges at it) moves only along it, onto its next vertex there, both sides
 * at once: seams and borders stay polylines the two sides share (no crack), simplified as
 * the rest is. The surface stays as whole as it was: a collapse that would join two
 * vertices' neighbourhoods elsewhere than along the edge, or turn a triangle over, is
 * refused; one that would close a tetrahedron flattens it into a fin. Costs are quadrics of
 * the planes of the triangles around each vertex, and of planes across the seams and
 * borders, which keep them in place. */

#define CS_SEAM_WEIGHT 2.0      /* of a seam's or border's planes, beside a triangle's */
#define CS_FLIP 0.05            /* a collapse may turn no triangle (in space or in the
                                 * texture) by more than acos of this */
#define CS_FAN 256              /* triangles around a vertex that may move: beyond, it stays */

typedef struct cs_list {
    uint32_t at, n, cap;        /* in the pool */
} cs_list;

typedef struct cs_entry {
    double cost;
    uint32_t v, u, ver;
} cs_entry;

typedef struct cs {
    const limen__mesh *m;
    uint32_t *tri;              /* per triangle: its corners' vertices of the weld attr */
    uint32_t *tp;               /* per triangle: its corners' welded positions */
    unsigned char *dead;        /* per triangle */
    size_t ntri, live;
    uint32_t np;                /* welded positions */
    float *pos;                 /* per welded position */
    double *q;                  /* per welded position: its quadric (10) */
    uint32_t *ver;              /* per welded position: its entries' version */
    unsigned char *gone;        /* per welded position: moved onto another */
    cs_list *fan;               /* per welded position: its triangles (some dead) */
    uint32_t *pool;
    size_t pool_n, pool_cap;
    cs_entry *heap;
    size_t nheap, heap_cap;
    uint32_t *nb, *nb2;         /* neighbours gathered (CS_FAN * 2 each) */
} cs;

/* A collapse's choice of vertex at the new position, per side: from[i] becomes to[i]. */
typedef struct cs_map {
    uint32_t from[4], to[4];
    int n;
} cs_map;

static void quadric_add_plane(double *q, const double n[3], double d, double w)
{
    q[0] += w * n[0] * n[0];
    q[1] += w * n[0] * n[1];
    q[2] += w * n[0] * n[2];
    q[3] += w * n[0] * d;
    q[4] += w * n[1] * n[1];
    q[5] += w * n[1] * n[2];
    q[6] += w * n[1] * d;
    q[7] += w * n[2] * n[2];
    q[8] += w * n[2] * d;
    q[9] += w * d * d;
}

static double quadric_eval(const double *q, const float *p)
{
    double x = p[0], y = p[1], z = p[2];
    double e = q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
               2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
    return e > 0 ? e : 0;
}

/* The normal (not unit: twice the area) of the triangle of positions a, b, c. */
static void tri_normal(const float *a, const float *b, const float *c, double out[3])
{
    double e1[3] = { (double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2] },
           e2[3] = { (double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2] };
    limen__cross3(e1, e2, out);
}

/* v's live triangles (its list compacted to them), *n their count. */
static const uint32_t *cs_fan(cs *c, uint32_t v, uint32_t *n)
{
    cs_list *l = &c->fan[v];
    uint32_t *t = c->pool + l->at, k = 0;
    for (uint32_t i = 0; i < l->n; i++)
        if (!c->dead[t[i]])
            t[k++] = t[i];
    l->n = k;
    *n = k;
    return t;
}

static bool cs_push_tri(cs *c, uint32_t v, uint32_t t)
{
    cs_list *l = &c->fan[v];
    if (l->n == l->cap) {
        uint32_t cap = l->cap * 2 + 4;
        if (c->pool_n + cap > c->pool_cap) {
            size_t pc = (c->pool_n + cap) * 2;
            uint32_t *p = realloc(c->pool, sizeof *p * pc);
            if (!p)
                return false;
            c->pool = p;
            c->pool_cap = pc;
        }
        memcpy(c->pool + c->pool_n, c->pool + l->at, sizeof(uint32_t) * l->n);
        l->at = (uint32_t)c->pool_n;
        l->cap = cap;
        c->pool_n += cap;
    }
    c->pool[l->at + l->n++] = t;
    return true;
}

/* The corner of triangle t at welded position v, or -1. */
static int cs_corner(const cs *c, size_t t, uint32_t v)
{
    for (int k = 0; k < 3; k++)
        if (c->tp[t * 3 + k] == v)
            return k;
    return -1;
}

/* v's neighbours (distinct) into out; their count, or -1 where more than CS_FAN * 2. */
static int cs_neighbours(cs *c, uint32_t v, uint32_t *out)
{
    uint32_t nf;
    const uint32_t *f = cs_fan(c, v, &nf);
    int n = 0;
    for (uint32_t i = 0; i < nf; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t w = c->tp[(size_t)f[i] * 3 + k];
            bool seen = w == v;
            for (int j = 0; j < n && !seen; j++)
                seen = out[j] == w;
            if (seen)
                continue;
            if (n == CS_FAN * 2)
                return -1;
            out[n++] = w;
        }
    return n;
}

/* Whether the edge from v to w (whose triangles are around v) is a seam or a border: other
 * than two triangles on it, or two that name other vertices of the weld at its ends.
 * *many: more than two. */
static bool cs_edge_open(cs *c, uint32_t v, uint32_t w, bool *many)
{
    uint32_t nf, on[3];
    const uint32_t *f = cs_fan(c, v, &nf);
    int n = 0;
    for (uint32_t i = 0; i < nf; i++)
        if (cs_corner(c, f[i], w) >= 0) {
            if (n == 2) {
                *many = true;
                return true;
            }
            on[n++] = f[i];
        }
    *many = false;
    if (n != 2)
        return true;
    const uint32_t *a = &c->tri[(size_t)on[0] * 3], *b = &c->tri[(size_t)on[1] * 3];
    return a[cs_corner(c, on[0], v)] != b[cs_corner(c, on[1], v)] ||
           a[cs_corner(c, on[0], w)] != b[cs_corner(c, on[1], w)];
}

/* What v's collapses have in common: its neighbours (in the cs's nb, until the next
 * cs_vert_make) and the edges at it on a seam or border. */
typedef struct cs_vert {
    uint32_t v;
    int nn;                     /* neighbours */
    int nopen;                  /* edges on a seam or a border */
    uint32_t open[2];           /* their other ends */
    bool locked;                /* it stays: too many triangles, an edge of three, a seam's
                                 * end or a corner where three charts meet */
} cs_vert;

static void cs_vert_make(cs *c, uint32_t v, cs_vert *x)
{
    uint32_t nf;
    cs_fan(c, v, &nf);
    x->v = v;
    x->nopen = 0;
    x->locked = nf > CS_FAN;
    x->nn = x->locked ? 0 : cs_neighbours(c, v, c->nb);
    if (x->nn < 0) {
        x->locked = true;
        x->nn = 0;
    }
    for (int j = 0; j < x->nn && !x->locked; j++) {
        bool many;
        if (cs_edge_open(c, v, c->nb[j], &many)) {
            if (many || x->nopen == 2)
                x->locked = true;
            else
                x->open[x->nopen++] = c->nb[j];
        }
    }
    x->locked |= x->nopen == 1;
}

/* Whether v (x) may move onto its neighbour u (see above), its choice of vertices in *map
 * and its cost in *cost. */
static bool cs_check(cs *c, const cs_vert *x, uint32_t u, cs_map *map, double *cost)
{
    uint32_t v = x->v, nf;
    /* on a seam or border, only along it */
    if (x->locked || (x->nopen == 2 && x->open[0] != u && x->open[1] != u))
        return false;
    const uint32_t *f = cs_fan(c, v, &nf);
    map->n = 0;
    int on_edge = 0;
    for (uint32_t i = 0; i < nf; i++) {
        size_t t = f[i];
        int ku = cs_corner(c, t, u);
        if (ku < 0)
            continue;
        uint32_t a = c->tri[t * 3 + cs_corner(c, t, v)], b = c->tri[t * 3 + ku];
        on_edge++;
        int j = 0;
        while (j < map->n && map->from[j] != a)
            j++;
        if (j < map->n && map->to[j] != b)
            return false;       /* one side, two vertices there: a cut ends here */
        if (j == map->n) {
            if (map->n == 4)
                return false;
            map->from[j] = a;
            map->to[j] = b;
            map->n++;
        }
    }
    if (on_edge == 0 || on_edge > 2)
        return false;
    /* every side of v has its vertex at u */
    for (uint32_t i = 0; i < nf; i++) {
        uint32_t a = c->tri[(size_t)f[i] * 3 + cs_corner(c, f[i], v)];
        int j = 0;
        while (j < map->n && map->from[j] != a)
            j++;
        if (j == map->n)
            return false;
    }
    int nn = x->nn;
    /* the neighbours v and u share are the edge's triangles' third corners alone (else
     * the surface would fold onto itself) */
    int nu = cs_neighbours(c, u, c->nb2), common = 0;
    if (nu < 0)
        return false;
    for (int j = 0; j < nn; j++)
        for (int k = 0; k < nu; k++)
            common += c->nb[j] == c->nb2[k];
    if (common != on_edge)
        return false;
    /* no triangle turns over, in space or in the texture, nor lands on one at u facing the
     * same way. Facing the other way, v, u and two neighbours are a closed tetrahedron
     * (which the test above lets by), flattened into a fin: two triangles back to back,
     * each with its own side's vertices, whose edges then stay (as a thin closed part of a
     * model, a leg, becomes a flat one) */
    const float *pu = &c->pos[(size_t)u * 3];
    const limen__mesh *m = c->m;
    uint32_t nfu;
    const uint32_t *fu = cs_fan(c, u, &nfu);
    for (uint32_t i = 0; i < nf; i++) {
        size_t t = f[i];
        if (cs_corner(c, t, u) >= 0)
            continue;
        int kv = cs_corner(c, t, v);
        uint32_t p1 = c->tp[t * 3 + (kv + 1) % 3], p2 = c->tp[t * 3 + (kv + 2) % 3];
        for (uint32_t j = 0; j < nfu; j++)
            if (cs_corner(c, fu[j], p1) >= 0 && cs_corner(c, fu[j], p2) >= 0 &&
                c->tp[(size_t)fu[j] * 3 + (cs_corner(c, fu[j], u) + 1) % 3] == p1)
                return false;
        const float *p[3], *q[3];
        for (int k = 0; k < 3; k++)
            p[k] = q[k] = &c->pos[(size_t)c->tp[t * 3 + k] * 3];
        q[kv] = pu;
        double a[3], b[3];
        tri_normal(p[0], p[1], p[2], a);
        tri_normal(q[0], q[1], q[2], b);
        double d = limen__dot3(a, b);
        if (!(d > CS_FLIP * sqrt(limen__dot3(a, a) * limen__dot3(b, b))))
            return false;
        if (m->uv) {
            uint32_t was = c->tri[t * 3 + kv], now = was;
            for (int j = 0; j < map->n; j++)
                if (map->from[j] == was)
                    now = map->to[j];
            const float *s[3], *r[3];
            for (int k = 0; k < 3; k++)
                s[k] = r[k] = &m->uv[(size_t)c->tri[t * 3 + k] * 2];
            r[kv] = &m->uv[(size_t)now * 2];
            double sa = ((double)s[1][0] - s[0][0]) * ((double)s[2][1] - s[0][1]) -
                        ((double)s[2][0] - s[0][0]) * ((double)s[1][1] - s[0][1]);
            double ra = ((double)r[1][0] - r[0][0]) * ((double)r[2][1] - r[0][1]) -
                        ((double)r[2][0] - r[0][0]) * ((double)r[1][1] - r[0][1]);
            if (sa * ra < 0)
                return false;
        }
    }
    *cost = quadric_eval(&c->q[(size_t)v * 10], pu);
    return true;
}

static bool cs_heap_push(cs *c, cs_entry e)
{
    if (c->nheap == c->heap_cap) {
        size_t cap = c->heap_cap * 2 + 64;
        cs_entry *h = realloc(c->heap, sizeof *h * cap);
        if (!h)
            return false;
        c->heap = h;
        c->heap_cap = cap;
    }
    size_t i = c->nheap++;
    while (i > 0) {
        size_t up = (i - 1) / 2;
        cs_entry *p = &c->heap[up];
        if (p->cost < e.cost || (p->cost == e.cost && p->v <= e.v))
            break;
        c->heap[i] = *p;
        i = up;
    }
    c->heap[i] = e;
    return true;
}

/* Drops the entries no longer current (each collapse offers its neighbours again, so the
 * heap would grow by several entries a collapse) and orders the rest again. */
static void cs_heap_prune(cs *c)
{
    size_t n = c->nheap;
    c->nheap = 0;
    for (size_t i = 0; i < n; i++) {
        cs_entry e = c->heap[i];
        if (!c->gone[e.v] && !c->gone[e.u] && e.ver == c->ver[e.v])
            cs_heap_push(c, e);         /* in place: never more than were there */
    }
}

static cs_entry cs_heap_pop(cs *c)
{
    cs_entry top = c->heap[0], last = c->heap[--c->nheap];
    size_t i = 0, n = c->nheap;
    for (;;) {
        size_t l = i * 2 + 1, r = l + 1, s = i;
        const cs_entry *best = &last;
        if (l < n && (c->heap[l].cost < best->cost ||
                      (c->heap[l].cost == best->cost && c->heap[l].v < best->v))) {
            s = l;
            best = &c->heap[l];
        }
        if (r < n && (c->heap[r].cost < best->cost ||
                      (c->heap[r].cost == best->cost && c->heap[r].v < best->v)))
            s = r;
        if (s == i)
            break;
        c->heap[i] = c->heap[s];
        i = s;
    }
    if (n > 0)
        c->heap[i] = last;
    return top;
}

/* v's cheapest collapse, into the heap (none where no neighbour may take it). */
static bool cs_offer(cs *c, uint32_t v)
{
    if (c->gone[v])
        return true;
    cs_vert x;
    cs_vert_make(c, v, &x);
    if (x.locked)
        return true;
    const uint32_t *cand = x.nopen == 2 ? x.open : c->nb;
    int n = x.nopen == 2 ? 2 : x.nn;
    cs_entry best = { .cost = INFINITY, .v = v, .u = UINT32_MAX, .ver = c->ver[v] };
    for (int j = 0; j < n; j++) {
        cs_map map;
        double cost;
        /* the cost first: the checks only where it would be the cheapest */
        if (quadric_eval(&c->q[(size_t)v * 10], &c->pos[(size_t)cand[j] * 3]) >= best.cost)
            continue;
        if (cs_check(c, &x, cand[j], &map, &cost) && cost < best.cost) {
            best.cost = cost;
            best.u = cand[j];
        }
    }
    return best.u == UINT32_MAX || cs_heap_push(c, best);
}

/* v moves onto u (cs_check said it may, with map). */
static bool cs_collapse(cs *c, uint32_t v, uint32_t u, const cs_map *map)
{
    uint32_t nf;
    const uint32_t *f = cs_fan(c, v, &nf);
    uint32_t moved[CS_FAN], nm = 0;
    for (uint32_t i = 0; i < nf; i++) {
        size_t t = f[i];
        int kv = cs_corner(c, t, v);
        if (cs_corner(c, t, u) >= 0) {
            c->dead[t] = 1;
            c->live--;
            continue;
        }
        uint32_t was = c->tri[t * 3 + kv];
        for (int j = 0; j < map->n; j++)
            if (map->from[j] == was)
                c->tri[t * 3 + kv] = map->to[j];
        c->tp[t * 3 + kv] = u;
        moved[nm++] = (uint32_t)t;
    }
    uint32_t nu;
    cs_fan(c, u, &nu);
    for (uint32_t i = 0; i < nm; i++)
        if (!cs_push_tri(c, u, moved[i]))
            return false;
    double *qv = &c->q[(size_t)v * 10], *qu = &c->q[(size_t)u * 10];
    for (int k = 0; k < 10; k++)
        qu[k] += qv[k];
    c->gone[v] = 1;
    c->fan[v].n = 0;
    /* u and its neighbours: their collapses change */
    uint32_t around[CS_FAN * 2];
    int na = cs_neighbours(c, u, around);
    c->ver[u]++;
    if (!cs_offer(c, u))
        return false;
    for (int j = 0; j < na; j++) {
        c->ver[around[j]]++;
        if (!cs_offer(c, around[j]))
            return false;
    }
    return true;
}

static void cs_free(cs *c)
{
    free(c->tri);
    free(c->tp);
    free(c->dead);
    free(c->pos);
    free(c->q);
    free(c->ver);
    free(c->gone);
    free(c->fan);
    free(c->pool);
    free(c->heap);
    free(c->nb);
    free(c->nb2);
}

/* The quadrics: each triangle's plane (weighted by its area) at its corners, and at a
 * seam's or border's ends the plane through it across the triangle. */
static void cs_quadrics(cs *c)
{
    for (size_t t = 0; t < c->ntri; t++) {
        if (c->dead[t])
            continue;
        const uint32_t *v = &c->tp[t * 3];
        const float *p[3] = { &c->pos[(size_t)v[0] * 3], &c->pos[(size_t)v[1] * 3],
                              &c->pos[(size_t)v[2] * 3] };
        double n[3];
        tri_normal(p[0], p[1], p[2], n);
        double l = sqrt(limen__dot3(n, n));
        if (!(l > 0))
            continue;
        for (int k = 0; k < 3; k++)
            n[k] /= l;
        double d = -(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]);
        for (int k = 0; k < 3; k++)
            quadric_add_plane(&c->q[(size_t)v[k] * 10], n, d, l * 0.5);
        for (int k = 0; k < 3; k++) {
            uint32_t a = v[k], b = v[(k + 1) % 3];
            bool many;
            if (!cs_edge_open(c, a, b, &many))
                continue;
            double e[3] = { (double)p[(k + 1) % 3][0] - p[k][0],
                            (double)p[(k + 1) % 3][1] - p[k][1],
                            (double)p[(k + 1) % 3][2] - p[k][2] },
                   s[3];
            limen__cross3(e, n, s);
            double sl = sqrt(limen__dot3(s, s));
            if (!(sl > 0))
                continue;
            for (int j = 0; j < 3; j++)
                s[j] /= sl;
            double sd = -(s[0] * p[k][0] + s[1] * p[k][1] + s[2] * p[k][2]);
            double w = CS_SEAM_WEIGHT * limen__dot3(e, e);
            quadric_add_plane(&c->q[(size_t)a * 10], s, sd, w);
            quadric_add_plane(&c->q[(size_t)b * 10], s, sd, w);
        }
    }
}

size_t limen__lod_simplify_charts(const limen__mesh *m, const uint32_t *shadow,
                                  const uint32_t *attr, const uint32_t *src, size_t n,
                                  size_t want, uint32_t *out, bool *ok)
{
    cs c = { .m = m, .ntri = n / 3 };
    uint32_t nv = m->nverts ? m->nverts : 1;
    uint32_t *vattr = malloc(sizeof *vattr * nv), *vpos = malloc(sizeof *vpos * nv),
             *pid = malloc(sizeof *pid * nv);
    size_t made = 0;
    *ok = false;
    c.tri = malloc(sizeof *c.tri * (n ? n : 1));
    c.tp = malloc(sizeof *c.tp * (n ? n : 1));
    c.dead = calloc(c.ntri ? c.ntri : 1, 1);
    c.nb = malloc(sizeof *c.nb * CS_FAN * 2);
    c.nb2 = malloc(sizeof *c.nb2 * CS_FAN * 2);
    if (!vattr || !vpos || !pid || !c.tri || !c.tp || !c.dead || !c.nb || !c.nb2)
        goto done;
    for (size_t i = 0; i < (size_t)m->ntris * 3; i++) {
        vattr[m->idx[i]] = attr[i];
        vpos[m->idx[i]] = shadow[i];
    }
    /* the welded positions, numbered in the order the source names them */
    memset(pid, 0xff, sizeof *pid * nv);
    for (size_t i = 0; i < c.ntri * 3; i++) {
        uint32_t v = src ? src[i] : m->idx[i], p = vpos[v];
        if (pid[p] == UINT32_MAX)
            pid[p] = c.np++;
        c.tri[i] = vattr[v];
        c.tp[i] = pid[p];
    }
    size_t np = c.np ? c.np : 1;
    c.pos = malloc(sizeof(float) * 3 * np);
    c.q = calloc(np * 10, sizeof(double));
    c.ver = calloc(np, sizeof *c.ver);
    c.gone = calloc(np, 1);
    c.fan = calloc(np, sizeof *c.fan);
    c.pool_cap = c.ntri * 3 + np * 4 + 64;
    c.pool = malloc(sizeof *c.pool * c.pool_cap);
    if (!c.pos || !c.q || !c.ver || !c.gone || !c.fan || !c.pool)
        goto done;
    for (uint32_t v = 0; v < m->nverts; v++)
        if (pid[v] != UINT32_MAX)
            memcpy(&c.pos[(size_t)pid[v] * 3], &m->pos[(size_t)v * 3], sizeof(float) * 3);
    /* a triangle with two corners at one position has no area, nor any use here */
    c.live = c.ntri;
    for (size_t t = 0; t < c.ntri; t++) {
        const uint32_t *p = &c.tp[t * 3];
        if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) {
            c.dead[t] = 1;
            c.live--;
        }
    }
    /* each position's triangles, in the pool (growing at its end when more come) */
    for (size_t t = 0; t < c.ntri; t++)
        for (int k = 0; !c.dead[t] && k < 3; k++)
            c.fan[c.tp[t * 3 + k]].cap++;
    for (uint32_t v = 0; v < c.np; v++) {
        c.fan[v].at = (uint32_t)c.pool_n;
        c.pool_n += c.fan[v].cap;
    }
    for (size_t t = 0; t < c.ntri; t++)
        for (int k = 0; !c.dead[t] && k < 3; k++) {
            cs_list *l = &c.fan[c.tp[t * 3 + k]];
            c.pool[l->at + l->n++] = (uint32_t)t;
        }
    cs_quadrics(&c);
    for (uint32_t v = 0; v < c.np; v++)
        if (!cs_offer(&c, v))
            goto done;
    while (c.live * 3 > want && c.nheap > 0) {
        if (c.nheap > (size_t)c.np * 2 + 1024)
            cs_heap_prune(&c);
        cs_entry e = cs_heap_pop(&c);
        if (c.gone[e.v] || c.gone[e.u] || e.ver != c.ver[e.v])
            continue;
        cs_map map;
        double cost;
        cs_vert x;
        cs_vert_make(&c, e.v, &x);
        if (!cs_check(&c, &x, e.u, &map, &cost)) {
            /* its neighbourhood changed since: offered again */
            c.ver[e.v]++;
            if (!cs_offer(&c, e.v))
                goto done;
            continue;
        }
        if (!cs_collapse(&c, e.v, e.u, &map))
            goto done;
    }
    /* the live triangles, in the source's order */
    for (size_t t = 0; t < c.ntri; t++)
        if (!c.dead[t]) {
            memcpy(&out[made], &c.tri[t * 3], sizeof(uint32_t) * 3);
            made += 3;
        }
    *ok = true;
done:
    free(vattr);
    free(vpos);
    free(pid);
    cs_free(&c);
    return made;
}

size_t limen__lod_charts_want(size_t cur, size_t floor, size_t room)
{
    size_t half = cur / 2;
    /* stuck there anyway; or a halving ends at the floor (floor >= half: as asked before) */
    if (floor * 4 > cur * 3 || floor >= half)
        return half;
    /* a halving leaves room for a step of 3/4 or less down to the floor: where both fit */
    if (floor * 4 <= half * 3)
        return half + floor <= room ? half : floor;
    /* else a step the floor is at most 3/4 of, with room for the floor of the level it is
     * made from to lie a little above the full mesh's (1/64, and two triangles) */
    size_t step = floor * 4 / 3 + floor / 64 + 2;
    return step * 4 <= cur * 3 && step + floor <= room ? step : floor;
}
