/* lod_bake.c - a textured mesh's coarse levels with a texture of their own.
 *
 * A texture atlas cut into many charts holds a textured mesh's levels of detail at its
 * charts: a level's triangle may not span two charts (between them it would show the atlas's
 * other charts and margins), so once every chart is down to its few triangles no further
 * level can be made (core/lod_charts.c). Past there a level is simplified by position alone
 * and given a parametrization and texture of its own: each triangle its own square of texels,
 * each texel the colour of the full surface at the point nearest to the texel's point on the
 * level. The colour a point of the level shows then comes from the full surface within the
 * level's bound plus the spacing of the texels the renderer blends there, which is the
 * level's error (limen__lod_bake's reach): a texture cannot smear across a seam by more.
 *
 * Squares: one per triangle, cell x cell texels, the triangle's right angle at the corner
 * opposite its longest edge, its corners on the centres of the square's corner texels; every
 * texel of the square (those beyond the triangle too) takes the colour of the triangle's point
 * nearest to it, so that blending near an edge, and mipmap levels while a texel of theirs
 * lies within one square, read the triangle's own colours. Squares lie along a Z-order curve
 * in the order of the triangles' centres along a Morton curve, so a coarser mipmap level's
 * texel blends triangles that lie together on the surface. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/lod_bake.h"
#include "core/texture.h"

#define REACH_SHARE 0.25        /* the texels' spacing (their blend's reach) at most this share
                                 * of a level's bound, where the texture's size allows */
#define CELL_MIN 4              /* texels a side of a triangle's square, at least, */
#define CELL_MAX 256            /* ... at most */
#define BAKE_TEXELS (2048 * 2048)   /* texels of a baked texture, at most */
#define SPREAD (sqrt(2.0) * (1.0 + (SUB - 1.0) / (2.0 * SUB)))  /* texels, see sides */
#define SUB 1                   /* points a texel's colour is the mean of, SUB x SUB: each
                                 * within (SUB - 1) / (2 SUB) texels of its centre a side */

bool limen__lod_bakeable(const limen__mesh *m)
{
    if (!m->uv || !m->texs || m->has_mask || m->has_blend || !m->nmats)
        return false;
    bool textured = false;
    for (uint32_t k = 0; k < m->nmats; k++) {
        if (m->mats[k].alpha_mode != LIMEN_ALPHA_OPAQUE)
            return false;
        textured = textured || m->texs[k * LIMEN__MAT_TEXTURES + LIMEN__MAT_BASE] ||
                   m->texs[k * LIMEN__MAT_TEXTURES + LIMEN__MAT_EMISSIVE];
    }
    return textured;
}

/* A level's triangle as its square lays it: corner a at the right angle (the one opposite
 * the longest edge), b along the square's first axis, c along its second, in m's order. */
typedef struct laid {
    double a[3], b[3], c[3];
    uint32_t v[3];              /* m's vertices at a, b, c */
} laid;

static void lay(const limen__mesh *m, const uint32_t *tri, laid *l)
{
    double p[3][3], len[3];
    for (int k = 0; k < 3; k++)
        for (int d = 0; d < 3; d++)
            p[k][d] = m->pos[(size_t)tri[k] * 3 + d];
    for (int k = 0; k < 3; k++) {
        double e[3];
        limen__sub3(p[(k + 2) % 3], p[(k + 1) % 3], e);
        len[k] = limen__dot3(e, e);     /* the edge opposite corner k */
    }
    int r = len[0] >= len[1] && len[0] >= len[2] ? 0 : len[1] >= len[2] ? 1 : 2;
    for (int d = 0; d < 3; d++) {
        l->a[d] = p[r][d];
        l->b[d] = p[(r + 1) % 3][d];
        l->c[d] = p[(r + 2) % 3][d];
    }
    for (int k = 0; k < 3; k++)
        l->v[k] = tri[(r + k) % 3];
}

/* The largest stretch of the map from the unit square's legs onto the triangle: the larger
 * singular value of [b - a, c - a]. */
