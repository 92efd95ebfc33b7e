/* assets.c - what the renderer keeps on the GPU for mesh and texture assets: vertex and
 * index buffers per mesh asset and one texture per image, shared by every node that shows
 * it, kept while a frame uses them and dropped after the first frame that does not.
 *
 * Every mesh is drawn indexed. A flat-shaded mesh shows each triangle's face normal
 * (computed as the ray tracer does), which the shaders take from the triangle's provoking
 * vertex (its last corner, GL's default convention) as a flat varying: so each triangle's
 * last corner is a vertex that holds its face normal, a vertex of the mesh where no earlier
 * triangle has taken it, else a copy of one, and its other corners share the mesh's
 * vertices. A 1.6M-triangle sphere is then about 1.6M vertices of 24 bytes and its indices
 * (58 MB), not 4.8M corners of 36 bytes (173 MB), and draws the same pixels. A vertex holds
 * texture coordinates and a colour only where the mesh has them (else one of each in a
 * buffer of their own that every vertex reads). Smooth shading interpolates the vertex
 * normals, so a smooth mesh's own vertices are drawn as they are. Each buffer is made when a
 * draw first needs it: the smooth one holds the levels of detail one after another (their
 * indices), the flat ones a level each. Both vertex arrays also read the renderer's instance
 * buffer (gl/batch.c): a model matrix, a normal matrix and an albedo per node. */
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

/* a flat vertex: position, normal (a triangle's face normal where it is one's last corner),
 * then texture coordinates and colour where the mesh has them (a mesh without takes them
 * from a buffer of one of each, read by every vertex) */
enum { FLAT_FLOATS = 6, UV_FLOATS = 2, COL_FLOATS = 4 };
#define EVERY_CORNER (1u << 30)         /* an instanced attribute's divisor no draw reaches:
                                         * every corner of every instance reads element 0 */
enum { GPU_LODS = 16 };         /* levels kept; a coarser one asked for gets the last */

