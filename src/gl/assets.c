/* assets.c - what the renderer keeps on the GPU for mesh and texture assets: one vertex
 * buffer per mesh asset and one texture per image, shared by every node that shows it, kept
 * while a frame uses them and dropped after the first frame that does not.
 *
 * A flat-shaded mesh is drawn unindexed, three corners per triangle, each with its
 * position, its triangle's face normal (computed as the ray tracer does), its vertex normal
 * and, where the mesh has them, its texture coordinates and colour (else one of each in a
 * buffer of their own that every corner reads). Smooth shading needs no face normal, so a smooth mesh's own
 * vertices are drawn indexed instead, which runs the vertex shader about once per vertex
 * rather than once per corner (its corners stand in where that buffer cannot be made). Each
 * buffer is made when a draw first needs it: the smooth one holds the levels of detail one
 * after another (their indices), the corners a buffer a level. Both vertex arrays also read the renderer's instance buffer (gl/batch.c): a
 * model matrix, a normal matrix and an albedo per node. */
#include <stdlib.h>
#include <string.h>

#include "gl/gl_internal.h"

#ifndef GL_REPEAT
#define GL_REPEAT 0x2901
#endif
#ifndef GL_RGB8
#define GL_RGB8 0x8051
#endif
#ifndef GL_RGBA8
#define GL_RGBA8 0x8058
#endif
#ifndef GL_RGBA
#define GL_RGBA 0x1908
#endif
#ifndef GL_UNPACK_ALIGNMENT
#define GL_UNPACK_ALIGNMENT 0x0CF5
#endif
#ifndef GL_TEXTURE_MAX_LEVEL
#define GL_TEXTURE_MAX_LEVEL 0x813D
#endif
#ifndef GL_NEAREST
#define GL_NEAREST 0x2600
#endif
#ifndef GL_LINEAR_MIPMAP_LINEAR
#define GL_LINEAR_MIPMAP_LINEAR 0x2703
#endif

/* a corner: position, face normal, vertex normal, then texture coordinates and colour where
 * the mesh has them (a mesh without takes them from a buffer of one of each, read by every
 * corner: a 1.6M-triangle mesh's corners are 115 MB less) */
enum { CORNER_FLOATS = 9, AT_FLAT = 3, AT_SMOOTH = 6, UV_FLOATS = 2, COL_FLOATS = 4 };
#define EVERY_CORNER (1u << 30)         /* an instanced attribute's divisor no draw reaches:
                                         * every corner of every instance reads element 0 */
enum { GPU_LODS = 16 };         /* levels kept; a coarser one asked for gets the last */

struct limen__gpu_asset {
    uint64_t serial;
    GLuint vao[GPU_LODS], vbo[GPU_LODS];        /* a mesh's corners, each level's own */
    GLuint tex;                 /* an image's texture */
    GLuint cvbo;                /* the texture coordinates and colour of every corner, for a
                                 * mesh without its own */
    int corner_floats;          /* floats a corner */
    GLuint svao, svbo, sibo;    /* smooth: the vertices, and each level's indices */
    GLint sfirst[GPU_LODS];     /* each level's first index and indices */
    GLsizei scount[GPU_LODS];
    bool used;                  /* by the frame being drawn */
    int filter;                 /* textures: the limen_texture_filter last set, + 1 */
};

static struct limen__gpu_asset *find(limen_renderer *r, uint64_t serial)
{
    for (int i = 0; i < r->nassets; i++)
        if (r->assets[i].serial == serial) {
            r->assets[i].used = true;
            return &r->assets[i];
        }
    if (r->nassets == r->assets_cap) {
        int cap = r->assets_cap ? r->assets_cap * 2 : 16;
        struct limen__gpu_asset *a = realloc(r->assets, sizeof *a * (size_t)cap);
        if (!a)
            return NULL;
        r->assets = a;
        r->assets_cap = cap;
    }
    struct limen__gpu_asset *a = &r->assets[r->nassets++];
    memset(a, 0, sizeof *a);
    a->serial = serial;
    a->used = true;
    return a;
}

static void face_normal(const limen_mesh_geometry *m, const uint32_t *ix, float n[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)m->positions[ix[1] * 3 + k] - m->positions[ix[0] * 3 + k];
        e2[k] = (double)m->positions[ix[2] * 3 + k] - m->positions[ix[0] * 3 + k];
    }
    double c[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0] };
    double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; k++)
        n[k] = len > 0 ? (float)(c[k] / len) : 0.0f;
}