static double stretch(const laid *l)
{
    double e1[3], e2[3];
    limen__sub3(l->b, l->a, e1);
    limen__sub3(l->c, l->a, e2);
    double g11 = limen__dot3(e1, e1), g22 = limen__dot3(e2, e2), g12 = limen__dot3(e1, e2);
    double h = 0.5 * (g11 - g22);
    return sqrt(0.5 * (g11 + g22) + sqrt(h * h + g12 * g12));
}

/* Position r along a Z-order curve: its column (the even bits) and row (the odd). */
static uint32_t z_x(uint32_t r)
{
    uint32_t x = 0;
    for (int b = 0; b < 16; b++)
        x |= ((r >> (2 * b)) & 1u) << b;
    return x;
}

static uint32_t z_y(uint32_t r)
{
    return z_x(r >> 1);
}

/* The side of the square that spaces a triangle of the given stretch's texels at most h
 * apart on it: a power of two from CELL_MIN to CELL_MAX. */
static int side_for(double stretch, double h)
{
    int c = CELL_MIN;
    while (c < CELL_MAX && !(stretch / (c - 1) <= h))
        c *= 2;
    return c;
}

static uint64_t texels_for(const double *st, uint32_t ntris, double h)
{
    uint64_t n = 0;
    for (uint32_t t = 0; t < ntris; t++) {
        uint64_t c = (uint64_t)side_for(st[t], h);
        n += c * c;
    }
    return n;
}

/* Each triangle's square: side[t] texels, the least that spaces its texels at most h apart
 * on it, h the spacing that keeps the texels' part of the reach within REACH_SHARE of geo,
 * or, where the squares would then exceed BAKE_TEXELS, the least spacing that fits (one
 * spacing for all: the reach is the largest); returns the reach (see limen__lod_bake);
 * false when out of memory. */
static bool sides(const limen__mesh *m, const uint32_t *idx, uint32_t ntris, double geo,
                  uint16_t *side, double *reach)
{
    double *st = malloc(sizeof *st * (ntris ? ntris : 1)), most = 0;
    if (!st)
        return false;
    for (uint32_t t = 0; t < ntris; t++) {
        laid l;
        lay(m, idx + (size_t)t * 3, &l);
        st[t] = stretch(&l);
        most = fmax(most, st[t]);
    }
    /* a point blends the four texels around it, each within sqrt(2) texels of it on the
     * square, each the mean of points within SPREAD texels of its centre, which the map
     * onto the triangle stretches by at most stretch / (side - 1) */
    double h = REACH_SHARE * geo / SPREAD;
    if (!(h > 0) || texels_for(st, ntris, h) > BAKE_TEXELS) {
        /* bisected between a spacing too fine and one every square of CELL_MIN meets (at
         * most LIMEN__BAKE_MAX_TRIS of them: within BAKE_TEXELS) */
        double lo = h > 0 ? h : 0, hi = fmax(most / (CELL_MIN - 1), lo);
        for (int i = 0; i < 60 && hi > lo * (1 + 1e-9); i++) {
            double mid = 0.5 * (lo + hi);
            if (texels_for(st, ntris, mid) > BAKE_TEXELS)
                lo = mid;
            else
                hi = mid;
        }
        h = hi;
    }
    double r = 0;
    for (uint32_t t = 0; t < ntris; t++) {
        side[t] = (uint16_t)side_for(st[t], h);
        r = fmax(r, SPREAD * st[t] / (side[t] - 1));
    }
    free(st);
    *reach = geo + r;
    return true;
}

/* ------------------------------------------------------------------ the bake */

typedef struct keyed {
    uint32_t key, tri;
} keyed;

static int by_key(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    return a->key != b->key ? (a->key < b->key ? -1 : 1) : (a->tri < b->tri ? -1 : a->tri > b->tri);
}

