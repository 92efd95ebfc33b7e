/* embree.c - limen's BVH (core/bvh.c) against Embree 3 for the ray tracer's job: the nearest
 * of n spheres along each primary ray, with the exact double-precision sphere test the truth
 * needs. Three contenders on the same spheres and rays, one thread each:
 *   limen      core/bvh.c over the spheres' boxes, the exact test at the leaves;
 *   embree     Embree user geometry (float boxes rounded outwards and widened for the float
 *              copy of the ray Embree traverses with), the same exact test in its callback;
 *   embree-f   Embree's own float spheres (RTC_GEOMETRY_TYPE_SPHERE_POINT): not exact, for
 *              reference only.
 * Prints build and trace times (medians) and how many rays' nearest sphere differs from a
 * scan of all spheres (limen and embree must show 0).
 *
 *   embree [--out FILE.csv] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <embree3/rtcore.h>

#include "core/bvh.h"
#include "core/internal.h"
#include "timing.h"

enum { W = 320, H = 240, REPS = 5 };

typedef struct sphere {
    double c[3], r;
} sphere;

static unsigned long long rng = 11;

static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

/* ------------------------------------------------------------------ the exact test */

/* The nearest hit so far of one ray. */
typedef struct nearest {
    const sphere *sp;
    double o[3], d[3];          /* d unit */
    double t;
    int id;
} nearest;

static void exact(nearest *q, int i)
{
    const sphere *s = &q->sp[i];
    double oc[3] = { q->o[0] - s->c[0], q->o[1] - s->c[1], q->o[2] - s->c[2] };
    double b = oc[0] * q->d[0] + oc[1] * q->d[1] + oc[2] * q->d[2];
    double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - s->r * s->r;
    double disc = b * b - c;
    if (disc < 0)
        return;
    double t = -b - sqrt(disc);
    if (t > 0 && (t < q->t || (t == q->t && i < q->id))) {
        q->t = t;
        q->id = i;
    }
}

static void ray_of(int x, int y, nearest *q)
{
    /* a pinhole at (0, 0, 12) looking down -z, 60 degrees high */
    double f = tan(M_PI / 6);
    double d[3] = { ((x + 0.5) * 2.0 / W - 1) * f * W / H, ((y + 0.5) * 2.0 / H - 1) * f, -1 };
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++)
        q->d[k] = d[k] / len;
    q->o[0] = q->o[1] = 0;
    q->o[2] = 12;
    q->t = INFINITY;
    q->id = -1;
}

/* ------------------------------------------------------------------ limen */

static void bvh_hit(void *ctx, int item, double *tmax)
{
    nearest *q = ctx;
    exact(q, item);
    *tmax = q->t;
}

/* ------------------------------------------------------------------ embree */

typedef struct context {
    struct RTCIntersectContext base;    /* first: Embree passes this pointer back */
    nearest *q;
} context;

static void user_bounds(const struct RTCBoundsFunctionArguments *a)
{
    const sphere *s = &((const sphere *)a->geometryUserPtr)[a->primID];
    /* outwards past float rounding, and wider by what the float ray may stray */
    for (int k = 0; k < 3; k++) {
        double e = 1e-5 * (fabs(s->c[k]) + s->r + 1);
        (&a->bounds_o->lower_x)[k] = nextafterf((float)(s->c[k] - s->r - e), -INFINITY);
        (&a->bounds_o->upper_x)[k] = nextafterf((float)(s->c[k] + s->r + e), INFINITY);
    }
}

static void user_intersect(const struct RTCIntersectFunctionNArguments *a)
{
    if (!a->valid[0])
        return;
    nearest *q = ((context *)a->context)->q;
    int before = q->id;
    exact(q, (int)a->primID);
    if (q->id != before) {
        struct RTCRayHit *rh = (struct RTCRayHit *)a->rayhit;
        /* a far limit no nearer than the exact hit: boxes at the same distance stay */
        rh->ray.tfar = nextafterf((float)q->t, INFINITY);
        rh->hit.geomID = 0;
        rh->hit.primID = a->primID;
    }
}

static RTCScene embree_scene(RTCDevice dev, sphere *sp, int n, bool user)
{
    RTCScene sc = rtcNewScene(dev);
    RTCGeometry g;
    if (user) {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, (unsigned)n);
        rtcSetGeometryUserData(g, sp);
        rtcSetGeometryBoundsFunction(g, user_bounds, NULL);
        rtcSetGeometryIntersectFunction(g, user_intersect);
    } else {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                           4 * sizeof(float), (size_t)n);
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 4; k++)
                v[4 * i + k] = (float)(k < 3 ? sp[i].c[k] : sp[i].r);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    return sc;
}