struct limen__gpu_asset {
    uint64_t serial;
    GLuint vao[GPU_LODS], vbo[GPU_LODS], ibo[GPU_LODS];     /* flat: each level's own */
    GLuint tex;                 /* an image's texture */
    GLuint cvbo;                /* the texture coordinates and colour of every vertex, for a
                                 * mesh without its own */
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

/* Floats a flat vertex of m holds. */
static int flat_floats(const limen_mesh_geometry *m)
{
    return FLAT_FLOATS + (m->uvs ? UV_FLOATS : 0) + (m->colors ? COL_FLOATS : 0);
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

enum { STAGE = 16384 };         /* triangles or vertices laid out at a time for an upload */
#define NO_VERTEX UINT32_MAX
#define TAKEN 0x80000000u       /* a flat vertex that is triangle (what & ~TAKEN)'s last
                                 * corner; else what names the mesh's vertex it copies */

/* The attributes of a vertex array whose buffer holds `floats` floats a vertex:
 * position, normal, then texture coordinates and colour where m has them (else every
 * vertex reads one of each from a buffer of their own), then the instances'. */
static void vertex_attributes(limen_renderer *r, const limen_mesh_geometry *m,
                              struct limen__gpu_asset *a, int floats)
{
    const GLsizei stride = (GLsizei)sizeof(float) * floats;
    GL(EnableVertexAttribArray)(0);
    GL(VertexAttribPointer)(0, 3, GL_FLOAT, GL_FALSE, stride, (void *)0);
    GL(EnableVertexAttribArray)(1);
    GL(VertexAttribPointer)(1, 3, GL_FLOAT, GL_FALSE, stride, (void *)(sizeof(float) * 3));
    size_t at_uv = FLAT_FLOATS, at_col = at_uv + (m->uvs ? UV_FLOATS : 0);
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
}

/* Level k drawn flat, buffers of its own made when a draw first needs that level (a mesh
 * drawn at one level holds no other's): its indices, each triangle's last corner a vertex
 * holding its face normal (the mesh's own vertex where no triangle before has taken it,
 * else a copy), the others the mesh's vertices as they are; then those vertices. Both go up
 * a slice at a time, so that what the upload holds besides the buffers stays small (a word
 * per vertex of the mesh and per vertex made) however big the mesh. */
static bool upload_level(limen_renderer *r, const limen_mesh_geometry *m,
                         struct limen__gpu_asset *a, int k)
{
    const uint32_t *ix;
    size_t ntris = (size_t)level(m, k, &ix), nv = (size_t)m->vertex_count;
    const int vf = flat_floats(m);
    /* map: each mesh vertex's vertex here, or NO_VERTEX; what: of each vertex here, TAKEN |
     * the triangle whose last corner it is, or the mesh's vertex it copies */
    uint32_t *map = upload_alloc(r, sizeof(uint32_t) * (nv ? nv : 1));
    uint32_t *what = upload_alloc(r, sizeof(uint32_t) * (nv + ntris ? nv + ntris : 1));
    uint32_t *sidx = upload_alloc(r, sizeof(uint32_t) * 3 * STAGE);
    float *svtx = upload_alloc(r, sizeof(float) * (size_t)vf * STAGE);
    if (!map || !what || !sidx || !svtx) {
        free(map);
        free(what);
        free(sidx);
        free(svtx);
        return false;
    }
    memset(map, 0xff, sizeof(uint32_t) * nv);
    GL(GenVertexArrays)(1, &a->vao[k]);
    GL(BindVertexArray)(a->vao[k]);
    GL(GenBuffers)(1, &a->ibo[k]);
    GL(BindBuffer)(GL_ELEMENT_ARRAY_BUFFER, a->ibo[k]);
    GL(BufferData)(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * 3 * ntris), NULL,
                   GL_STATIC_DRAW);
    uint32_t made = 0;
    for (size_t t0 = 0; t0 < ntris; t0 += STAGE) {
        size_t n = ntris - t0 < STAGE ? ntris - t0 : STAGE;
        for (size_t i = 0; i < n; i++) {
            const uint32_t *c = &ix[(t0 + i) * 3];
            for (int j = 0; j < 2; j++) {
                if (map[c[j]] == NO_VERTEX) {
                    map[c[j]] = made;
                    what[made++] = c[j];
                }
                sidx[i * 3 + j] = map[c[j]];
            }
            uint32_t v = map[c[2]];
            if (v == NO_VERTEX)
                v = map[c[2]] = made++;
            else if (what[v] & TAKEN)
                v = made++;     /* taken: a copy (the corners of others may share either) */
            what[v] = TAKEN | (uint32_t)(t0 + i);
            sidx[i * 3 + 2] = v;
        }
        GL(BufferSubData)(GL_ELEMENT_ARRAY_BUFFER, (GLintptr)(sizeof(uint32_t) * 3 * t0),
                          (GLsizeiptr)(sizeof(uint32_t) * 3 * n), sidx);
    }
    free(map);
    free(sidx);
    GL(GenBuffers)(1, &a->vbo[k]);
    GL(BindBuffer)(GL_ARRAY_BUFFER, a->vbo[k]);
    GL(BufferData)(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * (size_t)vf * made), NULL,
                   GL_STATIC_DRAW);
    for (size_t v0 = 0; v0 < made; v0 += STAGE) {
        size_t n = made - v0 < STAGE ? made - v0 : STAGE;
        float *o = svtx;
        for (size_t i = 0; i < n; i++) {
            uint32_t w = what[v0 + i], src;
            float nrm[3] = { 0, 0, 0 };
            if (w & TAKEN) {
                const uint32_t *c = &ix[(size_t)(w & ~TAKEN) * 3];
                src = c[2];
                face_normal(m, c, nrm);
            } else {
                src = w;
                if (m->normals)
                    memcpy(nrm, &m->normals[(size_t)src * 3], sizeof nrm);
            }
            memcpy(o, &m->positions[(size_t)src * 3], sizeof(float) * 3);
            memcpy(o + 3, nrm, sizeof nrm);
            o += FLAT_FLOATS;
            if (m->uvs) {
                memcpy(o, &m->uvs[(size_t)src * 2], sizeof(float) * UV_FLOATS);
                o += UV_FLOATS;
            }
            if (m->colors) {
                memcpy(o, &m->colors[(size_t)src * 4], sizeof(float) * COL_FLOATS);
                o += COL_FLOATS;
            }
        }
        GL(BufferSubData)(GL_ARRAY_BUFFER, (GLintptr)(sizeof(float) * (size_t)vf * v0),
                          (GLsizeiptr)(sizeof(float) * (size_t)vf * n), svtx);
    }
    free(what);
    free(svtx);
    vertex_attributes(r, m, a, vf);
    return true;
}