static uint32_t spread10(uint32_t x)
{
    x &= 0x3ff;
    x = (x | (x << 16)) & 0x030000ff;
    x = (x | (x << 8)) & 0x0300f00f;
    x = (x | (x << 4)) & 0x030c30c3;
    x = (x | (x << 2)) & 0x09249249;
    return x;
}

/* The triangles by their squares, largest first, and then in the order of their centres
 * along a Morton curve over m's box. */
static keyed *square_order(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                           const uint16_t *side)
{
    keyed *o = malloc(sizeof *o * (ntris ? ntris : 1));
    if (!o)
        return NULL;
    for (uint32_t t = 0; t < ntris; t++) {
        uint32_t q[3];
        for (int d = 0; d < 3; d++) {
            double c = 0, ext = m->hi[d] - m->lo[d];
            for (int k = 0; k < 3; k++)
                c += m->pos[(size_t)idx[t * 3 + k] * 3 + d];
            double f = ext > 0 ? (c / 3 - m->lo[d]) / ext : 0;
            q[d] = (uint32_t)fmin(511.0, fmax(0.0, f * 512.0));
        }
        uint32_t smaller = 0;
        while ((CELL_MAX >> smaller) > side[t])
            smaller++;
        o[t] = (keyed){ smaller << 27 | spread10(q[0]) | spread10(q[1]) << 1 | spread10(q[2]) << 2,
                        t };
    }
    qsort(o, ntris, sizeof *o, by_key);
    return o;
}

/* The point of triangle (a, b, c) nearest to p, as weights of b and c (*u, *v). */
static void nearest_on(const double p[3], const double a[3], const double b[3],
                       const double c[3], double *u, double *v)
{
    double ab[3], ac[3], ap[3];
    limen__sub3(b, a, ab);
    limen__sub3(c, a, ac);
    limen__sub3(p, a, ap);
    double d1 = limen__dot3(ab, ap), d2 = limen__dot3(ac, ap);
    double g11 = limen__dot3(ab, ab), g22 = limen__dot3(ac, ac), g12 = limen__dot3(ab, ac);
    double det = g11 * g22 - g12 * g12;
    double s = 0, t = 0;
    if (det > 0) {
        s = (g22 * d1 - g12 * d2) / det;
        t = (g11 * d2 - g12 * d1) / det;
    }
    if (det > 0 && s >= 0 && t >= 0 && s + t <= 1) {
        *u = s;
        *v = t;
        return;
    }
    /* outside (or no area): the nearest of the three edges' nearest points */
    const double *ends[3][2] = { { a, b }, { a, c }, { b, c } };
    double best = INFINITY;
    *u = *v = 0;
    for (int e = 0; e < 3; e++) {
        double d[3], q[3];
        limen__sub3(ends[e][1], ends[e][0], d);
        limen__sub3(p, ends[e][0], q);
        double dd = limen__dot3(d, d), f = dd > 0 ? limen__dot3(q, d) / dd : 0;
        f = fmin(1.0, fmax(0.0, f));
        double x[3];
        for (int k = 0; k < 3; k++)
            x[k] = ends[e][0][k] + f * d[k] - p[k];
        double d2e = limen__dot3(x, x);
        if (d2e < best) {
            best = d2e;
            *u = e == 0 ? f : e == 1 ? 0 : 1 - f;
            *v = e == 0 ? 0 : e == 1 ? f : f;
        }
    }
}

static unsigned char byte_of(double x)
{
    return (unsigned char)lrint(fmin(1.0, fmax(0.0, x)) * 255.0);
}

/* Of the vertices of m at v's position (through rep, each vertex's weld: at[first[r]] to
 * at[first[r + 1] - 1] those of weld r), the one whose normal faces most as n. */
static uint32_t facing(const limen__mesh *m, const uint32_t *weld, const uint32_t *first,
                       const uint32_t *at, uint32_t v, const double n[3])
{
    uint32_t rep = weld[v], best = v;
    double most = -INFINITY;
    for (uint32_t i = first[rep]; i < first[rep + 1]; i++) {
        const float *q = &m->nrm[(size_t)at[i] * 3];
        double d = q[0] * n[0] + q[1] * n[1] + q[2] * n[2];
        if (d > most) {
            most = d;
            best = at[i];
        }
    }
    return best;
}

