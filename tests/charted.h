/* charted.h - a textured asset made here, as a game's exporter makes one, for the levels of
 * detail of assets (tests/test_lod.c, bench/lod_build.c): five faces of a cube blown up to a
 * rippled ball (the sixth left open, a border), each face its own chart of the texture (its
 * own tile of a 3 x 2 atlas), so every vertex on an edge between faces is there twice, at
 * one position with two texture coordinates (a seam), and the normals are smooth across.
 *
 * charted_ball(n, tile, pos, nrm, uv, idx): n x n squares a face, 5 * n * n * 2 triangles,
 * counter-clockwise from outside; each face cut into charts of tile x tile squares (tile = n:
 * one chart a face; n a multiple of tile), each its own part of the texture, so seams run
 * between all of them. pos and nrm hold charted_verts(n, tile) * 3 floats, uv * 2, idx
 * 5 * n * n * 6 indices. charted_chart(tile, v): the chart vertex v belongs to. */
#ifndef LIMEN_TESTS_CHARTED_H
#define LIMEN_TESTS_CHARTED_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

static inline int charted_verts(int n, int tile)
{
    return 5 * (n / tile) * (n / tile) * (tile + 1) * (tile + 1);
}

static inline int charted_chart(int tile, uint32_t v)
{
    return (int)(v / (uint32_t)((tile + 1) * (tile + 1)));
}

/* The point of the ball in direction d (normalised here), and its normal (by a small step). */
static inline void charted_point(const double d[3], double out[3])
{
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double x = d[0] / l, y = d[1] / l, z = d[2] / l;
    double r = 1 + 0.04 * sin(5 * x + 1) * sin(4 * y) * cos(3 * z) + 0.02 * sin(11 * y + 7 * z);
    out[0] = r * x;
    out[1] = r * y;
    out[2] = r * z;
}

/* The faces: each its centre direction and two axes across it (right-handed: a x b = c). */
static const int charted_face[5][3][3] = {
    { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },      /* +x: y, z */
    { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },     /* -x: z, y */
    { { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 0 } },      /* +y: z, x */
    { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },     /* -y: x, z */
    { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },      /* +z: x, y (-z is open) */
};

/* The point of face f at square corner (i, j) of n x n, and its normal (across two small
 * steps on the surface), into pos[v * 3] and nrm[v * 3]. */
static inline void charted_vertex(int f, int n, int i, int j, float *pos, float *nrm, size_t v)
{
    const int(*c)[3] = charted_face[f];
    double s = -1 + 2.0 * i / n, t = -1 + 2.0 * j / n, d[3], p[3], q[3], r[3];
    for (int a = 0; a < 3; a++)
        d[a] = c[0][a] + s * c[1][a] + t * c[2][a];
    charted_point(d, p);
    double h = 1e-4, ds[3], dt[3], e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
        ds[a] = d[a] + h * c[1][a];
        dt[a] = d[a] + h * c[2][a];
    }
    charted_point(ds, q);
    charted_point(dt, r);
    for (int a = 0; a < 3; a++) {
        e1[a] = q[a] - p[a];
        e2[a] = r[a] - p[a];
    }
    double nn[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0] };
    double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    for (int a = 0; a < 3; a++) {
        pos[v * 3 + a] = (float)p[a];
        nrm[v * 3 + a] = (float)(nn[a] / l);
    }
}

static inline void charted_ball(int n, int tile, float *pos, float *nrm, float *uv,
                                uint32_t *idx)
{
    int per = n / tile, charts = 5 * per * per, side = 1;
    while (side * side < charts)
        side++;                 /* the atlas: side x side cells, a chart in each */
    size_t k = 0, v = 0;
    for (int f = 0; f < 5; f++) {
        for (int cj = 0; cj < per; cj++)
            for (int ci = 0; ci < per; ci++) {
                int chart = (f * per + cj) * per + ci;
                uint32_t first = (uint32_t)v;
                for (int jj = 0; jj <= tile; jj++)
                    for (int ii = 0; ii <= tile; ii++, v++) {
                        charted_vertex(f, n, ci * tile + ii, cj * tile + jj, pos, nrm, v);
                        /* the chart's cell of the atlas, a margin inside it */
                        uv[v * 2] = (float)((chart % side + 0.05 + 0.9 * ii / tile) / side);
                        uv[v * 2 + 1] = (float)((chart / side + 0.05 + 0.9 * jj / tile) / side);
                    }
                for (int jj = 0; jj < tile; jj++)
                    for (int ii = 0; ii < tile; ii++) {
                        uint32_t a = first + (uint32_t)(jj * (tile + 1) + ii), b = a + 1,
                                 cc = a + (uint32_t)tile + 1, e = cc + 1;
                        uint32_t q[6] = { a, b, e, a, e, cc };
                        for (int x = 0; x < 6; x++)
                            idx[k++] = q[x];
                    }
            }
    }
}


