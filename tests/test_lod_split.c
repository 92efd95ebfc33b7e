/* test_lod_split.c - a big mesh simplified in blocks (core/lod_split.c): blocks meet
 * without a crack, the result is the same on one thread and two, and it is about the size
 * asked for. (A level's bound is measured whatever made it: test_lod.) */
#include <float.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

#include "bumpy.h"
#include "check.h"
#include "core/lod_weld.h"

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static const float *sort_pos;

/* By position. */
static int cmp_pos(const void *a, const void *b)
{
    const float *p = sort_pos + (size_t)*(const uint32_t *)a * 3, *q = sort_pos + (size_t)*(const uint32_t *)b * 3;
    for (int k = 0; k < 3; k++)
        if (p[k] != q[k])
            return p[k] < q[k] ? -1 : 1;
    return 0;
}

/* The edges (a, b) of idx, as positions (weld: per vertex, the first at its position), run
 * by a triangle whose reverse (b, a) no triangle runs: where a surface is open. Sorted, into
 * *out; returns how many. */
static size_t open_edges(const uint32_t *weld, const uint32_t *idx, size_t n, uint64_t **out)
{
    uint64_t *e = malloc(sizeof *e * (n ? n : 1)), *open = malloc(sizeof *open * (n ? n : 1));
    size_t ne = 0, no = 0;
    for (size_t t = 0; t < n / 3; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = weld[idx[t * 3 + k]], b = weld[idx[t * 3 + (k + 1) % 3]];
            if (a != b)
                e[ne++] = (uint64_t)a << 32 | b;
        }
    qsort(e, ne, sizeof *e, cmp_u64);
    for (size_t i = 0; i < ne; i++) {
        uint64_t rev = e[i] << 32 | e[i] >> 32;
        if (!bsearch(&rev, e, ne, sizeof *e, cmp_u64))
            open[no++] = e[i];
    }
    free(e);
    *out = open;
    return no;
}

static void test_blocks_whole(void)
{
    int u = 240, v = 150, nv = (u + 1) * (v + 1);
    size_t n = (size_t)u * v * 6;
    float *pos = malloc(sizeof(float) * 3 * (size_t)nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * n), *weld = malloc(sizeof(uint32_t) * (size_t)nv),
             *one = malloc(sizeof(uint32_t) * n), *two = malloc(sizeof(uint32_t) * n);
    bumpy_sphere(u, v, pos, idx);
    /* per vertex, the first at its position */
    uint32_t *order = malloc(sizeof(uint32_t) * (size_t)nv);
    for (int i = 0; i < nv; i++)
        order[i] = (uint32_t)i;
    sort_pos = pos;
    qsort(order, (size_t)nv, sizeof *order, cmp_pos);
    for (int i = 0; i < nv; i++)
        weld[order[i]] = i > 0 && !cmp_pos(&order[i - 1], &order[i]) ? weld[order[i - 1]] : order[i];
    free(order);
    size_t want = n / 6 * 3;
    float e1 = -1, e2 = -1;
    bool ok1 = false, ok2 = false;
    /* 72,000 triangles in blocks of 10,000: eight blocks */
    size_t m1 = limen__lod_simplify_split(pos, (uint32_t)nv, idx, n, want, FLT_MAX, &e1, one,
                                          10000, false, &ok1);
    size_t m2 = limen__lod_simplify_split(pos, (uint32_t)nv, idx, n, want, FLT_MAX, &e2, two,
                                          10000, true, &ok2);
    CHECK(ok1 && ok2);
    CHECK_MSG(m1 == m2 && !memcmp(one, two, sizeof(uint32_t) * m1) && e1 == e2,
              "one thread and two differ: %zu / %zu indices, errors %g / %g", m1, m2, e1, e2);
    /* halved, near enough: held borders cost a few triangles */
    CHECK_MSG(m1 % 3 == 0 && m1 >= want * 9 / 10 && m1 <= want * 11 / 10,
              "%zu indices made towards %zu", m1, want);
    CHECK(e1 > 0 && e1 < 0.1f);
    bool in_range = true;
    for (size_t i = 0; i < m1; i++)
        in_range = in_range && one[i] < (uint32_t)nv;
    CHECK(in_range);
    /* no crack where blocks meet: every open edge of the result was one of the mesh's (the
     * poles' slivers), held in place */
    uint64_t *open_in, *open_out;
    size_t nin = open_edges(weld, idx, n, &open_in), nout = open_edges(weld, one, m1, &open_out);
    size_t new_open = 0;
    for (size_t i = 0; i < nout; i++)
        new_open += !bsearch(&open_out[i], open_in, nin, sizeof *open_in, cmp_u64);
    CHECK_MSG(new_open == 0, "%zu open edges where blocks meet (%zu open in the mesh)", new_open,
              nin);
    free(open_in);
    free(open_out);
    free(pos);
    free(idx);
    free(weld);
    free(one);
    free(two);
}

static const check_case cases[] = {
    { "blocks_whole", test_blocks_whole },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