static bool emits(const limen__mesh *m)
{
    for (uint32_t k = 0; k < m->nmats; k++)
        if (m->texs[k * LIMEN__MAT_TEXTURES + LIMEN__MAT_EMISSIVE] ||
            m->mats[k].emissive[0] > 0 || m->mats[k].emissive[1] > 0 || m->mats[k].emissive[2] > 0)
            return true;
    return false;
}

void limen__lod_baked_free(limen__mesh *b)
{
    if (!b)
        return;
    free(b->pos);
    free(b->nrm);
    free(b->uv);
    free(b->idx);
    free(b->bvh);
    free(b->tri_order);
    free(b->lods);
    free(b->parts);
    free(b->tri_part);
    for (uint32_t i = 0; b->texs && i < LIMEN__MAT_TEXTURES; i++)
        limen__texture_free(b->texs[i]);
    free(b->texs);
    free(b->mats);
    free(b);
}

limen__mesh *limen__lod_bake(const limen__mesh *m, const limen__lod_target *full,
                             const uint32_t *shadow, const uint32_t *idx, uint32_t ntris,
                             double geo, double *reach)
{
    if (!ntris || ntris > LIMEN__BAKE_MAX_TRIS)
        return NULL;
    uint16_t *side = malloc(sizeof *side * ntris);
    uint32_t *place = malloc(sizeof *place * 2 * ntris);
    keyed *order = NULL;
    if (!side || !place || !sides(m, idx, ntris, geo, side, reach) ||
        !(order = square_order(m, idx, ntris, side))) {
        free(side);
        free(place);
        return NULL;
    }
    /* squares along a Z-order curve of CELL_MIN-texel units, largest first: each begins
     * where a square of its size may (a multiple of its units), in a texture of W x H */
    uint64_t units = 0;
    int W = CELL_MIN, H = 0;
    for (uint32_t r = 0; r < ntris; r++) {
        int c = side[order[r].tri];
        place[2 * r] = z_x((uint32_t)units) * CELL_MIN;
        place[2 * r + 1] = z_y((uint32_t)units) * CELL_MIN;
        units += (uint64_t)(c / CELL_MIN) * (uint64_t)(c / CELL_MIN);
        W = (int)place[2 * r] + c > W ? (int)place[2 * r] + c : W;
        H = (int)place[2 * r + 1] + c > H ? (int)place[2 * r + 1] + c : H;
    }
    size_t nv = (size_t)ntris * 3, texels = (size_t)W * (size_t)H;
    bool glow = emits(m);
    limen__mesh *b = calloc(1, sizeof *b);
    uint32_t *first = calloc((size_t)m->nverts + 1, sizeof *first);
    uint32_t *at = malloc(sizeof *at * (m->nverts ? m->nverts : 1));
    /* (texels no square covers, past the last, stay black) */
    unsigned char *base = calloc(texels, 3), *glows = glow ? calloc(texels, 3) : NULL;
    if (b) {
        b->pos = malloc(sizeof(float) * 3 * nv);
        b->nrm = malloc(sizeof(float) * 3 * nv);
        b->uv = malloc(sizeof(float) * 2 * nv);
        b->idx = malloc(sizeof(uint32_t) * nv);
        b->lods = calloc(1, sizeof *b->lods);
        b->parts = calloc(1, sizeof *b->parts);
        b->tri_part = calloc(ntris, sizeof *b->tri_part);
        b->texs = calloc(LIMEN__MAT_TEXTURES, sizeof *b->texs);
        b->mats = calloc(1, sizeof *b->mats);
    }
    if (!b || !first || !at || !base || (glow && !glows) || !b->pos || !b->nrm ||
        !b->uv || !b->idx || !b->lods || !b->parts || !b->tri_part || !b->texs || !b->mats) {
        free(order), free(side), free(place);
        free(first);
        free(at);
        free(base);
        free(glows);
        limen__lod_baked_free(b);
        return NULL;
    }
    /* the vertices at each welded position (rep: each vertex's weld), for the normals */
    uint32_t *rep = malloc(sizeof *rep * (m->nverts ? m->nverts : 1)), *fill = NULL;
    if (rep && (fill = malloc(sizeof *fill * (m->nverts ? m->nverts : 1)))) {
        for (uint32_t v = 0; v < m->nverts; v++)
            rep[v] = v;
        for (size_t i = 0; i < (size_t)m->ntris * 3; i++)
            rep[m->idx[i]] = shadow[i];
        for (uint32_t v = 0; v < m->nverts; v++)
            first[rep[v] + 1]++;
        for (uint32_t v = 0; v < m->nverts; v++)
            first[v + 1] += first[v];
        memcpy(fill, first, sizeof *fill * m->nverts);
        for (uint32_t v = 0; v < m->nverts; v++)
            at[fill[rep[v]]++] = v;
    }
    free(fill);
    if (!fill) {
        free(rep), free(order), free(first), free(at), free(base), free(glows);
        free(side), free(place);
        limen__lod_baked_free(b);
        return NULL;
    }
    uint32_t hint = 0;
    for (uint32_t r = 0; r < ntris; r++) {
        laid l;
        lay(m, idx + (size_t)order[r].tri * 3, &l);
        const int C = side[order[r].tri];
        int x0 = (int)place[2 * r], y0 = (int)place[2 * r + 1];
        double e1[3], e2[3], n[3];
        limen__sub3(l.b, l.a, e1);
        limen__sub3(l.c, l.a, e2);
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        /* the corners: on the centres of the square's corner texels */
        const double cu[3] = { x0 + 0.5, x0 + C - 0.5, x0 + 0.5 };
        const double cv[3] = { y0 + 0.5, y0 + 0.5, y0 + C - 0.5 };
        for (int k = 0; k < 3; k++) {
            size_t o = (size_t)r * 3 + (size_t)k;
            uint32_t v = facing(m, rep, first, at, l.v[k], n);
            const double *p = k == 0 ? l.a : k == 1 ? l.b : l.c;
            for (int d = 0; d < 3; d++) {
                b->pos[o * 3 + d] = (float)p[d];
                b->nrm[o * 3 + d] = m->nrm[(size_t)v * 3 + d];
            }
            b->uv[o * 2] = (float)(cu[k] / W);
            b->uv[o * 2 + 1] = (float)(cv[k] / H);
            b->idx[o] = (uint32_t)o;
        }
        for (int j = 0; j < C; j++)
            for (int i = 0; i < C; i++) {
                /* the mean of SUB x SUB points around the texel's centre (on the square),
                 * each the triangle's point nearest to it, each the colour of the full
                 * surface's point nearest to that, sampled in the full image: the mean is
                 * over the surface, never over the mesh's atlas (whose mipmap levels blend
                 * its charts with their neighbours and margins) */
                double albedo[3] = { 0, 0, 0 }, em[3] = { 0, 0, 0 };
                for (int sj = 0; sj < SUB; sj++)
                    for (int si = 0; si < SUB; si++) {
                        double s = (i + (si + 0.5) / SUB - 0.5) / (C - 1);
                        double t = (j + (sj + 0.5) / SUB - 0.5) / (C - 1);
                        s = fmax(s, 0.0);
                        t = fmax(t, 0.0);
                        if (s + t > 1) {
                            double over = 0.5 * (s + t - 1);
                            s = fmax(s - over, 0.0);
                            t = fmax(t - over, 0.0);
                        }
                        double p[3];
                        for (int d = 0; d < 3; d++)
                            p[d] = l.a[d] + s * e1[d] + t * e2[d];
                        uint32_t tri;
                        limen__lod_target_nearest(full, p, hint, &tri);
                        hint = tri;
                        const uint32_t *fx = &m->idx[(size_t)tri * 3];
                        double q[3][3];
                        for (int k = 0; k < 3; k++)
                            for (int d = 0; d < 3; d++)
                                q[k][d] = m->pos[(size_t)fx[k] * 3 + d];
                        double u, v, c[3], alpha, e[3];
                        nearest_on(p, q[0], q[1], q[2], &u, &v);
                        limen__mesh_material_at(m, NULL, NULL, LIMEN_FILTER_LINEAR, NULL, tri,
                                                u, v, c, &alpha, e);
                        for (int k = 0; k < 3; k++) {
                            albedo[k] += c[k] / (SUB * SUB);
                            em[k] += e[k] / (SUB * SUB);
                        }
                    }
                size_t px = ((size_t)(H - 1 - (y0 + j)) * (size_t)W + (size_t)(x0 + i)) * 3;
                for (int c = 0; c < 3; c++) {
                    base[px + c] = byte_of(albedo[c]);
                    if (glows)
                        glows[px + c] = byte_of(em[c]);
                }
            }
    }
    free(rep);
    free(order);
    free(side);
    free(place);
    free(first);
    free(at);
    char name[512];
    snprintf(name, sizeof name, "%.480s (baked)", m->name);
    b->texs[LIMEN__MAT_BASE] = limen__texture_own(base, W, H, name);
    if (glows)
        b->texs[LIMEN__MAT_EMISSIVE] = limen__texture_own(glows, W, H, name);
    if (!b->texs[LIMEN__MAT_BASE] || (glows && !b->texs[LIMEN__MAT_EMISSIVE])) {
        limen__lod_baked_free(b);
        return NULL;
    }
    b->refs = 1;
    b->nverts = (uint32_t)nv;
    b->ntris = ntris;
    b->file_normals = m->file_normals;
    memcpy(b->lo, m->lo, sizeof b->lo);
    memcpy(b->hi, m->hi, sizeof b->hi);
    b->nparts = b->nmats = 1;
    b->parts[0] = (limen_mesh_part){ 0, (int)ntris, 0 };
    limen_material *mt = &b->mats[0];
    *mt = m->mats[0];
    mt->name = "baked";
    for (int k = 0; k < 4; k++)
        mt->base_color[k] = 1.0f;
    mt->base_texture = &b->texs[LIMEN__MAT_BASE]->pub;
    mt->base_texcoord = 0;
    const float same[6] = { 1, 0, 0, 1, 0, 0 };
    memcpy(mt->base_transform, same, sizeof same);
    for (int k = 0; k < 3; k++)
        mt->emissive[k] = glows ? 1.0f : 0.0f;
    mt->emissive_texture = glows ? &b->texs[LIMEN__MAT_EMISSIVE]->pub : NULL;
    mt->metallic_roughness_texture = mt->normal_texture = mt->occlusion_texture = NULL;
    b->tex = NULL;
    b->bytes = sizeof *b + nv * (sizeof(float) * 8 + sizeof(uint32_t)) +
               sizeof(uint32_t) * ntris + b->texs[LIMEN__MAT_BASE]->bytes +
               (glows ? b->texs[LIMEN__MAT_EMISSIVE]->bytes : 0);
    b->lods[0] = (limen_mesh_lod){ .indices = b->idx, .triangle_count = (int)ntris,
                                   .parts = b->parts };
    b->nlods = 1;
    snprintf(b->name, sizeof b->name, "%s", name);
    b->serial = limen__next_serial();
    b->pub = (limen_mesh_geometry){ .id = b->serial, .vertex_count = (int)nv,
                                    .triangle_count = (int)ntris, .positions = b->pos,
                                    .normals = b->nrm, .uvs = b->uv, .indices = b->idx,
                                    .lod_count = 1, .lods = b->lods, .part_count = 1,
                                    .parts = b->parts, .material_count = 1,
                                    .materials = b->mats };
    return b;
}
