/* rtc.c - the ray tracer's traversal through Embree 3 (intel's kept ray tracing kernels):
 * one user geometry whose primitives are the spatial index's items (core/index.c), their
 * boxes the index's boxes. Embree only chooses which items a ray may meet; the caller's
 * exact double-precision test decides (core/trace.c), so Embree's float arithmetic never
 * reaches a pixel. Its boxes are rounded outwards to floats and widened by 1e-5 of the
 * scene's extent, and each ray starts where it enters the scene's box, so that the float
 * copy of the ray Embree traverses with (error ~1e-7 of the extent) can only keep boxes the
 * exact ray misses, never lose one it meets. Measured against core/bvh.c in bench/embree.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "core/reserve.h"
#include "core/rtc.h"

struct limen__rtc {
    RTCDevice device;
    RTCScene scene;
    RTCGeometry geom;
    const limen__bvh *trees[2];
    int counts[2];
    int *items, items_cap;      /* per primitive: its item, the shapes' first */
    limen__box root;
    double widen;
};

/* One ray's traversal: the caller's test and where the ray was moved to. */
typedef struct context {
    struct RTCIntersectContext base;    /* first: Embree hands this pointer back */
    const limen__rtc *r;
    limen__bvh_hit_fn hit;
    void *ctx;
    double shift, tmax;
} context;

static int item_of(const limen__rtc *r, unsigned prim, int *tree)
{
    *tree = prim >= (unsigned)r->counts[0];
    return r->items[prim];
}

static void bounds(const struct RTCBoundsFunctionArguments *a)
{
    const limen__rtc *r = a->geometryUserPtr;
    int tree, id = item_of(r, a->primID, &tree);
    const limen__box *b = &r->trees[tree]->boxes[id];
    for (int k = 0; k < 3; k++) {
        (&a->bounds_o->lower_x)[k] = nextafterf((float)(b->lo[k] - r->widen), -INFINITY);
        (&a->bounds_o->upper_x)[k] = nextafterf((float)(b->hi[k] + r->widen), INFINITY);
    }
}

static void intersect(const struct RTCIntersectFunctionNArguments *a)
{
    if (!a->valid[0])
        return;
    context *c = (context *)a->context;
    int tree;
    double before = c->tmax;
    c->hit(c->ctx, item_of(c->r, a->primID, &tree), &c->tmax);
    if (c->tmax < before) {
        /* no nearer than the exact hit, so boxes entered at the same distance stay */
        struct RTCRayHit *rh = (struct RTCRayHit *)a->rayhit;
        rh->ray.tfar = nextafterf((float)(c->tmax - c->shift + c->r->widen), INFINITY);
    }
}

limen__rtc *limen__rtc_create(void)
{
    limen__rtc *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    r->device = rtcNewDevice(NULL);
    if (!r->device) {
        free(r);
        return NULL;
    }
    return r;
}

void limen__rtc_free(limen__rtc *r)
{
    if (!r)
        return;
    if (r->scene)
        rtcReleaseScene(r->scene);
    rtcReleaseDevice(r->device);
    free(r->items);
    free(r);
}

bool limen__rtc_commit(limen__rtc *r, const limen__bvh *shapes, const limen__bvh *surfaces)
{
    if (r->scene)
        rtcReleaseScene(r->scene);
    r->scene = NULL;
    r->trees[0] = shapes;
    r->trees[1] = surfaces;
    /* the trees' items, without the holes their removals left in `order` */
    if (!limen__reserve((void **)&r->items, &r->items_cap, shapes->nitems + surfaces->nitems + 1,
                        sizeof *r->items))
        return false;
    int n = 0;
    for (int t = 0; t < 2; t++) {
        for (int i = 0; i < r->trees[t]->norder; i++)
            if (r->trees[t]->order[i] >= 0)
                r->items[n++] = r->trees[t]->order[i];
        r->counts[t] = t ? n - r->counts[0] : n;
    }
    limen__box_empty(&r->root);
    double extent = 0;
    for (int t = 0; t < 2; t++) {
        if (!r->trees[t]->nnodes)
            continue;
        limen__box_add(&r->root, &r->trees[t]->nodes[0].box);
    }
    for (int k = 0; k < 3; k++)
        extent = fmax(extent, fmax(fabs(r->root.lo[k]), fabs(r->root.hi[k])));
    r->widen = 1e-5 * (extent + 1.0);
    for (int k = 0; k < 3; k++) {
        r->root.lo[k] -= 2 * r->widen;
        r->root.hi[k] += 2 * r->widen;
    }
    r->scene = rtcNewScene(r->device);
    if (!r->scene)
        return false;
    rtcSetSceneFlags(r->scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(r->device, RTC_GEOMETRY_TYPE_USER);
    if (!g)
        return false;
    rtcSetGeometryUserPrimitiveCount(g, (unsigned)(r->counts[0] + r->counts[1]));
    rtcSetGeometryUserData(g, r);
    rtcSetGeometryBoundsFunction(g, bounds, NULL);
    rtcSetGeometryIntersectFunction(g, intersect);
    rtcCommitGeometry(g);
    rtcAttachGeometry(r->scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(r->scene);
    return rtcGetDeviceError(r->device) == RTC_ERROR_NONE;
}

void limen__rtc_ray(const limen__rtc *r, const double o[3], const double d[3], double tmin,
                    double tmax, limen__bvh_hit_fn hit, void *ctx)
{
    if (!r->counts[0] && !r->counts[1])
        return;
    /* the segment inside the scene's box, in double */
    double t0 = tmin, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < r->root.lo[k] || o[k] > r->root.hi[k])
                return;
            continue;
        }
        double a = (r->root.lo[k] - o[k]) / d[k], b = (r->root.hi[k] - o[k]) / d[k];
        t0 = fmax(t0, fmin(a, b));
        t1 = fmin(t1, fmax(a, b));
    }
    if (!(t0 <= t1))
        return;
    context c = { .r = r, .hit = hit, .ctx = ctx, .shift = t0, .tmax = tmax };
    rtcInitIntersectContext(&c.base);
    struct RTCRayHit rh;
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = (float)(o[0] + t0 * d[0]);
    rh.ray.org_y = (float)(o[1] + t0 * d[1]);
    rh.ray.org_z = (float)(o[2] + t0 * d[2]);
    rh.ray.dir_x = (float)d[0];
    rh.ray.dir_y = (float)d[1];
    rh.ray.dir_z = (float)d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = isfinite(tmax) ? nextafterf((float)(tmax - t0 + r->widen), INFINITY) : INFINITY;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(r->scene, &c.base, &rh);
}