/* Floats a corner of m holds. */
static int corner_floats(const limen_mesh_geometry *m)
{
    return CORNER_FLOATS + (m->uvs ? UV_FLOATS : 0) + (m->colors ? COL_FLOATS : 0);
}

/* The corners of ntris triangles (their indices ix) from buf on. */
static float *lay_corners(const limen_mesh_geometry *m, const uint32_t *ix, int ntris, float *buf)
{
    for (int t = 0; t < ntris; t++, ix += 3) {
        float fn[3];
        face_normal(m, ix, fn);
        for (int k = 0; k < 3; k++) {
            memcpy(buf, &m->positions[ix[k] * 3], sizeof(float) * 3);
            memcpy(buf + AT_FLAT, fn, sizeof fn);
            memcpy(buf + AT_SMOOTH, &m->normals[ix[k] * 3], sizeof(float) * 3);
            buf += CORNER_FLOATS;
            if (m->uvs) {
                memcpy(buf, &m->uvs[ix[k] * 2], sizeof(float) * UV_FLOATS);
                buf += UV_FLOATS;
            }
            if (m->colors) {
                memcpy(buf, &m->colors[ix[k] * 4], sizeof(float) * COL_FLOATS);
                buf += COL_FLOATS;
            }
        }
    }
    return buf;
}

/* Per-instance attributes from the instance buffer: model matrix (locations 3-6), normal
 * matrix (7-9), albedo (10), as gl/batch.c lays them. */
static void instance_arrays(limen_renderer *r)
{
    if (!r->inst_vbo)
        GL(GenBuffers)(1, &r->inst_vbo);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->inst_vbo);
    const GLsizei stride = sizeof(float) * LIMEN__INSTANCE_FLOATS;
    for (int i = 0; i < 8; i++) {
        int size = i < 4 ? 4 : 3, at = i < 4 ? 4 * i : 16 + 3 * (i - 4);
        GL(EnableVertexAttribArray)((GLuint)(3 + i));
        GL(VertexAttribPointer)((GLuint)(3 + i), size, GL_FLOAT, GL_FALSE, stride,
                                (void *)(sizeof(float) * (size_t)at));
        GL(VertexAttribDivisor)((GLuint)(3 + i), 1);
    }
}

/* A new vertex array (bound) with a new array buffer holding `bytes` of data. */
static void vertex_arrays(limen_renderer *r, GLuint *vao, GLuint *vbo, size_t bytes,
                          const void *data)
{
    GL(GenVertexArrays)(1, vao);
    GL(BindVertexArray)(*vao);
    GL(GenBuffers)(1, vbo);
    GL(BindBuffer)(GL_ARRAY_BUFFER, *vbo);
    GL(BufferData)(GL_ARRAY_BUFFER, (GLsizeiptr)bytes, data, GL_STATIC_DRAW);
}

/* The levels kept of mesh m (a mesh without levels is its own level 0). */
static int levels(const limen_mesh_geometry *m)
{
    return !m->lods || m->lod_count < 1 ? 1 : m->lod_count > GPU_LODS ? GPU_LODS : m->lod_count;
}

/* Level k of mesh m: its indices, and its triangles (returned). */
static int level(const limen_mesh_geometry *m, int k, const uint32_t **ix)
{
    if (!m->lods || m->lod_count < 1) {
        *ix = m->indices;
        return m->triangle_count;
    }
    *ix = m->lods[k].indices;
    return m->lods[k].triangle_count;
}

/* Corners (three a triangle) of all kept levels together. */
static size_t level_corners(const limen_mesh_geometry *m)
{
    size_t n = 0;
    const uint32_t *ix;
    for (int k = 0; k < levels(m); k++)
        n += (size_t)level(m, k, &ix) * 3;
    return n;
}

/* Scratch memory for an upload; NULL where the test fault LIMEN__RFAULT_UPLOAD is on. */
static void *upload_alloc(const limen_renderer *r, size_t bytes)
{
    return r->faults & LIMEN__RFAULT_UPLOAD ? NULL : malloc(bytes);
}

enum { STAGE_TRIS = 16384 };     /* triangles laid out at a time for an upload */

