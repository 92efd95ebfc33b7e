/* lod_bake.c - a textured mesh's coarse levels with a texture of their own.
 *
 * A texture atlas cut into many charts holds a textured mesh's levels of detail at its
 * charts: a level's triangle may not span two charts (between them it would show the atlas's
 * other charts and margins), so once every chart is down to its few triangles no further
 * level can be made (core/lod_charts.c). Past there a level is simplified by position alone
 * and given a parametrization and texture of its own: each triangle its own square of
 * texels, each texel the colour of the full surface at the point nearest to the texel's
 * point on the level (within the level's bound of it). The colour a point of the
 * level shows then comes from the full surface within the level's bound plus the spacing of
 * the texels the renderer blends there, which is the level's error (limen__lod_bake's
 * reach): a texture cannot smear across a seam by more.
 *
 * Squares: one per triangle, a multiple of 4 texels a side, the triangle's right angle at
 * the corner opposite its longest edge, its corners on the centres of the square's corner
 * texels; every texel of the square (those beyond the triangle too) takes the colour of the
 * triangle's point nearest to it, so that blending near an edge, and mipmap levels while a
 * texel of theirs lies within one square (the first two: squares begin on multiples of 4
 * texels), read the triangle's own colours. Squares lie in rows, largest first, then in the
 * order of the triangles' centres along a Morton curve, so a coarser mipmap level's texel
 * mostly blends triangles that lie together on the surface. */
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
#define BAKE_TEXELS (1024 * 1024)   /* texels of a baked texture, at most, */
#define TRI_TEXELS 512          /* ... and at most this many a triangle (a level's bake costs a
                                 * search of the full surface per texel) */
#define SPREAD 1.4142135623730951  /* texels: how far from a point lie the four it blends */
#define THREAD_TRIS 64          /* a level this big is baked on two threads */

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

/* The side of the square that spaces a triangle of the given stretch's texels at most h
 * apart on it: a multiple of CELL_MIN from CELL_MIN to CELL_MAX. */
