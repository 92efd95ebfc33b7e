/* ray.h - the tests' brute-force ray against one triangle (Moller-Trumbore, in double), to
 * hold the library's hierarchies and pixels to: test_mesh.c, test_render.c. */
#ifndef LIMEN_TESTS_RAY_H
#define LIMEN_TESTS_RAY_H

#include <stdbool.h>

/* Whether the ray o + t d, t > 0, meets triangle abc (either side); *t, and the hit's
 * barycentric u (towards b) and v (towards c). */
static inline bool ray_triangle(const float *a, const float *b, const float *c,
                                const double o[3], const double d[3], double *t, double *u,
                                double *v)
{
    double e1[3], e2[3], sv[3];
    for (int i = 0; i < 3; i++) {
        e1[i] = (double)b[i] - a[i];
        e2[i] = (double)c[i] - a[i];
        sv[i] = o[i] - a[i];
    }
    double p[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                    d[0] * e2[1] - d[1] * e2[0] };
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return false;
    double q[3] = { sv[1] * e1[2] - sv[2] * e1[1], sv[2] * e1[0] - sv[0] * e1[2],
                    sv[0] * e1[1] - sv[1] * e1[0] };
    *u = (sv[0] * p[0] + sv[1] * p[1] + sv[2] * p[2]) / det;
    *v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return *u >= 0 && *v >= 0 && *u + *v <= 1 && *t > 0;
}

#endif
