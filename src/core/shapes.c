/* shapes.c - the unit shapes' triangles (limen_unit_geometry): made once in the process, on
 * first use, and never changed after, so that every backend (limen's own, a game's) draws a
 * box, ball, cylinder or square from the same triangles. A curved shape comes in levels, one
 * per tessellation the draw list may ask for (limen_draw_cmd.segments): the coarsest whose
 * silhouette stays within a fraction of a pixel of the true shape, the ray tracer's. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/shapes.h"
#include "core/texture.h"

/* level k of a curved shape has limen__unit_segments[k] segments around: finest first */
const int limen__unit_segments[LIMEN__UNIT_LEVELS] = { 256, 192, 128, 96, 64, 48, 32, 24, 16,
                                                       12, 8 };

int limen__unit_level(int segments)
{
    int k = LIMEN__UNIT_LEVELS - 1;     /* the level with as many segments, or the next finer */
    while (k > 0 && limen__unit_segments[k] < segments)
        k--;
    return k;
}

/* One shape's arrays as they grow: positions, normals and uvs, each level's indices after
 * the last. */
typedef struct builder {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    uint32_t nverts, nidx, vcap, icap;
    int failed;
} builder;

/* A vertex; its uv by the rule of a box face, which is a square's too (limen_uv_rule): the
 * two other axes of the face's normal, in order, over [0, 1]. */
static uint32_t vert(builder *b, float px, float py, float pz, float nx, float ny, float nz)
{
    if (b->failed)
        return 0;
    if (b->nverts == b->vcap) {
        uint32_t cap = b->vcap ? b->vcap * 2 : 1024;
        float *p = realloc(b->pos, sizeof *p * 3 * cap);
        if (p)
            b->pos = p;
        float *n = p ? realloc(b->nrm, sizeof *n * 3 * cap) : NULL;
        if (n)
            b->nrm = n;
        float *uv = n ? realloc(b->uv, sizeof *uv * 2 * cap) : NULL;
        if (!uv) {
            b->failed = 1;
            return 0;
        }
        b->uv = uv;
        b->vcap = cap;
    }
    const float v[2][3] = { { px, py, pz }, { nx, ny, nz } };
    int a = fabsf(nx) > 0.5f ? 0 : fabsf(ny) > 0.5f ? 1 : 2;
    memcpy(b->pos + 3 * b->nverts, v[0], sizeof v[0]);
    memcpy(b->nrm + 3 * b->nverts, v[1], sizeof v[1]);
    b->uv[2 * b->nverts] = v[0][(a + 1) % 3] + 0.5f;
    b->uv[2 * b->nverts + 1] = v[0][(a + 2) % 3] + 0.5f;
    return b->nverts++;
}

