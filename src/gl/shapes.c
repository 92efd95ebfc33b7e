/* shapes.c - builds the unit meshes once per renderer. Curved shapes come in levels of
 * detail: the draw list says, per view, how many segments (the coarsest whose silhouette
 * stays within a fraction of a pixel of the true shape, the ray tracer's). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gl_internal.h"
#include "gl/shapes.h"

const int limen__lod_segments[LIMEN__LODS] = { 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256 };

typedef struct builder {
    limen__meshes *m;
    uint32_t vcap, icap;
    int failed;
} builder;

static uint32_t vert(builder *b, float px, float py, float pz, float nx, float ny, float nz)
{
    limen__meshes *m = b->m;
    if (m->nverts == b->vcap) {
        uint32_t cap = b->vcap ? b->vcap * 2 : 1024;
        limen__vertex *v = realloc(m->verts, sizeof *v * cap);
        if (!v) {
            b->failed = 1;
            return 0;
        }
        m->verts = v;
        b->vcap = cap;
    }
    m->verts[m->nverts] = (limen__vertex){ { px, py, pz }, { nx, ny, nz } };
    return m->nverts++;
}

static void tri(builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    limen__meshes *m = b->m;
    if (b->failed)
        return;
    if (m->nidx + 3 > b->icap) {
        uint32_t cap = b->icap ? b->icap * 2 : 4096;
        uint32_t *p = realloc(m->idx, sizeof *p * cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        m->idx = p;
        b->icap = cap;
    }
    m->idx[m->nidx++] = i0;
    m->idx[m->nidx++] = i1;
    m->idx[m->nidx++] = i2;
}

/* Quad a-b-c-d, counter-clockwise seen from the front. */
static void quad4(builder *b, uint32_t a, uint32_t bb, uint32_t c, uint32_t d)
{
    tri(b, a, bb, c);
    tri(b, a, c, d);
}

static void build_box(builder *b)
{
    /* For each face: normal axis, sign; two tangent axes forming a right-handed frame. */
    for (int axis = 0; axis < 3; axis++) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            float n[3] = { 0, 0, 0 };
            n[axis] = (float)sgn;
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            uint32_t ids[4];
            static const float uv[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
            for (int k = 0; k < 4; k++) {
                float p[3];
                p[axis] = 0.5f * (float)sgn;
                p[u] = 0.5f * uv[k][0];
                p[v] = 0.5f * uv[k][1];
                ids[k] = vert(b, p[0], p[1], p[2], n[0], n[1], n[2]);
            }
            /* u x v = +axis, so (u,v) order is CCW from +axis; reverse for the -axis face. */
            if (sgn > 0)
                quad4(b, ids[0], ids[1], ids[2], ids[3]);
            else
                quad4(b, ids[0], ids[3], ids[2], ids[1]);
        }
    }
}

static void build_quad(builder *b)
{
    uint32_t a = vert(b, -0.5f, -0.5f, 0, 0, 0, 1);
    uint32_t c = vert(b, 0.5f, -0.5f, 0, 0, 0, 1);
    uint32_t d = vert(b, 0.5f, 0.5f, 0, 0, 0, 1);
    uint32_t e = vert(b, -0.5f, 0.5f, 0, 0, 0, 1);
    quad4(b, a, c, d, e);
}

/* Polygons inscribed in a curve fall inside it by their sagitta; pushing the vertices out
 * by f splits the error evenly inside and outside, halving the largest silhouette error
 * for the same triangles. A UV sphere's faces sag most at their centres, about
 * 1 - cos^2(pi/n) of the radius; a cylinder's sides at their middles, 1 - cos(pi/n). */
static double sphere_push(int slices)
{
    double c = cos(M_PI / slices);
    return 2.0 / (1.0 + c * c);
}

static double cylinder_push(int slices)
{
    return 2.0 / (1.0 + cos(M_PI / slices));
}

static void build_sphere(builder *b, int slices)
{
    int stacks = slices / 2;
    uint32_t base = b->m->nverts;
    float f = (float)sphere_push(slices);
    for (int i = 0; i <= stacks; i++) {
        double phi = M_PI * i / stacks;     /* from +Y down */
        for (int j = 0; j <= slices; j++) {
            double th = 2.0 * M_PI * j / slices;
            float x = (float)(sin(phi) * cos(th)), y = (float)cos(phi),
                  z = (float)(-sin(phi) * sin(th));
            vert(b, f * x, f * y, f * z, x, y, z);
        }
    }
    for (int i = 0; i < stacks; i++) {
        for (int j = 0; j < slices; j++) {
            uint32_t a = base + (uint32_t)(i * (slices + 1) + j), c = a + (uint32_t)slices + 1;
            /* th grows towards -z seen from above: (a, c, c+1) is CCW from outside */
            /* the top row's (a, c+1, a+1) and the bottom row's (a, c, c+1) would have two
             * corners on the pole: zero area; the other triangle of each quad closes it */
            if (i != stacks - 1)
                tri(b, a, c, c + 1);
            if (i != 0)
                tri(b, a, c + 1, a + 1);
        }
    }
}