static int embree_trace(RTCScene sc, const sphere *sp, bool user, const int *truth)
{
    int wrong = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            nearest q = { .sp = sp };
            ray_of(x, y, &q);
            context ctx;
            rtcInitIntersectContext(&ctx.base);
            ctx.q = &q;
            struct RTCRayHit rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = (float)q.o[0];
            rh.ray.org_y = (float)q.o[1];
            rh.ray.org_z = (float)q.o[2];
            rh.ray.dir_x = (float)q.d[0];
            rh.ray.dir_y = (float)q.d[1];
            rh.ray.dir_z = (float)q.d[2];
            rh.ray.tnear = 0;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = ~0u;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(sc, &ctx.base, &rh);
            int id = user                                         ? q.id
                     : rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1
                                                                : (int)rh.hit.primID;
            wrong += truth && id != truth[y * W + x];
        }
    }
    return wrong;
}

/* ------------------------------------------------------------------ main */

int main(int argc, char **argv)
{
    const char *out = NULL;
    if (argc == 3 && !strcmp(argv[1], "--out"))
        out = argv[2];
    else if (argc != 1) {
        fprintf(stderr, "usage: embree [--out FILE.csv]\n");
        return 2;
    }
    /* written whole or not at all (core/file.c), like everything limen writes */
    limen__out o = { 0 };
    if (out && limen__out_open(&o, out)) {
        fprintf(stderr, "embree: cannot write %s\n", out);
        return 1;
    }
    FILE *f = o.f;
    if (f)
        fprintf(f, "spheres,contender,build_ms,trace_ms,wrong_rays\n");
    RTCDevice dev = rtcNewDevice("threads=1");
    if (!dev) {
        fprintf(stderr, "embree: no device\n");
        limen__out_abort(&o);
        return 1;
    }
    static const int NS[] = { 200, 2000, 20000 };
    printf("%d x %d primary rays, one thread; times are medians of %d\n", W, H, REPS);
    for (size_t k = 0; k < sizeof NS / sizeof NS[0]; k++) {
        int n = NS[k];
        sphere *sp = malloc(sizeof *sp * (size_t)n);
        limen__box *boxes = malloc(sizeof *boxes * (size_t)n);
        int *ids = malloc(sizeof *ids * (size_t)n), *truth = malloc(sizeof *truth * W * H);
        double r = 1.2 / sqrt((double)n);
        for (int i = 0; i < n; i++) {
            sp[i].c[0] = 20 * uniform() - 10;
            sp[i].c[1] = 12 * uniform() - 6;
            sp[i].c[2] = -20 * uniform() - 5;
            sp[i].r = r;
            limen__box_sphere(&boxes[i], sp[i].c, r * (1 + 1e-9));
            ids[i] = i;
        }
        /* the truth: every sphere for every ray */
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                nearest q = { .sp = sp };
                ray_of(x, y, &q);
                for (int i = 0; i < n; i++)
                    exact(&q, i);
                truth[y * W + x] = q.id;
            }
        double tb[3][REPS], tt[3][REPS];
        int wrong[3] = { 0, 0, 0 };
        for (int rep = 0; rep < REPS; rep++) {
            limen__bvh b = { 0 };
            double t0 = now_ms();
            limen__bvh_build(&b, ids, n, boxes, n);
            tb[0][rep] = now_ms() - t0;
            t0 = now_ms();
            int bad = 0;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    nearest q = { .sp = sp };
                    ray_of(x, y, &q);
                    limen__bvh_ray(&b, q.o, q.d, 0, INFINITY, bvh_hit, &q);
                    bad += q.id != truth[y * W + x];
                }
            tt[0][rep] = now_ms() - t0;
            wrong[0] = bad;
            limen__bvh_free(&b);
            for (int c = 1; c <= 2; c++) {
                t0 = now_ms();
                RTCScene sc = embree_scene(dev, sp, n, c == 1);
                tb[c][rep] = now_ms() - t0;
                t0 = now_ms();
                wrong[c] = embree_trace(sc, sp, c == 1, truth);
                tt[c][rep] = now_ms() - t0;
                rtcReleaseScene(sc);
            }
        }
        static const char *NAMES[] = { "limen", "embree", "embree-f" };
        for (int c = 0; c < 3; c++) {
            double build = median(tb[c], REPS), trace = median(tt[c], REPS);
            printf("%6d spheres  %-9s build %8.3f ms  trace %8.2f ms  rays whose nearest "
                   "sphere differs from the scan: %d\n", n, NAMES[c], build, trace, wrong[c]);
            if (f)
                fprintf(f, "%d,%s,%.4f,%.3f,%d\n", n, NAMES[c], build, trace, wrong[c]);
        }
        free(sp);
        free(boxes);
        free(ids);
        free(truth);
    }
    rtcReleaseDevice(dev);
    if (f && limen__out_close(&o)) {
        fprintf(stderr, "embree: cannot write %s\n", out);
        return 1;
    }
    return 0;
}
