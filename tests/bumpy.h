/* bumpy.h - a generated mesh for measuring levels of detail (tests/test_lod.c checks their
 * errors, bench/lod_build.c times their making), built here so that no file is needed.
 *
 * bumpy_sphere(u, v, pos, idx): a sphere of radius about 1 on a (u + 1) x (v + 1) grid of
 * latitude and longitude, its radius rippled at two sizes; u * v * 2 triangles, counter-
 * clockwise from outside. At the poles, as a careless exporter makes them, a row of corners
 * on the axis (at the rippled radius) and slivers. pos holds (u + 1) * (v + 1) * 3 floats,
 * idx u * v * 6 indices. */
#ifndef LIMEN_TESTS_BUMPY_H
#define LIMEN_TESTS_BUMPY_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

static inline void bumpy_sphere(int u, int v, float *pos, uint32_t *idx)
{
    for (int j = 0; j <= v; j++)
        for (int i = 0; i <= u; i++) {
            double th = M_PI * j / v, ph = 2 * M_PI * i / u;
            double r = 1 + 0.05 * sin(7 * th) * cos(9 * ph) + 0.01 * sin(31 * th + 17 * ph);
            float *q = &pos[(j * (u + 1) + i) * 3];
            q[0] = (float)(r * sin(th) * cos(ph));
            q[1] = (float)(r * cos(th));
            q[2] = (float)(r * sin(th) * sin(ph));
        }
    size_t k = 0;
    for (int j = 0; j < v; j++)
        for (int i = 0; i < u; i++) {
            uint32_t a = (uint32_t)(j * (u + 1) + i), b = a + 1, c = a + (uint32_t)u + 1, d = c + 1;
            uint32_t q[6] = { a, c, b, b, c, d };
            for (int x = 0; x < 6; x++)
                idx[k++] = q[x];
        }
}

#endif