/* Level k's corners, a buffer of their own made when a draw first needs that level: a
 * mesh drawn at one level holds no other's (a 1.6M-triangle mesh's levels together hold as
 * many corners as the mesh again). They go up a slice of triangles at a time, so that what
 * the upload holds besides the buffer itself stays small however big the mesh. */
static bool upload_level(limen_renderer *r, const limen_mesh_geometry *m,
                         struct limen__gpu_asset *a, int k)
{
    const uint32_t *ix;
    int ntris = level(m, k, &ix), stage = ntris < STAGE_TRIS ? ntris : STAGE_TRIS;
    const int cf = corner_floats(m);
    const GLsizei stride = (GLsizei)sizeof(float) * cf;
    float *buf = upload_alloc(r, sizeof(float) * (size_t)cf * 3 * (size_t)(stage ? stage : 1));
    if (!buf)
        return false;
    a->corner_floats = cf;
    vertex_arrays(r, &a->vao[k], &a->vbo[k], sizeof(float) * (size_t)cf * 3 * (size_t)ntris,
                  NULL);
    for (int t = 0; t < ntris; t += STAGE_TRIS) {
        int n = ntris - t < STAGE_TRIS ? ntris - t : STAGE_TRIS;
        lay_corners(m, ix + (size_t)t * 3, n, buf);
        GL(BufferSubData)(GL_ARRAY_BUFFER, (GLintptr)(sizeof(float) * (size_t)cf * 3 * (size_t)t),
                          (GLsizeiptr)(sizeof(float) * (size_t)cf * 3 * (size_t)n), buf);
    }
    free(buf);
    GL(EnableVertexAttribArray)(0);
    GL(VertexAttribPointer)(0, 3, GL_FLOAT, GL_FALSE, stride, (void *)0);
    GL(EnableVertexAttribArray)(1);
    size_t at_uv = CORNER_FLOATS, at_col = at_uv + (m->uvs ? UV_FLOATS : 0);
    GL(EnableVertexAttribArray)(2);
    if (m->uvs)
        GL(VertexAttribPointer)(2, 2, GL_FLOAT, GL_FALSE, stride, (void *)(sizeof(float) * at_uv));
    GL(EnableVertexAttribArray)(11);    /* vertex colours (materials) */
    if (m->colors)
        GL(VertexAttribPointer)(11, 4, GL_FLOAT, GL_FALSE, stride,
                                (void *)(sizeof(float) * at_col));
    if (!m->uvs || !m->colors) {
        /* what a mesh without them reads at every corner: (0, 0) and white */
        static const float every[UV_FLOATS + COL_FLOATS] = { 0, 0, 1, 1, 1, 1 };
        if (!a->cvbo) {
            GL(GenBuffers)(1, &a->cvbo);
            GL(BindBuffer)(GL_ARRAY_BUFFER, a->cvbo);
            GL(BufferData)(GL_ARRAY_BUFFER, sizeof every, every, GL_STATIC_DRAW);
        }
        GL(BindBuffer)(GL_ARRAY_BUFFER, a->cvbo);
        if (!m->uvs) {
            GL(VertexAttribPointer)(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
            GL(VertexAttribDivisor)(2, EVERY_CORNER);
        }
        if (!m->colors) {
            GL(VertexAttribPointer)(11, 4, GL_FLOAT, GL_FALSE, 0,
                                    (void *)(sizeof(float) * UV_FLOATS));
            GL(VertexAttribDivisor)(11, EVERY_CORNER);
        }
    }
    instance_arrays(r);
    GL(BindBuffer)(GL_ARRAY_BUFFER, a->vbo[k]);
    return true;
}

enum { VERTEX_FLOATS = 12 };    /* smooth: position, vertex normal, texture coordinates,
                                 * colour */

static bool upload_smooth(limen_renderer *r, const limen_mesh_geometry *m,
                          struct limen__gpu_asset *a)
{
    size_t nv = (size_t)m->vertex_count, nidx = level_corners(m);
    float *buf = upload_alloc(r, sizeof(float) * VERTEX_FLOATS * nv);
    uint32_t *idx = upload_alloc(r, sizeof(uint32_t) * nidx), *at = idx;
    if (!buf || !idx) {
        free(buf);
        free(idx);
        return false;
    }
    for (size_t v = 0; v < nv; v++) {
        float *c = buf + v * VERTEX_FLOATS;
        memcpy(c, &m->positions[v * 3], sizeof(float) * 3);
        memcpy(c + 3, &m->normals[v * 3], sizeof(float) * 3);
        c[6] = m->uvs ? m->uvs[v * 2] : 0.0f;
        c[7] = m->uvs ? m->uvs[v * 2 + 1] : 0.0f;
        for (int k = 0; k < 4; k++)
            c[8 + k] = m->colors ? m->colors[v * 4 + k] : 1.0f;
    }
    for (int k = 0; k < levels(m); k++) {
        const uint32_t *ix;
        size_t n = (size_t)level(m, k, &ix) * 3;
        a->sfirst[k] = (GLint)(at - idx);
        a->scount[k] = (GLsizei)n;
        memcpy(at, ix, sizeof(uint32_t) * n);
        at += n;
    }
    vertex_arrays(r, &a->svao, &a->svbo, sizeof(float) * VERTEX_FLOATS * nv, buf);
    GL(GenBuffers)(1, &a->sibo);
    GL(BindBuffer)(GL_ELEMENT_ARRAY_BUFFER, a->sibo);
    GL(BufferData)(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * nidx), idx,
                   GL_STATIC_DRAW);
    free(buf);
    free(idx);
    const GLsizei stride = sizeof(float) * VERTEX_FLOATS;
    for (int i = 0; i < 3; i++) {
        GL(EnableVertexAttribArray)((GLuint)i);
        GL(VertexAttribPointer)((GLuint)i, i == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, stride,
                                (void *)(sizeof(float) * 3 * (size_t)i));
    }
    GL(EnableVertexAttribArray)(11);
    GL(VertexAttribPointer)(11, 4, GL_FLOAT, GL_FALSE, stride, (void *)(sizeof(float) * 8));
    instance_arrays(r);
    return true;
}