static int side_for(double stretch, double h)
{
    double need = stretch / h + 1;      /* (side - 1) h >= stretch */
    if (!(need <= CELL_MAX))
        return CELL_MAX;
    int c = CELL_MIN * (int)ceil(need / CELL_MIN);
    return c < CELL_MIN ? CELL_MIN : c > CELL_MAX ? CELL_MAX : c;
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
 * or, where the squares would then exceed BAKE_TEXELS or TRI_TEXELS a triangle, the least
 * spacing that fits (one spacing for all: the reach is the largest); returns the reach (see
 * limen__lod_bake); false when out of memory. */
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
    /* a point blends the four texels around it, each within SPREAD texels of it on the
     * square, which the map onto the triangle stretches by at most stretch / (side - 1) */
    double h = REACH_SHARE * geo / SPREAD;
    uint64_t most_texels = (uint64_t)TRI_TEXELS * ntris;
    if (most_texels > BAKE_TEXELS)
        most_texels = BAKE_TEXELS;
    if (most_texels < (uint64_t)CELL_MIN * CELL_MIN * ntris)
        most_texels = (uint64_t)CELL_MIN * CELL_MIN * ntris;
    if (!(h > 0) || texels_for(st, ntris, h) > most_texels) {
        /* bisected between a spacing too fine and one every square of CELL_MIN meets (at
         * most LIMEN__BAKE_MAX_TRIS of them: CELL_MIN^2 a triangle is allowed) */
        double lo = h > 0 ? h : 0, hi = fmax(most / (CELL_MIN - 1), lo);
        for (int i = 0; i < 60 && hi > lo * (1 + 1e-9); i++) {
            double mid = 0.5 * (lo + hi);
            if (texels_for(st, ntris, mid) > most_texels)
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
            q[d] = (uint32_t)fmin(255.0, fmax(0.0, f * 256.0));
        }
        uint32_t smaller = (uint32_t)(CELL_MAX - side[t]) / CELL_MIN;    /* 0 to 63 */
        o[t] = (keyed){ smaller << 26 | limen__morton3(q[0], q[1], q[2]), t };
    }
    qsort(o, ntris, sizeof *o, by_key);
    return o;
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

/* A share of a bake: squares from .. to of the order, each texel found from the last's
 * triangle (so the same for the same share, on one thread or two). */
typedef struct baker {
    const limen__mesh *m;
    const limen__lod_target *full;
    const uint32_t *idx, *rep, *first, *at, *place;
    const keyed *order;
    const uint16_t *side;
    limen__mesh *b;
    unsigned char *base, *glows;
    int W, H;
    uint32_t from, to;
} baker;

static void *bake_share(void *arg)
{
    baker *w = arg;
    const limen__mesh *m = w->m;
    uint32_t hint = 0;
    for (uint32_t r = w->from; r < w->to; r++) {
        laid l;
        lay(m, w->idx + (size_t)w->order[r].tri * 3, &l);
        const int C = w->side[w->order[r].tri];
        int x0 = (int)w->place[2 * r], y0 = (int)w->place[2 * r + 1];
        double e1[3], e2[3], n[3];
        limen__sub3(l.b, l.a, e1);
        limen__sub3(l.c, l.a, e2);
        limen__cross3(e1, e2, n);
        /* the corners: on the centres of the square's corner texels */
        const double cu[3] = { x0 + 0.5, x0 + C - 0.5, x0 + 0.5 };
        const double cv[3] = { y0 + 0.5, y0 + 0.5, y0 + C - 0.5 };
        for (int k = 0; k < 3; k++) {
            size_t o = (size_t)r * 3 + (size_t)k;
            uint32_t v = facing(m, w->rep, w->first, w->at, l.v[k], n);
            const double *p = k == 0 ? l.a : k == 1 ? l.b : l.c;
            for (int d = 0; d < 3; d++) {
                w->b->pos[o * 3 + d] = (float)p[d];
                w->b->nrm[o * 3 + d] = m->nrm[(size_t)v * 3 + d];
            }
            w->b->uv[o * 2] = (float)(cu[k] / w->W);
            w->b->uv[o * 2 + 1] = (float)(cv[k] / w->H);
            w->b->idx[o] = (uint32_t)o;
        }
        for (int j = 0; j < C; j++)
            for (int i = 0; i < C; i++) {
                /* the triangle's point nearest to the texel's centre (on the square) */
                double st = (double)i / (C - 1), tt = (double)j / (C - 1);
                if (st + tt > 1) {
                    double over = 0.5 * (st + tt - 1);
                    st -= over;
                    tt -= over;
                }
                double p[3];
                for (int d = 0; d < 3; d++)
                    p[d] = l.a[d] + st * e1[d] + tt * e2[d];
                /* the full surface's point nearest to that, searched from the last texel's
                 * triangle (a walk from there, taken where it ended within the level's
                 * bound, often ended on the wrong sheet of a thin part: a helmet's inner
                 * shell); its colour sampled in the full image, never from the atlas's
                 * mipmap levels, which blend its charts with their neighbours and margins */
                uint32_t tri;
                limen__lod_target_nearest(w->full, p, hint, &tri);
                hint = tri;
                const uint32_t *fx = &m->idx[(size_t)tri * 3];
                double q[3][3];
                for (int k = 0; k < 3; k++)
                    for (int d = 0; d < 3; d++)
                        q[k][d] = m->pos[(size_t)fx[k] * 3 + d];
                double u, v, albedo[3], alpha, em[3];
                limen__tri_nearest(p, q[0], q[1], q[2], &u, &v);
                limen__mesh_material_at(m, NULL, NULL, LIMEN_FILTER_LINEAR, NULL, tri, u, v,
                                        albedo, &alpha, em);
                size_t row = (size_t)(w->H - 1 - (y0 + j)) * (size_t)w->W;
                size_t px = (row + (size_t)(x0 + i)) * 3;
                for (int c = 0; c < 3; c++) {
                    w->base[px + c] = byte_of(albedo[c]);
                    if (w->glows)
                        w->glows[px + c] = byte_of(em[c]);
                }
            }
    }
    return NULL;
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
    /* squares in rows of a texture W wide (about the square root of their texels, at least
     * the largest), largest first: a row as high as its first */
    uint64_t all = 0;
    for (uint32_t t = 0; t < ntris; t++)
        all += (uint64_t)side[t] * side[t];
    int W = CELL_MIN * (int)ceil(sqrt((double)all) / CELL_MIN), H = 0, x = 0, row = 0;
    if (W < side[order[0].tri])
        W = side[order[0].tri];
    for (uint32_t r = 0; r < ntris; r++) {
        int c = side[order[r].tri];
        if (x + c > W) {
            H += row;
            x = 0;
        }
        if (x == 0)
            row = c;
        place[2 * r] = (uint32_t)x;
        place[2 * r + 1] = (uint32_t)H;
        x += c;
    }
    H += row;
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
    /* the squares in two shares, the second on a thread of its own where one starts */
    baker work[2];
    for (int k = 0; k < 2; k++)
        work[k] = (baker){ .m = m, .full = full, .idx = idx, .rep = rep, .first = first,
                           .at = at, .place = place, .order = order, .side = side, .b = b,
                           .base = base, .glows = glows, .W = W, .H = H,
                           .from = k ? ntris / 2 : 0, .to = k ? ntris : ntris / 2 };
    limen__lod_both(bake_share, &work[0], &work[1], ntris >= THREAD_TRIS);
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