/* The same ball in another layout of charts, as an exporter packs a model's islands: each
 * face's charts are bricks of bw x bh squares in rows, every other row shifted by half a
 * brick (bricks cut at the face's edges), so where charts meet, three do (one brick's side
 * runs on past the corner of two others), not four; each its own cell of the atlas.
 * charted_bricks(n, bw, bh, pos, nrm, uv, idx, chart): returns the vertex count, and with
 * pos not NULL fills pos and nrm (3 floats a vertex), uv (2), chart (the chart of each
 * vertex) and idx (5 * n * n * 6 indices, counter-clockwise from outside). */
static inline int charted_bricks(int n, int bw, int bh, float *pos, float *nrm, float *uv,
                                 uint32_t *idx, int *chart)
{
    int charts = 0, side = 1;
    for (int pass = 0; pass < 2; pass++) {
        size_t k = 0, v = 0;
        int c = 0;
        for (int f = 0; f < 5; f++)
            for (int y0 = 0, r = 0; y0 < n; y0 += bh, r++)
                for (int x = -(r % 2) * (bw / 2); x < n; x += bw) {
                    int x0 = x > 0 ? x : 0, x1 = x + bw < n ? x + bw : n,
                        y1 = y0 + bh < n ? y0 + bh : n;
                    if (x1 <= x0)
                        continue;
                    uint32_t first = (uint32_t)v, w = (uint32_t)(x1 - x0 + 1);
                    for (int j = y0; j <= y1; j++)
                        for (int i = x0; i <= x1; i++, v++) {
                            if (pass == 0 || !pos)
                                continue;
                            charted_vertex(f, n, i, j, pos, nrm, v);
                            uv[v * 2] = (float)((c % side + 0.05 + 0.9 * (i - x) / bw) / side);
                            uv[v * 2 + 1] =
                                (float)((c / side + 0.05 + 0.9 * (j - y0) / bh) / side);
                            chart[v] = c;
                        }
                    for (int j = 0; pass == 1 && pos && j < y1 - y0; j++)
                        for (int i = 0; i < x1 - x0; i++) {
                            uint32_t a = first + (uint32_t)j * w + (uint32_t)i, b = a + 1,
                                     cc = a + w, e = cc + 1;
                            uint32_t q[6] = { a, b, e, a, e, cc };
                            for (int t = 0; t < 6; t++)
                                idx[k++] = q[t];
                        }
                    c++;
                }
        if (pass == 0) {
            charts = c;
            while (side * side < charts)
                side++;
        } else {
            return (int)v;
        }
    }
    return 0;
}

/* The ball in any layout of charts: square_chart gives each square's chart (face f's square
 * (i, j) of n x n at square_chart[(f * n + j) * n + i]; a chart's squares on one face, joined
 * by their sides), charts of them numbered from 0. A chart has a vertex at each corner of
 * its squares (where two charts meet, each its own: a seam), and its own cell of a
 * side x side atlas (side * side >= charts), the box around its squares there with a margin
 * (so a concave chart's cell holds, in its notches, texels no triangle of it shows).
 * charted_layout(n, square_chart, pos, nrm, uv, idx, chart): returns the vertex count, or
 * -1 when out of memory, and with pos not NULL fills pos and nrm (3 floats a vertex), uv
 * (2), chart (per vertex) and idx (5 * n * n * 6 indices, counter-clockwise from outside). */