static void build_cylinder(builder *b, int slices)
{
    uint32_t base = b->m->nverts;
    float f = (float)cylinder_push(slices);
    for (int j = 0; j <= slices; j++) {
        double th = 2.0 * M_PI * j / slices;
        float x = (float)cos(th), z = (float)-sin(th);
        vert(b, f * x, 0, f * z, x, 0, z);
        vert(b, f * x, 1, f * z, x, 0, z);
    }
    for (int j = 0; j < slices; j++) {
        uint32_t a = base + (uint32_t)(2 * j);
        quad4(b, a, a + 2, a + 3, a + 1);
    }
    for (int cap = 0; cap < 2; cap++) {
        float y = (float)cap, ny = cap ? 1.0f : -1.0f;
        uint32_t centre = vert(b, 0, y, 0, 0, ny, 0);
        uint32_t ring = b->m->nverts;
        for (int j = 0; j < slices; j++) {
            double th = 2.0 * M_PI * j / slices;
            vert(b, f * (float)cos(th), y, f * (float)-sin(th), 0, ny, 0);
        }
        for (int j = 0; j < slices; j++) {
            uint32_t p = ring + (uint32_t)j, q = ring + (uint32_t)((j + 1) % slices);
            if (cap)
                tri(b, centre, p, q);
            else
                tri(b, centre, q, p);
        }
    }
}

typedef void (*build_fn)(builder *b);

int limen__meshes_build(limen__meshes *m)
{
    memset(m, 0, sizeof *m);
    builder b = { m, 0, 0, 0 };
    uint32_t first = 0;
#define RANGE(dst, call)                                                                 \
    do {                                                                                 \
        first = m->nidx;                                                                 \
        call;                                                                            \
        (dst) = (limen__range){ first, m->nidx - first };                                \
    } while (0)
    RANGE(m->box, build_box(&b));
    RANGE(m->quad, build_quad(&b));
    for (int l = 0; l < LIMEN__LODS; l++) {
        RANGE(m->sphere[l], build_sphere(&b, limen__lod_segments[l]));
        RANGE(m->cylinder[l], build_cylinder(&b, limen__lod_segments[l]));
    }
#undef RANGE
    if (b.failed) {
        limen__meshes_free(m);
        return -1;
    }
    return 0;
}

void limen__meshes_free(limen__meshes *m)
{
    free(m->verts);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/* Which mesh, and how the unit mesh is scaled, for a node (gl_internal.h): the unit shape
 * its kind draws as, stretched along each local axis by the dim the kind's facts name. */
bool limen__unit_mesh(limen_renderer *r, const limen_drawable *node, int segments,
                      limen__range *range, vec3 scale, int *shape)
{
    const limen_kind_info *k = limen_kind_get(node->kind);
    if (!k)
        return false;
    for (int a = 0; a < 3; a++)
        scale[a] = k->scale[a] >= 0 ? node->dims[k->scale[a]] : 1.0f;
    *shape = 0;
    switch (k->unit) {
    case LIMEN_UNIT_NONE:
    case LIMEN_UNIT_COUNT:
        return false;
    case LIMEN_UNIT_BOX:
        *range = r->meshes.box;
        return true;
    case LIMEN_UNIT_SQUARE:
        *range = r->meshes.quad;
        return true;
    case LIMEN_UNIT_BALL:
        *shape = LIMEN__SHAPE_SPHERE;
        break;
    case LIMEN_UNIT_CYLINDER:
        *shape = LIMEN__SHAPE_CYLINDER;
        break;
    }
    /* the draw list's tessellation (limen_draw_cmd.segments): the level that has as many
     * segments, or the next finer */
    int lod = 0;
    while (lod < LIMEN__LODS - 1 && limen__lod_segments[lod] < segments)
        lod++;
    *range = *shape == LIMEN__SHAPE_SPHERE ? r->meshes.sphere[lod] : r->meshes.cylinder[lod];
    return true;
}