bool limen__gpu_mesh_bind(limen_renderer *r, const limen_mesh_geometry *m, bool smooth, int lod,
                          GLint *first, GLsizei *count, bool *indexed)
{
    struct limen__gpu_asset *a = find(r, m->id);
    if (!a) {
        limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory for the meshes' list");
        return false;
    }
    int nlods = levels(m);
    lod = lod < 0 ? 0 : lod >= nlods ? nlods - 1 : lod;
    /* each buffer is made when a draw first needs it: a mesh only ever drawn smooth has no
     * corners (the corners stand in where the smooth buffer cannot be made) */
    *indexed = smooth && (a->svao || upload_smooth(r, m, a));
    if (*indexed) {
        GL(BindVertexArray)(a->svao);
        *first = a->sfirst[lod];
        *count = a->scount[lod];
        return true;
    }
    if (!a->vao[lod] && !upload_level(r, m, a, lod)) {
        limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory uploading a mesh of %d triangles "
                         "(it is not drawn)", m->triangle_count);
        return false;
    }
    GL(BindVertexArray)(a->vao[lod]);
    GL(BindBuffer)(GL_ARRAY_BUFFER, a->vbo[lod]);
    GL(VertexAttribPointer)(1, 3, GL_FLOAT, GL_FALSE, (GLsizei)sizeof(float) * a->corner_floats,
                            (void *)(sizeof(float) * (smooth ? AT_SMOOTH : AT_FLAT)));
    const uint32_t *ix;
    *first = 0;
    *count = (GLsizei)level(m, lod, &ix) * 3;
    return true;
}

int limen__gpu_mesh_level(const limen_mesh_geometry *m, int lod)
{
    int nlods = levels(m);
    return lod < 0 ? 0 : lod >= nlods ? nlods - 1 : lod;
}

/* Uploads image t with its mipmap levels (limen_image.levels: the texels the ray tracer
 * samples, rows bottom first: GL's t = 0 is the image's bottom row, as v = 0 is). */