enum { VERTEX_FLOATS = 12 };    /* smooth: position, vertex normal, texture coordinates,
                                 * colour */

/* The smooth buffer: the mesh's vertices, and every kept level's indices one after
 * another; the vertices go up a slice at a time, the indices straight from the levels. */
static bool upload_smooth(limen_renderer *r, const limen_mesh_geometry *m,
                          struct limen__gpu_asset *a)
{
    size_t nv = (size_t)m->vertex_count, nidx = level_corners(m);
    float *buf = upload_alloc(r, sizeof(float) * VERTEX_FLOATS * STAGE);
    if (!buf)
        return false;
    vertex_arrays(r, &a->svao, &a->svbo, sizeof(float) * VERTEX_FLOATS * nv, NULL);
    for (size_t v0 = 0; v0 < nv; v0 += STAGE) {
        size_t n = nv - v0 < STAGE ? nv - v0 : STAGE;
        for (size_t i = 0; i < n; i++) {
            size_t v = v0 + i;
            float *c = buf + i * VERTEX_FLOATS;
            memcpy(c, &m->positions[v * 3], sizeof(float) * 3);
            memcpy(c + 3, &m->normals[v * 3], sizeof(float) * 3);
            c[6] = m->uvs ? m->uvs[v * 2] : 0.0f;
            c[7] = m->uvs ? m->uvs[v * 2 + 1] : 0.0f;
            for (int k = 0; k < 4; k++)
                c[8 + k] = m->colors ? m->colors[v * 4 + k] : 1.0f;
        }
        GL(BufferSubData)(GL_ARRAY_BUFFER, (GLintptr)(sizeof(float) * VERTEX_FLOATS * v0),
                          (GLsizeiptr)(sizeof(float) * VERTEX_FLOATS * n), buf);
    }
    free(buf);
    GL(GenBuffers)(1, &a->sibo);
    GL(BindBuffer)(GL_ELEMENT_ARRAY_BUFFER, a->sibo);
    GL(BufferData)(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * nidx), NULL,
                   GL_STATIC_DRAW);
    size_t at = 0;
    for (int k = 0; k < levels(m); k++) {
        const uint32_t *ix;
        size_t n = (size_t)level(m, k, &ix) * 3;
        a->sfirst[k] = (GLint)at;
        a->scount[k] = (GLsizei)n;
        GL(BufferSubData)(GL_ELEMENT_ARRAY_BUFFER, (GLintptr)(sizeof(uint32_t) * at),
                          (GLsizeiptr)(sizeof(uint32_t) * n), ix);
        at += n;
    }
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
     * flat one, and the reverse */
    *indexed = true;
    if (smooth) {
        if (!a->svao && !upload_smooth(r, m, a)) {
            limen__draw_fail(r, LIMEN_ERR_NOMEM, "out of memory uploading a mesh of %d "
                             "triangles (it is not drawn)", m->triangle_count);
            return false;
        }
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
        if (a->ibo[k])
            GL(DeleteBuffers)(1, &a->ibo[k]);
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