static inline int charted_layout(int n, const int *square_chart, float *pos, float *nrm,
                                 float *uv, uint32_t *idx, int *chart)
{
    int charts = 0, side = 1, np = (n + 1) * (n + 1);
    for (int q = 0; q < 5 * n * n; q++)
        charts = square_chart[q] + 1 > charts ? square_chart[q] + 1 : charts;
    while (side * side < charts)
        side++;
    /* each chart's box of squares: i0, j0, and its larger side */
    int *box = malloc(sizeof(int) * 4 * (size_t)(charts ? charts : 1));
    /* per corner of a face's squares, up to four charts' vertices there (chart, vertex) */
    int *at = malloc(sizeof(int) * 8 * (size_t)np);
    if (!box || !at) {
        free(box);
        free(at);
        return -1;
    }
    for (int c = 0; c < charts; c++) {
        box[c * 4] = box[c * 4 + 1] = n;
        box[c * 4 + 2] = box[c * 4 + 3] = -1;
    }
    for (int f = 0; f < 5; f++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                int *b = &box[square_chart[(f * n + j) * n + i] * 4];
                b[0] = i < b[0] ? i : b[0];
                b[1] = j < b[1] ? j : b[1];
                b[2] = i > b[2] ? i : b[2];
                b[3] = j > b[3] ? j : b[3];
            }
    int v = 0;
    size_t k = 0;
    for (int f = 0; f < 5; f++) {
        for (int p = 0; p < np * 8; p++)
            at[p] = -1;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                int c = square_chart[(f * n + j) * n + i];
                uint32_t corner[4];
                for (int q = 0; q < 4; q++) {
                    int ii = i + (q == 1 || q == 2), jj = j + (q >= 2), p = jj * (n + 1) + ii;
                    int slot = 0;
                    while (slot < 4 && at[p * 8 + slot * 2] >= 0 && at[p * 8 + slot * 2] != c)
                        slot++;
                    if (at[p * 8 + slot * 2] < 0) {
                        at[p * 8 + slot * 2] = c;
                        at[p * 8 + slot * 2 + 1] = v;
                        if (pos) {
                            const int *b = &box[c * 4];
                            int span = b[2] - b[0] > b[3] - b[1] ? b[2] - b[0] + 1 : b[3] - b[1] + 1;
                            charted_vertex(f, n, ii, jj, pos, nrm, (size_t)v);
                            uv[v * 2] = (float)((c % side + 0.05 + 0.9 * (ii - b[0]) / span) / side);
                            uv[v * 2 + 1] =
                                (float)((c / side + 0.05 + 0.9 * (jj - b[1]) / span) / side);
                            chart[v] = c;
                        }
                        v++;
                    }
                    corner[q] = (uint32_t)at[p * 8 + slot * 2 + 1];
                }
                /* the square (i, j) to (i + 1, j + 1): a b e, a e cc as charted_ball's */
                uint32_t t[6] = { corner[0], corner[1], corner[2], corner[0], corner[2], corner[3] };
                for (int x = 0; pos && x < 6; x++)
                    idx[k++] = t[x];
            }
    }
    free(box);
    free(at);
    return v;
}

/* Concave charts: each face cut into blocks of 2 x 2 cells of cell x cell squares, each
 * block an L of three cells (a corner turning inward, at the block's centre) and the square
 * of the fourth, the L turned a quarter further from block to block; into square_chart
 * (5 * n * n, n a multiple of 2 * cell) for charted_layout. Returns the charts. */
static inline int charted_ells(int n, int cell, int *square_chart)
{
    int per = n / (2 * cell), charts = 0;
    for (int f = 0; f < 5; f++)
        for (int bj = 0; bj < per; bj++)
            for (int bi = 0; bi < per; bi++, charts += 2) {
                /* the square's cell of the block, 0-3, turning from block to block */
                int turn = (bi + 2 * bj + f) % 4;
                for (int j = 0; j < 2 * cell; j++)
                    for (int i = 0; i < 2 * cell; i++) {
                        int quarter = (i >= cell) + 2 * (j >= cell);
                        square_chart[(f * n + bj * 2 * cell + j) * n + bi * 2 * cell + i] =
                            charts + (quarter == turn);
                    }
            }
    return charts;
}

/* A charted ball's arrays, made and freed together: nv vertices (positions, normals,
 * texture coordinates, each one's chart) and nt triangles. charted_arrays_make is false
 * where nv is not positive or memory runs out (what was made is freed by
 * charted_arrays_free all the same). */
typedef struct charted_arrays {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    int *chart;
} charted_arrays;

static inline bool charted_arrays_make(charted_arrays *a, int nv, int nt)
{
    *a = (charted_arrays){ 0 };
    if (nv <= 0 || nt <= 0)
        return false;
    a->pos = malloc(sizeof(float) * 3 * (size_t)nv);
    a->nrm = malloc(sizeof(float) * 3 * (size_t)nv);
    a->uv = malloc(sizeof(float) * 2 * (size_t)nv);
    a->idx = malloc(sizeof(uint32_t) * 3 * (size_t)nt);
    a->chart = malloc(sizeof(int) * (size_t)nv);
    return a->pos && a->nrm && a->uv && a->idx && a->chart;
}

static inline void charted_arrays_free(charted_arrays *a)
{
    free(a->pos);
    free(a->nrm);
    free(a->uv);
    free(a->idx);
    free(a->chart);
    *a = (charted_arrays){ 0 };
}

#endif