static void tri(builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    if (b->failed)
        return;
    if (b->nidx + 3 > b->icap) {
        uint32_t cap = b->icap ? b->icap * 2 : 4096;
        uint32_t *p = realloc(b->idx, sizeof *p * cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->idx = p;
        b->icap = cap;
    }
    b->idx[b->nidx++] = i0;
    b->idx[b->nidx++] = i1;
    b->idx[b->nidx++] = i2;
}

/* Quad a-b-c-d, counter-clockwise seen from the front. */
static void quad4(builder *b, uint32_t a, uint32_t bb, uint32_t c, uint32_t d)
{
    tri(b, a, bb, c);
    tri(b, a, c, d);
}

static void build_box(builder *b, int segments)
{
    (void)segments;
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

static void build_square(builder *b, int segments)
{
    (void)segments;
    uint32_t a = vert(b, -0.5f, -0.5f, 0, 0, 0, 1);
    uint32_t c = vert(b, 0.5f, -0.5f, 0, 0, 0, 1);
    uint32_t d = vert(b, 0.5f, 0.5f, 0, 0, 0, 1);
    uint32_t e = vert(b, -0.5f, 0.5f, 0, 0, 0, 1);
    quad4(b, a, c, d, e);
}

/* Polygons inscribed in a curve fall inside it by their sagitta; pushing the vertices out
 * by f splits the error evenly inside and outside, halving the largest silhouette error
 * for the same triangles. A UV sphere's faces sag most at their centres, about
 * 1 - cos^2(pi/n) of the radius; a cylinder's sides at their middles, 1 - cos(pi/n). The
 * error either way is then f - 1. */
static double sphere_push(int slices)
{
    double c = cos(M_PI / slices);
    return 2.0 / (1.0 + c * c);
}

static double cylinder_push(int slices)
{
    return 2.0 / (1.0 + cos(M_PI / slices));
}

static void build_ball(builder *b, int slices)
{
    int stacks = slices / 2;
    uint32_t base = b->nverts;
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
    uint32_t base = b->nverts;
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
        uint32_t ring = b->nverts;
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

/* A unit shape's geometry, with what its public view points at. */
typedef struct unit {
    limen_mesh_geometry pub;
    limen_mesh_lod lods[LIMEN__UNIT_LEVELS];
    limen_mesh_part parts[LIMEN__UNIT_LEVELS];
    limen_material material;
    builder b;
} unit;

static _Atomic(unit *) units[LIMEN_UNIT_COUNT];
static pthread_mutex_t units_lock = PTHREAD_MUTEX_INITIALIZER;

/* What builds each shape, and whether it is curved (a level per tessellation, no uvs). */
static void (*builder_of(limen_unit_shape shape, bool *curved))(builder *, int)
{
    *curved = false;
    switch (shape) {
    case LIMEN_UNIT_NONE:
    case LIMEN_UNIT_COUNT:
        break;
    case LIMEN_UNIT_BOX:
        return build_box;
    case LIMEN_UNIT_SQUARE:
        return build_square;
    case LIMEN_UNIT_BALL:
        *curved = true;
        return build_ball;
    case LIMEN_UNIT_CYLINDER:
        *curved = true;
        return build_cylinder;
    }
    return NULL;
}

int limen__unit_levels(limen_unit_shape shape)
{
    bool curved;
    return !builder_of(shape, &curved) ? 0 : curved ? LIMEN__UNIT_LEVELS : 1;
}

/* Makes shape's geometry; NULL when out of memory. */
static unit *unit_make(limen_unit_shape shape)
{
    bool curved;
    void (*build)(builder *, int) = builder_of(shape, &curved);
    int levels = limen__unit_levels(shape);
    if (!build)
        return NULL;
    unit *u = calloc(1, sizeof *u);
    if (!u)
        return NULL;
    uint32_t first[LIMEN__UNIT_LEVELS + 1];
    for (int k = 0; k < levels; k++) {
        first[k] = u->b.nidx;
        int segments = limen__unit_segments[k];
        build(&u->b, segments);
        double c = cos(M_PI / segments), err = shape == LIMEN_UNIT_BALL ? (1 - c * c) / (1 + c * c)
                                             : (1 - c) / (1 + c);
        u->lods[k].error = levels > 1 ? (float)err : 0.0f;
    }
    first[levels] = u->b.nidx;
    if (u->b.failed) {
        free(u->b.pos), free(u->b.nrm), free(u->b.uv), free(u->b.idx), free(u);
        return NULL;
    }
    u->material = (limen_material){ .name = "", .base_color = { 1, 1, 1, 1 },
                                    .base_transform = { 1, 0, 0, 1, 0, 0 },
                                    .alpha_mode = LIMEN_ALPHA_OPAQUE, .alpha_cutoff = 0.5f,
                                    .roughness = 1, .normal_scale = 1, .occlusion_strength = 1 };
    for (int k = 0; k < levels; k++) {
        int tris = (int)(first[k + 1] - first[k]) / 3;
        u->parts[k] = (limen_mesh_part){ 0, tris, 0 };
        u->lods[k].indices = u->b.idx + first[k];
        u->lods[k].triangle_count = tris;
        u->lods[k].parts = &u->parts[k];
    }
    u->pub = (limen_mesh_geometry){ .id = limen__next_serial(), .vertex_count = (int)u->b.nverts,
                                    .triangle_count = u->lods[0].triangle_count,
                                    .positions = u->b.pos, .normals = u->b.nrm,
                                    .uvs = curved ? NULL : u->b.uv,
                                    .indices = u->lods[0].indices, .lod_count = levels,
                                    .lods = u->lods, .part_count = 1, .parts = u->parts,
                                    .material_count = 1, .materials = &u->material };
    return u;
}

const limen_mesh_geometry *limen_unit_geometry(limen_unit_shape shape)
{
    if ((unsigned)shape >= LIMEN_UNIT_COUNT || shape == LIMEN_UNIT_NONE)
        return NULL;
    unit *u = atomic_load(&units[shape]);
    if (!u) {
        pthread_mutex_lock(&units_lock);
        u = atomic_load(&units[shape]);
        if (!u && (u = unit_make(shape)))
            atomic_store(&units[shape], u);
        pthread_mutex_unlock(&units_lock);
    }
    return u ? &u->pub : NULL;
}
