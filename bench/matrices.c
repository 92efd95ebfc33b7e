/* matrices.c - the three ways of building a mirror matrix, timed and checked over random
 * planes and planes whose normals lie near (or at) (0,-1,0) and (0,1,0):
 *   closed   limen__mirror_mat4: I - 2 n n^T, translation -2 d n, in double
 *   node     limen__mirror_mat4_node: W diag(1,1,-1,1) W^-1 from the mirror's float world
 *            matrix (which a scene graph holds already: building W is not timed)
 *   axis     limen__mirror_mat4_axis_angle: seed 000's A^-1 F A with an axis-angle rotation
 *            of n onto +Y, in float
 * For each matrix M (float) the error is measured in double: orthogonality max|R^T R - I|
 * of its 3x3 part, involution max|M M - I|, and the distance max|M - M_exact| from the
 * reflection computed in double from the same (float) plane.
 *
 *   matrices [--full] [--out FILE.csv]
 *
 * Time: many calls over a set of planes with a volatile sink, the median of several runs,
 * in nanoseconds per matrix (the loop's own cost, about a nanosecond, included). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "core/lmath.h"
#include "core/testing.h"

enum { NPLANES = 4096, METHODS = 3, SETS = 5 };

/* CSV keys (no commas), and the names printed */
static const char *METHOD_KEYS[METHODS] = { "closed", "node", "axis_angle" };
static const char *METHOD_NAMES[METHODS] = { "closed form", "node transform",
                                             "axis-angle (seed)" };
static const char *SET_KEYS[SETS] = { "random", "near_neg_y", "near_pos_y", "at_neg_y",
                                      "at_pos_y" };
static const char *SET_NAMES[SETS] = { "random", "near (0,-1,0)", "near (0,1,0)",
                                       "at (0,-1,0)", "at (0,1,0)" };

static vec4 g_planes[NPLANES];
static mat4 g_worlds[NPLANES];
static volatile float g_sink;

/* ------------------------------------------------------------------ random planes */

static unsigned long long g_rng = 0x9E3779B97F4A7C15ull;

static double uniform(void)    /* [0, 1) */
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

static double gauss(void)
{
    double u = uniform() + 1e-300, v = uniform();
    return sqrt(-2.0 * log(u)) * cos(2.0 * M_PI * v);
}

/* A unit normal for plane i of a set, in double. */
static void set_normal(int set, double n[3])
{
    if (set == 0) {
        double len;
        do {
            n[0] = gauss(), n[1] = gauss(), n[2] = gauss();
            len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        } while (len < 1e-9);
        for (int k = 0; k < 3; k++)
            n[k] /= len;
        return;
    }
    double pole = (set == 1 || set == 3) ? -1.0 : 1.0;
    if (set >= 3) {
        n[0] = 0, n[1] = pole, n[2] = 0;
        return;
    }
    /* tilted from the pole by an angle log-uniform in [1e-8, 1e-1] rad, any azimuth */
    double ang = pow(10.0, -8.0 + 7.0 * uniform()), az = 2.0 * M_PI * uniform();
    n[0] = sin(ang) * cos(az);
    n[1] = pole * cos(ang);
    n[2] = sin(ang) * sin(az);
}

/* The plane (float, as a scene would hold it) and a float world matrix whose local z = 0
 * is that plane with +Z its normal. */
static void make_set(int set)
{
    for (int i = 0; i < NPLANES; i++) {
        double n[3], d = 4.0 * uniform() - 2.0;
        set_normal(set, n);
        for (int k = 0; k < 3; k++)
            g_planes[i][k] = (float)n[k];
        g_planes[i][3] = (float)d;
        /* tangents: any orthonormal pair completing n */
        double a[3] = { 1, 0, 0 };
        if (fabs(n[0]) > 0.9)
            a[0] = 0, a[1] = 1;
        double t[3] = { a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2],
                        a[0] * n[1] - a[1] * n[0] };
        double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        for (int k = 0; k < 3; k++)
            t[k] /= tl;
        double b[3] = { n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                        n[0] * t[1] - n[1] * t[0] };
        glm_mat4_identity(g_worlds[i]);
        for (int k = 0; k < 3; k++) {
            g_worlds[i][0][k] = (float)t[k];
            g_worlds[i][1][k] = (float)b[k];
            g_worlds[i][2][k] = (float)n[k];
            g_worlds[i][3][k] = (float)(-d * n[k]);
        }
    }
}

/* ------------------------------------------------------------------ methods */