static bool upload_texture(limen_renderer *r, const limen_image *t, struct limen__gpu_asset *a)
{
    /* an image with alpha (a model's own) goes up RGBA, at one level (it has no others) */
    int ch = t->alpha ? 4 : 3;
    unsigned char *flip = upload_alloc(r, (size_t)t->width * (size_t)t->height * (size_t)ch);
    if (!flip)
        return false;
    GL(GenTextures)(1, &a->tex);
    GL(BindTexture)(GL_TEXTURE_2D, a->tex);
    GL(PixelStorei)(GL_UNPACK_ALIGNMENT, 1);
    int nlevels = t->levels && t->level_count > 0 && !t->alpha ? t->level_count : 1;
    for (int k = 0; k < nlevels; k++) {
        limen_image_level l = t->levels ? t->levels[k]
                                        : (limen_image_level){ t->width, t->height, t->rgb };
        size_t row = (size_t)l.width * 3;
        for (int j = 0; j < l.height && ch == 3; j++)
            memcpy(flip + (size_t)j * row, l.rgb + (size_t)(l.height - 1 - j) * row, row);
        for (int j = 0; j < l.height && ch == 4; j++) {
            const unsigned char *src = l.rgb + (size_t)(l.height - 1 - j) * row;
            const unsigned char *al = t->alpha + (size_t)(l.height - 1 - j) * (size_t)l.width;
            unsigned char *dst = flip + (size_t)j * l.width * 4;
            for (int i = 0; i < l.width; i++) {
                memcpy(dst + i * 4, src + i * 3, 3);
                dst[i * 4 + 3] = al[i];
            }
        }
        GL(TexImage2D)(GL_TEXTURE_2D, k, ch == 4 ? GL_RGBA8 : GL_RGB8, l.width, l.height, 0,
                       ch == 4 ? GL_RGBA : GL_RGB, GL_UNSIGNED_BYTE, flip);
    }
    GL(PixelStorei)(GL_UNPACK_ALIGNMENT, 4);
    free(flip);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, nlevels - 1);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return true;
}

GLuint limen__gpu_texture(limen_renderer *r, const limen_image *t, limen_texture_filter filter)
{
    return limen__gpu_texture_on(r, t, 1, filter);
}

GLuint limen__gpu_texture_on(limen_renderer *r, const limen_image *t, int unit,
                             limen_texture_filter filter)
{
    struct limen__gpu_asset *a = find(r, t->id);
    if (!a) {
        limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory for the textures' list");
        return 0;
    }
    /* albedo textures live on unit 1 (unit 0 holds the texture method's view images) */
    GL(ActiveTexture)(GL_TEXTURE0 + (GLenum)unit);
    if (a->tex)
        GL(BindTexture)(GL_TEXTURE_2D, a->tex);
    else if (!upload_texture(r, t, a)) {
        limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory uploading a %dx%d texture (it "
                         "is not drawn)", t->width, t->height);
        GL(ActiveTexture)(GL_TEXTURE0);
        return 0;
    }
    /* the sampling state lives in the texture object: set where the draw wants another */
    if (a->filter != (int)filter + 1) {
        GLint min = filter == LIMEN_FILTER_NEAREST ? GL_NEAREST
                    : filter == LIMEN_FILTER_LINEAR ? GL_LINEAR
                                                    : GL_LINEAR_MIPMAP_LINEAR;
        GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min);
        GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER,
                          filter == LIMEN_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR);
        a->filter = (int)filter + 1;
    }
    GL(ActiveTexture)(GL_TEXTURE0);
    return a->tex;
}

static void drop(limen_renderer *r, struct limen__gpu_asset *a)
{
    for (int k = 0; k < GPU_LODS; k++) {
        if (a->vbo[k])
            GL(DeleteBuffers)(1, &a->vbo[k]);
        if (a->vao[k])
            GL(DeleteVertexArrays)(1, &a->vao[k]);
    }
    if (a->cvbo)
        GL(DeleteBuffers)(1, &a->cvbo);
    if (a->svao) {
        GL(DeleteVertexArrays)(1, &a->svao);
        GL(DeleteBuffers)(1, &a->svbo);
        GL(DeleteBuffers)(1, &a->sibo);
    }
    if (a->tex)
        GL(DeleteTextures)(1, &a->tex);
}

void limen__gpu_assets_sweep(limen_renderer *r)
{
    int kept = 0;
    for (int i = 0; i < r->nassets; i++) {
        if (!r->assets[i].used) {
            drop(r, &r->assets[i]);
            continue;
        }
        r->assets[i].used = false;
        r->assets[kept++] = r->assets[i];
    }
    r->nassets = kept;
}

void limen__gpu_assets_free(limen_renderer *r)
{
    for (int i = 0; i < r->nassets; i++)
        drop(r, &r->assets[i]);
    free(r->assets);
    r->assets = NULL;
    r->nassets = r->assets_cap = 0;
}