static void build(int method, int i, mat4 out)
{
    switch (method) {
    case 0: limen__mirror_mat4(g_planes[i], out); break;
    case 1:
        if (limen__mirror_mat4_node(g_worlds[i], out))
            glm_mat4_identity(out);
        break;
    default: limen__mirror_mat4_axis_angle(g_planes[i], out); break;
    }
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median over `runs` runs of `calls` calls each, in ns per call. */
static double time_method(int method, int calls, int runs)
{
    double t[32];
    mat4 m;
    for (int r = 0; r < runs && r < 32; r++) {
        double t0 = now_ns();
        for (int c = 0; c < calls; c++) {
            build(method, c & (NPLANES - 1), m);
            g_sink = m[1][1];
        }
        t[r] = (now_ns() - t0) / calls;
    }
    qsort(t, (size_t)runs, sizeof t[0], cmp_double);
    return t[runs / 2];
}

/* ------------------------------------------------------------------ errors */

typedef struct errs {
    double ortho, invol, exact;     /* max over the matrix's entries; INFINITY if not finite */
} errs;

static errs measure(const vec4 plane, mat4 mf)
{
    double m[4][4], e[4][4];
    errs out = { 0, 0, 0 };
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            m[c][r] = mf[c][r];
            if (!isfinite(m[c][r]))
                out.ortho = out.invol = out.exact = INFINITY;
        }
    if (isinf(out.ortho))
        return out;
    /* the exact reflection of the float plane, in double */
    double n[3] = { plane[0], plane[1], plane[2] }, d = plane[3];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    d /= len;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            if (c < 3 && r < 3)
                e[c][r] = (r == c ? 1.0 : 0.0) - 2.0 * n[r] * n[c];
            else if (c == 3 && r < 3)
                e[c][r] = -2.0 * d * n[r];
            else
                e[c][r] = (r == c) ? 1.0 : 0.0;
            out.exact = fmax(out.exact, fabs(m[c][r] - e[c][r]));
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += m[i][k] * m[j][k];     /* column i . column j */
            out.ortho = fmax(out.ortho, fabs(s - (i == j)));
        }
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += m[k][r] * m[c][k];
            out.invol = fmax(out.invol, fabs(s - (r == c)));
        }
    return out;
}

/* ------------------------------------------------------------------ main */

int main(int argc, char **argv)
{
    int full = 0;
    const char *out = "build/bench/matrices.csv";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--full"))
            full = 1;
        else if (!strcmp(argv[i], "--quick"))
            full = 0;
        else if (!strcmp(argv[i], "--out") && i + 1 < argc)
            out = argv[++i];
        else {
            fprintf(stderr, "usage: matrices [--quick|--full] [--out FILE.csv]\n");
            return 1;
        }
    }
    int calls = full ? 2000000 : 400000, runs = full ? 11 : 5;
    limen__out file;    /* written whole or not at all */
    if (limen__out_open(&file, out)) {
        fprintf(stderr, "matrices: cannot write %s\n", out);
        return 1;
    }
    FILE *f = file.f;
    fprintf(f, "method,set,ns_per_matrix,err_median,err_max,ortho_max,invol_max,exact_max,"
               "non_finite_share\n");
    printf("%-18s %-14s %9s %11s %11s %11s %11s %11s %9s\n", "method", "planes", "ns/matrix",
           "err median", "err max", "ortho max", "invol max", "vs exact", "non-fin.");
    static double errv[NPLANES];
    for (int set = 0; set < SETS; set++) {
        make_set(set);
        for (int mth = 0; mth < METHODS; mth++) {
            double ns = time_method(mth, calls, runs);
            double omax = 0, imax = 0, xmax = 0;
            int bad = 0;
            for (int i = 0; i < NPLANES; i++) {
                mat4 m;
                build(mth, i, m);
                errs e = measure(g_planes[i], m);
                if (isinf(e.ortho))
                    bad++;
                errv[i] = fmax(e.ortho, e.invol);
                omax = fmax(omax, e.ortho);
                imax = fmax(imax, e.invol);
                xmax = fmax(xmax, e.exact);
            }
            qsort(errv, NPLANES, sizeof errv[0], cmp_double);
            double med = errv[NPLANES / 2], emax = errv[NPLANES - 1];
            fprintf(f, "%s,%s,%.2f,%.3e,%.3e,%.3e,%.3e,%.3e,%.4f\n", METHOD_KEYS[mth],
                    SET_KEYS[set], ns, med, emax, omax, imax, xmax, (double)bad / NPLANES);
            printf("%-18s %-14s %9.1f %11.2e %11.2e %11.2e %11.2e %11.2e %8.1f%%\n",
                   METHOD_NAMES[mth], SET_NAMES[set], ns, med, emax, omax, imax, xmax,
                   100.0 * bad / NPLANES);
        }
    }
    if (limen__out_close(&file)) {
        fprintf(stderr, "matrices: cannot write %s\n", out);
        return 1;
    }
    return 0;
}
