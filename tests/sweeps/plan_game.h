/* plan_game.h - a renderer of limen's view tree with OpenGL of its own, walking the plan
 * (limen_plan_view, limen_plan_view_surfaces, limen_plan_things, limen_plan_clones)
 * rather than the draw list: the stencil method written out as a game would have written it
 * before limen had a draw list (examples/own_renderer.c was this file until then).
 *
 * The sweeps keep it because they need what no draw list offers: any view's projection or
 * clip method replaced (the oblique projection forced where the planner falls back to the
 * user clip plane) and the surfaces' flat passes drawn their own way (plan_gl.h's hooks:
 * game.proj, game.clip, game.flat_surface). test_sweep_approach measures those against the
 * ray tracer; nothing else includes it. OpenGL 3.3 core through OSMesa, a depth24/stencil8
 * framebuffer object of its own, LIMEN_DEPTH_NO or (GL 4.5) LIMEN_DEPTH_ZO.
 *
 * Drawing one view v (v's pixels hold stencil == v->stencil): scissor to v->scissor; a
 * nested view resets depth to the far plane inside its pixels; v's things (each passing
 * through a portal drawn twice: cut at the portal, and its copy cut at the partner); in a
 * nested view the background where depth is still far; then each surface: RECURSE marks its
 * visible pixels with stencil + 1, draws the child view there and seals (the surface's depth
 * over the child's pixels, stencil back); FILL draws the fill colour; BACK a lit matte quad.
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE         /* M_PI */
#endif
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GL/osmesa.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "limen.h"

#define SEGMENTS 96             /* fixed tessellation of spheres and cylinders */

/* ============================================================ 0. small maths */

/* c = a * b, column-major 4x4 (c may not alias a or b). */
static void mat4_mul(const float a[16], const float b[16], float c[16])
{
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            c[j * 4 + i] = a[i] * b[j * 4] + a[4 + i] * b[j * 4 + 1] +
                           a[8 + i] * b[j * 4 + 2] + a[12 + i] * b[j * 4 + 3];
}

/* ============================================================ 1. context */

typedef struct mesh { GLsizei first, count; } mesh;
enum { MESH_QUAD, MESH_BOX, MESH_SPHERE, MESH_CYLINDER, MESH_COUNT };
enum { MESH_FILE = -1 };                /* a triangle mesh of the scene's (item.geo) */
/* where the normal comes from: the vertices', the true sphere's or cylinder's, or the
 * triangle's plane (a mesh without smooth normals) */
enum { SHAPE_FLAT = 0, SHAPE_SPHERE = 1, SHAPE_CYLINDER = 2, SHAPE_FACETS = 3 };
/* where texture coordinates come from: none, a plane's, a box face's, a mesh's own */
enum { UV_NONE, UV_PLANE, UV_BOX, UV_MESH };

/* A scene mesh on the GPU: its vertices, and all its levels of detail in one index buffer. */
typedef struct gpu_mesh {
    uint64_t id;                        /* limen_mesh_geometry.id */
    GLuint vao, vbo, ibo;
    int levels;
    GLsizei first[16], count[16];       /* level k: indices [first, first + count) */
} gpu_mesh;

/* An image on the GPU. */
typedef struct gpu_image { uint64_t id; GLuint tex; } gpu_image;

/* What the game draws for one node this frame. */
typedef struct item {
    limen_node node;
    limen_node_kind kind;
    int mesh, shape, uv;
    const gpu_mesh *geo;                /* MESH_FILE: its triangles */
    const limen_drawable *src;          /* what limen says of it (for the level of detail) */
    GLuint tex;                         /* albedo texture, or 0 */
    float repeat[2];                    /* its coordinates scaled by these (tiling) */
    limen_texture_filter filter;        /* how it is sampled */
    float model[16];                    /* world matrix times the mesh's scale */
    float scale[3];                     /* unit mesh -> node-local units (for the checker) */
    float color[3], color_b[3], cell;   /* albedo, or checker colours a and b */
    float back[3], fill[3];             /* mirrors and portals */
    int drawn;                          /* 0: hidden, or nothing to draw (a light) */
} item;

typedef struct game {
    int w, h;                           /* the frame's size in pixels */
    OSMesaContext ctx;
    unsigned char token[4 * 4 * 4];     /* OSMesa needs a buffer; we draw into our FBO */
    PFNGLCLIPCONTROLPROC clip_control;  /* GL 4.5 (NULL on a 3.3 context) */
    GLuint fbo, color_rb, depth_rb, prog, vao, vbo, ibo;
    struct {
        GLint model, view_proj, clip_plane, cut, scale, eye, albedo, albedo_b, cell, tint,
            ambient, shape, flat, uv, textured, tex, repeat, nlights, light_pos, light_col,
            base, emissive, cutoff,
            light_inv_r2;
    } u;
    gpu_mesh *meshes_gpu;               /* the scene meshes and images uploaded so far */
    int nmeshes_gpu;
    gpu_image *images;
    int nimages;
    limen_scene *scene;                 /* the scene being drawn */
    mesh meshes[MESH_COUNT];
    limen_plan *plan;                   /* the game's plan, rebuilt every frame ... */
    limen_drawables *draw;              /* ... and its list of what to draw */
    const limen_plan *drawing;          /* the plan being drawn */
    item *items;                        /* this frame's drawables, as the game draws them */
    int nitems, items_cap;
    float background[3];
    /* Hooks for tests/sweeps/plan_gl.h, which draws through this game with some views'
     * projections or clip methods replaced and the surfaces' flat passes drawn its own way.
     * A game leaves them NULL. */
    const float (*proj)[16];
    const limen_clip_method *clip;
    void (*flat_surface)(struct game *g, const limen_view *v, const item *it, const float rgb[3]);
    void *hook_data;
    const float *cut;                   /* world plane that cuts surfaces (see use_view) */
    const limen_view *view;             /* the view being drawn (levels of detail) */
} game;

static int make_current(game *g)
{
    return OSMesaMakeCurrent(g->ctx, g->token, GL_UNSIGNED_BYTE, 4, 4) ? 0 : -1;
}

static GLuint renderbuffer(GLenum format, int w, int h)
{
    GLuint rb;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
    return rb;
}

static int context_create(game *g)
{
    static const int versions[][2] = { { 4, 5 }, { 3, 3 } };
    for (int i = 0; i < 2 && !g->ctx; i++) {
        const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                                OSMESA_STENCIL_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                OSMESA_CONTEXT_MAJOR_VERSION, versions[i][0],
                                OSMESA_CONTEXT_MINOR_VERSION, versions[i][1], 0 };
        g->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    }
    if (!g->ctx || make_current(g))
        return -1;
    /* glClipControl (GL 4.5) is not exported by libOSMesa: fetch it as a loader would */
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor >= 45)
        g->clip_control = (PFNGLCLIPCONTROLPROC)OSMesaGetProcAddress("glClipControl");
    g->color_rb = renderbuffer(GL_RGBA8, g->w, g->h);
    g->depth_rb = renderbuffer(GL_DEPTH24_STENCIL8, g->w, g->h);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              g->depth_rb);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE ? 0 : -1;
}

/* ============================================================ 2. shader */

static const char *vs_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_nrm;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in vec4 a_col;\n"      /* a mesh's vertex colours (else white) */
    "uniform mat4 u_model, u_view_proj;\n"
    "uniform vec3 u_scale;\n"
    "uniform vec4 u_clip_plane, u_cut;\n"
    "uniform int u_shape, u_uv;\n"
    "out vec3 v_world, v_local, v_normal;\n"
    "out vec2 v_uv;\n"
    "out vec4 v_col;\n"
    "void main() {\n"
    "    vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "    v_col = a_col;\n"
    "    v_world = w.xyz; v_local = a_pos * u_scale;\n"
    "    vec3 n = a_nrm;\n"                                /* boxes, quads, cylinder caps */
    "    if (u_shape == 1) n = a_pos;\n"                   /* the true sphere's normal */
    "    else if (u_shape == 2 && abs(a_nrm.y) < 0.5) n = vec3(a_pos.x, 0.0, a_pos.z);\n"
    /* linear in n, so interpolating it gives the true normal at every pixel */
    "    v_normal = transpose(inverse(mat3(u_model))) * n;\n"
    /* texture coordinates: a plane's over its extent, a box face's two other axes */
    "    vec3 q = a_pos + 0.5;\n"
    "    v_uv = u_uv == 3 ? a_uv : u_uv == 1 ? q.xy\n"
    "         : abs(a_nrm.x) > 0.5 ? q.yz : abs(a_nrm.y) > 0.5 ? q.zx : q.xy;\n"
    "    gl_ClipDistance[0] = dot(u_clip_plane, w);\n"
    "    gl_ClipDistance[1] = dot(u_cut, w);\n"   /* a shape cut at a portal it passes */
    "    gl_Position = u_view_proj * w;\n"
    "}\n";

static const char *fs_src =
    "#version 330 core\n"
    "in vec3 v_world, v_local, v_normal;\n"
    "in vec2 v_uv;\n"
    "in vec4 v_col;\n"
    "uniform vec3 u_eye, u_albedo, u_albedo_b, u_tint;\n"
    "uniform vec4 u_base;\n"                     /* a mesh part's material (else white): */
    "uniform vec3 u_emissive;\n"                 /* base colour, emission, and the mask's */
    "uniform float u_cutoff;\n"                  /* cutoff (-1: none) */
    "uniform float u_cell, u_ambient;\n"
    "uniform int u_flat, u_nlights, u_shape, u_textured;\n"
    "uniform sampler2D u_tex;\n"
    "uniform vec2 u_repeat;\n"
    "uniform vec3 u_light_pos[8], u_light_col[8];\n"
    "uniform float u_light_inv_r2[8];\n"          /* 1 / range^2; 0: no range */
    "out vec4 o_color;\n"
    "void main() {\n"
    "    if (u_flat != 0) { o_color = vec4(u_albedo * u_tint, 1.0); return; }\n"
    "    vec3 n = normalize(u_shape == 3 ? cross(dFdx(v_world), dFdy(v_world)) : v_normal);\n"
    "    if (dot(n, u_eye - v_world) < 0.0) n = -n;\n"  /* two-sided: face the eye */
    "    vec3 albedo = u_albedo;\n"
    "    if (u_cell > 0.0) {\n"                     /* a quad's local z is 0: xy only */
    "        vec3 c = floor(v_local / u_cell);\n"
    "        float k = c.x + c.y + c.z;\n"
    "        if (k - 2.0 * floor(k * 0.5) > 0.5) albedo = u_albedo_b;\n"
    "    }\n"
    /* tiled (limen_node_set_texture_repeat); rows were uploaded top first: v = 0 is the
     * image's bottom */
    "    float alpha = u_base.a * v_col.a;\n"
    "    albedo *= u_base.rgb * v_col.rgb;\n"
    "    if (u_textured != 0) {\n"
    "        vec4 t = texture(u_tex, vec2(0.0, 1.0) + vec2(1.0, -1.0) * v_uv * u_repeat);\n"
    "        albedo *= t.rgb;\n"
    "        alpha *= t.a;\n"
    "    }\n"
    "    if (alpha < u_cutoff) discard;\n"
    "    vec3 light = vec3(0.0);\n"
    "    for (int i = 0; i < u_nlights; i++) {\n"
    "        vec3 d = u_light_pos[i] - v_world;\n"
    "        float q = dot(d, d) * u_light_inv_r2[i];\n"    /* (distance / range)^2 */
    "        float w = clamp(1.0 - q * q, 0.0, 1.0);\n"
    "        light += u_light_col[i] * w * w * max(0.0, dot(n, normalize(d)));\n"
    "    }\n"
    "    vec3 c = clamp(albedo * (u_ambient + (1.0 - u_ambient) * light), 0.0, 1.0);\n"
    "    c = clamp(c + u_emissive, 0.0, 1.0);\n"     /* emission, after shading */
    "    o_color = vec4(c * u_tint, alpha);\n"
    "}\n";

static int program_create(game *g)
{
    const char *src[2] = { vs_src, fs_src };
    const GLenum type[2] = { GL_VERTEX_SHADER, GL_FRAGMENT_SHADER };
    char log[512] = "";
    GLint ok = 0;
    g->prog = glCreateProgram();
    for (int i = 0; i < 2; i++) {
        GLuint sh = glCreateShader(type[i]);
        glShaderSource(sh, 1, &src[i], NULL);
        glCompileShader(sh);
        glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            glGetShaderInfoLog(sh, sizeof log, NULL, log);
            fprintf(stderr, "shader: %s\n", log);
        }
        glAttachShader(g->prog, sh);
        glDeleteShader(sh);                     /* goes with the program */
    }
    glLinkProgram(g->prog);
    glGetProgramiv(g->prog, GL_LINK_STATUS, &ok);
#define U(field, name) g->u.field = glGetUniformLocation(g->prog, name)
    U(model, "u_model"); U(view_proj, "u_view_proj");
    U(clip_plane, "u_clip_plane"); U(cut, "u_cut"); U(scale, "u_scale"); U(eye, "u_eye");
    U(albedo, "u_albedo"); U(albedo_b, "u_albedo_b"); U(cell, "u_cell"); U(tint, "u_tint");
    U(ambient, "u_ambient"); U(shape, "u_shape"); U(flat, "u_flat"); U(uv, "u_uv");
    U(textured, "u_textured"); U(tex, "u_tex"); U(repeat, "u_repeat");
    U(nlights, "u_nlights"); U(light_pos, "u_light_pos"); U(light_col, "u_light_col");
    U(light_inv_r2, "u_light_inv_r2");
    U(base, "u_base"); U(emissive, "u_emissive"); U(cutoff, "u_cutoff");
#undef U
    glUseProgram(g->prog);
    glUniform1i(g->u.tex, 0);                   /* texture unit 0 */
    /* what a part's material leaves as it is: white, no emission, no mask */
    glUniform4f(g->u.base, 1, 1, 1, 1);
    glUniform3f(g->u.emissive, 0, 0, 0);
    glUniform1f(g->u.cutoff, -1);
    glVertexAttrib4f(3, 1, 1, 1, 1);            /* the colour of vertices without one */
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUniform4f(g->u.cut, 0, 0, 0, 1);
    return ok ? 0 : -1;
}

/* ============================================================ 3. meshes */

/* Unit meshes in one vertex buffer (position, normal), counter-clockwise seen from
 * outside: quad 1x1 on z = 0 facing +Z; box 1x1x1 centred; sphere of radius 1; cylinder of
 * radius 1 from y = 0 to y = 1, capped. */
#define MAX_VERTS (28 + (SEGMENTS + 1) * (SEGMENTS / 2 + 7))
#define MAX_INDEX (42 + 6 * SEGMENTS * (SEGMENTS / 2 + 3))
typedef struct builder { float v[6 * MAX_VERTS]; GLuint idx[MAX_INDEX]; GLuint nv, ni; } builder;

static GLuint vtx(builder *b, float x, float y, float z, float nx, float ny, float nz)
{
    float *p = b->v + 6 * b->nv;
    p[0] = x, p[1] = y, p[2] = z, p[3] = nx, p[4] = ny, p[5] = nz;
    return b->nv++;
}

static void tri(builder *b, GLuint i0, GLuint i1, GLuint i2)
{
    b->idx[b->ni++] = i0, b->idx[b->ni++] = i1, b->idx[b->ni++] = i2;
}

/* The square face of the unit box facing (sgn) `axis`, at distance `dist` from the origin. */
static void face(builder *b, int axis, int sgn, float dist)
{
    static const float uv[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    int u = (axis + 1) % 3, v = (axis + 2) % 3;     /* u x v = +axis */
    GLuint id[4];
    for (int k = 0; k < 4; k++) {
        float p[3], n[3] = { 0, 0, 0 };
        n[axis] = (float)sgn;
        p[axis] = dist, p[u] = 0.5f * uv[k][0], p[v] = 0.5f * uv[k][1] * (float)sgn;
        id[k] = vtx(b, p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    tri(b, id[0], id[1], id[2]);
    tri(b, id[0], id[2], id[3]);
}

/* A surface of revolution about +Y: rings of (radius, height, normal radial, normal y),
 * listed from the top down, each of SEGMENTS + 1 vertices (the seam is doubled). */
static void lathe(builder *b, int rings, const float (*ring)[4])
{
    GLuint base = b->nv;
    for (int i = 0; i < rings; i++)
        for (int j = 0; j <= SEGMENTS; j++) {
            double th = 2.0 * M_PI * j / SEGMENTS;
            float c = (float)cos(th), s = (float)-sin(th);
            const float *r = ring[i];
            vtx(b, r[0] * c, r[1], r[0] * s, r[2] * c, r[3], r[2] * s);
        }
    for (int i = 0; i + 1 < rings; i++)
        for (int j = 0; j < SEGMENTS; j++) {
            GLuint a = base + (GLuint)(i * (SEGMENTS + 1) + j), c = a + SEGMENTS + 1;
            tri(b, a, c, c + 1);
            tri(b, a, c + 1, a + 1);
        }
}

static void build_meshes(game *g, builder *b)
{
    g->meshes[MESH_QUAD].first = (GLsizei)b->ni;
    face(b, 2, 1, 0.0f);
    g->meshes[MESH_BOX].first = (GLsizei)b->ni;
    for (int axis = 0; axis < 3; axis++)
        for (int sgn = -1; sgn <= 1; sgn += 2)
            face(b, axis, sgn, 0.5f * (float)sgn);
    g->meshes[MESH_SPHERE].first = (GLsizei)b->ni;
    float sphere[SEGMENTS / 2 + 1][4];
    for (int i = 0; i <= SEGMENTS / 2; i++) {
        double phi = M_PI * i / (SEGMENTS / 2);     /* from the north pole down */
        float r = (float)sin(phi), y = (float)cos(phi);
        sphere[i][0] = sphere[i][2] = r, sphere[i][1] = sphere[i][3] = y;
    }
    lathe(b, SEGMENTS / 2 + 1, sphere);
    g->meshes[MESH_CYLINDER].first = (GLsizei)b->ni;
    static const float top[2][4] = { { 0, 1, 0, 1 }, { 1, 1, 0, 1 } };
    static const float side[2][4] = { { 1, 1, 1, 0 }, { 1, 0, 1, 0 } };
    static const float bottom[2][4] = { { 1, 0, 0, -1 }, { 0, 0, 0, -1 } };
    lathe(b, 2, top);
    lathe(b, 2, side);
    lathe(b, 2, bottom);
    for (int m = 0; m < MESH_COUNT; m++)
        g->meshes[m].count = (m + 1 < MESH_COUNT ? g->meshes[m + 1].first : (GLsizei)b->ni) -
                             g->meshes[m].first;
}

static int meshes_create(game *g)
{
    builder *b = calloc(1, sizeof *b);
    if (!b)
        return -1;
    build_meshes(g, b);
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 6 * b->nv), b->v, GL_STATIC_DRAW);
    glGenBuffers(1, &g->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(GLuint) * b->ni), b->idx,
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          (void *)(3 * sizeof(float)));
    free(b);
    return 0;
}

/* The GPU copy of a scene mesh: vertices (position, normal, texture coordinates) and every
 * level's indices (limen_mesh_geometry.lods; level 0 is the full mesh). NULL if out of
 * memory. */
static const gpu_mesh *mesh_upload(game *g, const limen_mesh_geometry *m)
{
    for (int i = 0; i < g->nmeshes_gpu; i++)
        if (g->meshes_gpu[i].id == m->id)
            return &g->meshes_gpu[i];
    gpu_mesh *grown = realloc(g->meshes_gpu, sizeof *grown * (size_t)(g->nmeshes_gpu + 1));
    if (!grown)
        return NULL;
    g->meshes_gpu = grown;
    size_t nv = (size_t)m->vertex_count, ni = 0;
    int levels = m->lod_count < 16 ? m->lod_count : 16;
    for (int k = 0; k < levels; k++)
        ni += 3 * (size_t)m->lods[k].triangle_count;
    float *v = malloc(sizeof(float) * 12 * nv);
    GLuint *idx = malloc(sizeof(GLuint) * ni);
    if (!v || !idx) {
        free(v);
        free(idx);
        return NULL;
    }
    for (size_t i = 0; i < nv; i++) {
        memcpy(v + 12 * i, m->positions + 3 * i, sizeof(float) * 3);
        memcpy(v + 12 * i + 3, m->normals + 3 * i, sizeof(float) * 3);
        v[12 * i + 6] = m->uvs ? m->uvs[2 * i] : 0.0f;
        v[12 * i + 7] = m->uvs ? m->uvs[2 * i + 1] : 0.0f;
        for (int c = 0; c < 4; c++)             /* vertex colours, white where none */
            v[12 * i + 8 + c] = m->colors ? m->colors[4 * i + c] : 1.0f;
    }
    gpu_mesh *gm = &g->meshes_gpu[g->nmeshes_gpu++];
    memset(gm, 0, sizeof *gm);
    gm->id = m->id;
    gm->levels = levels;
    for (int k = 0, at = 0; k < levels; k++) {
        gm->first[k] = at;
        gm->count[k] = 3 * m->lods[k].triangle_count;
        memcpy(idx + at, m->lods[k].indices, sizeof(GLuint) * (size_t)gm->count[k]);
        at += gm->count[k];
    }
    glGenVertexArrays(1, &gm->vao);
    glBindVertexArray(gm->vao);
    glGenBuffers(1, &gm->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, gm->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 12 * nv), v, GL_STATIC_DRAW);
    glGenBuffers(1, &gm->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gm->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(GLuint) * ni), idx, GL_STATIC_DRAW);
    for (GLuint a = 0; a < 4; a++) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, a == 2 ? 2 : a == 3 ? 4 : 3, GL_FLOAT, GL_FALSE,
                              12 * sizeof(float), (void *)(sizeof(float) * (a == 3 ? 8 : 3 * a)));
    }
    glBindVertexArray(g->vao);
    free(v);
    free(idx);
    return gm;
}

/* The GPU copy of an image with its mipmap levels, repeating (limen_node_set_texture); the
 * filter is set where it is drawn. 0 if out of memory. */
static GLuint image_upload(game *g, const limen_image *im)
{
    for (int i = 0; i < g->nimages; i++)
        if (g->images[i].id == im->id)
            return g->images[i].tex;
    gpu_image *grown = realloc(g->images, sizeof *grown * (size_t)(g->nimages + 1));
    if (!grown)
        return 0;
    g->images = grown;
    gpu_image *gi = &g->images[g->nimages++];
    gi->id = im->id;
    glGenTextures(1, &gi->tex);
    glBindTexture(GL_TEXTURE_2D, gi->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* limen's own levels, so that the texels are the ones its ray tracer reads; an image
     * with alpha (a mesh material's) has only its own level, and goes up RGBA */
    int levels = im->alpha ? 1 : im->level_count;
    unsigned char *rgba = im->alpha ? malloc((size_t)im->width * (size_t)im->height * 4) : NULL;
    for (size_t i = 0; rgba && i < (size_t)im->width * (size_t)im->height; i++) {
        memcpy(rgba + 4 * i, im->rgb + 3 * i, 3);
        rgba[4 * i + 3] = im->alpha[i];
    }
    if (rgba)
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, im->width, im->height, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, rgba);
    for (int k = 0; !im->alpha && k < levels; k++)
        glTexImage2D(GL_TEXTURE_2D, k, GL_RGB8, im->levels[k].width, im->levels[k].height, 0,
                     GL_RGB, GL_UNSIGNED_BYTE, im->levels[k].rgb);
    free(rgba);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return gi->tex;
}

static void game_destroy(game *g)
{
    if (g->ctx && !make_current(g)) {
        for (int i = 0; i < g->nmeshes_gpu; i++) {
            glDeleteBuffers(1, &g->meshes_gpu[i].vbo);
            glDeleteBuffers(1, &g->meshes_gpu[i].ibo);
            glDeleteVertexArrays(1, &g->meshes_gpu[i].vao);
        }
        for (int i = 0; i < g->nimages; i++)
            glDeleteTextures(1, &g->images[i].tex);
        glDeleteProgram(g->prog);
        glDeleteBuffers(1, &g->vbo);
        glDeleteBuffers(1, &g->ibo);
        glDeleteVertexArrays(1, &g->vao);
        glDeleteFramebuffers(1, &g->fbo);
        glDeleteRenderbuffers(1, &g->color_rb);
        glDeleteRenderbuffers(1, &g->depth_rb);
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    }
    if (g->ctx)
        OSMesaDestroyContext(g->ctx);
    limen_plan_destroy(g->plan);
    limen_drawables_destroy(g->draw);
    free(g->meshes_gpu);
    free(g->images);
    free(g->items);
    free(g);
}

static game *game_create(int w, int h)
{
    game *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    g->w = w, g->h = h;
    if (context_create(g) || program_create(g) || meshes_create(g) || limen_plan_create(&g->plan) ||
        limen_drawables_create(&g->draw)) {
        game_destroy(g);
        return NULL;
    }
    return g;
}

/* ============================================================ 4. reading the scene */

/* The game's picture of one drawable; 0 if it draws nothing (a light, a mesh without
 * triangles, or what cannot be uploaded). */
static int read_item(game *g, const limen_drawable *d, item *it)
{
    memset(it, 0, sizeof *it);
    it->node = d->node;
    it->kind = d->kind;
    it->src = d;
    const float *dims = d->dims;
    switch (it->kind) {
    case LIMEN_NODE_BOX:      it->mesh = MESH_BOX;      memcpy(it->scale, dims, 3 * sizeof *dims);
                              break;
    case LIMEN_NODE_SPHERE:   it->mesh = MESH_SPHERE;   it->shape = SHAPE_SPHERE;
                              it->scale[0] = it->scale[1] = it->scale[2] = dims[0]; break;
    case LIMEN_NODE_CYLINDER: it->mesh = MESH_CYLINDER; it->shape = SHAPE_CYLINDER;
                              it->scale[0] = it->scale[2] = dims[0], it->scale[1] = dims[1]; break;
    case LIMEN_NODE_QUAD: case LIMEN_NODE_MIRROR: case LIMEN_NODE_PORTAL:
        it->mesh = MESH_QUAD, it->scale[0] = dims[0], it->scale[1] = dims[1], it->scale[2] = 1;
        break;
    case LIMEN_NODE_MESH:
        if (!d->mesh || !(it->geo = mesh_upload(g, d->mesh)))
            return 0;
        it->mesh = MESH_FILE, it->shape = d->smooth ? SHAPE_FLAT : SHAPE_FACETS;
        it->scale[0] = it->scale[1] = it->scale[2] = 1;     /* in the node's own units */
        break;
    default:
        return 0;                               /* lights */
    }
    memcpy(it->model, d->world, sizeof it->model);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            it->model[c * 4 + r] *= it->scale[c];
    memcpy(it->color, d->color, sizeof it->color);
    memcpy(it->color_b, d->checker, sizeof it->color_b);
    it->cell = d->cell;
    /* (the planner folds mirror tints into limen_view.tint) */
    memcpy(it->back, d->back, sizeof it->back);
    memcpy(it->fill, d->fill, sizeof it->fill);
    memcpy(it->repeat, d->texture_repeat, sizeof it->repeat);
    it->filter = d->texture_filter;
    if (d->texture && (it->tex = image_upload(g, d->texture)))
        it->uv = it->kind == LIMEN_NODE_MESH ? UV_MESH : it->kind == LIMEN_NODE_BOX ? UV_BOX : UV_PLANE;
    return 1;
}

/* Reads what this frame draws, in one call: shapes and surfaces, lights, ambient and
 * background. items[i] is the drawable i's picture (or not drawn). */
static void read_scene(game *g, limen_scene *s)
{
    float light_pos[LIMEN_MAX_LIGHTS][3], light_col[LIMEN_MAX_LIGHTS][3], ambient;
    float inv_r2[LIMEN_MAX_LIGHTS];
    int nlights = 0;
    const limen_drawable *d;
    if (limen_drawables_build(g->draw, s))
        fprintf(stderr, "  drawables: %s\n", limen_scene_error(s));
    int n = limen_drawables_items(g->draw, &d);
    if (n > g->items_cap) {
        item *grown = realloc(g->items, sizeof *grown * (size_t)n);
        if (grown)
            g->items = grown, g->items_cap = n;
    }
    g->nitems = n < g->items_cap ? n : g->items_cap;
    for (int i = 0; i < g->nitems; i++) {
        item *it = &g->items[i];
        it->drawn = d[i].visible && read_item(g, &d[i], it);
        if (d[i].visible && d[i].kind == LIMEN_NODE_LIGHT && nlights < LIMEN_MAX_LIGHTS) {
            memcpy(light_pos[nlights], d[i].world + 12, sizeof light_pos[0]);
            memcpy(light_col[nlights], d[i].color, sizeof light_col[0]);
            inv_r2[nlights++] = d[i].range > 0 ? 1.0f / (d[i].range * d[i].range) : 0.0f;
        }
    }
    limen_drawables_environment(g->draw, g->background, &ambient);
    glUniform1f(g->u.ambient, ambient);
    glUniform1i(g->u.nlights, nlights);
    if (nlights) {
        glUniform3fv(g->u.light_pos, nlights, &light_pos[0][0]);
        glUniform3fv(g->u.light_col, nlights, &light_col[0][0]);
        glUniform1fv(g->u.light_inv_r2, nlights, inv_r2);
    }
}

/* The picture of a node the plan names, or NULL. */
static const item *find_item(const game *g, limen_node n)
{
    int i = limen_drawables_find(g->draw, n);
    return i >= 0 && i < g->nitems && g->items[i].drawn ? &g->items[i] : NULL;
}

static int is_surface(const item *it)
{
    return it->kind == LIMEN_NODE_MIRROR || it->kind == LIMEN_NODE_PORTAL;
}

/* ============================================================ 5. drawing the view tree */

static void gl_set(GLenum cap, int on)
{
    if (on)
        glEnable(cap);
    else
        glDisable(cap);
}

/* The uniforms of one view: matrices, eye, clip plane, winding, tint. */
static void use_view(game *g, const limen_view *v)
{
    float vp[16];
    mat4_mul(g->proj ? g->proj[v->id] : v->proj, v->view, vp);
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, vp);
    glUniform3fv(g->u.eye, 1, v->eye);
    static const float no_clip[4] = { 0, 0, 0, 1 };
    limen_clip_method clip = g->clip ? g->clip[v->id] : v->clip;
    int plane = clip == LIMEN_CLIP_PLANE;       /* else the projection does the cutting */
    gl_set(GL_CLIP_DISTANCE0, plane);
    glUniform4fv(g->u.clip_plane, 1, plane ? v->clip_plane : no_clip);
    glFrontFace(v->front_face_cw ? GL_CW : GL_CCW);
    glUniform3fv(g->u.tint, 1, v->tint);
    g->view = v;
    /* depth clamping keeps surfaces from the near plane, the exit plane of an oblique view */
    g->cut = v->depth > 0 && clip == LIMEN_CLIP_OBLIQUE ? v->clip_plane : NULL;
}

/* Sets texture tex (0: none) for the next draw, sampled as the item says. */
static void use_texture(game *g, const item *it, GLuint tex)
{
    glUniform1i(g->u.textured, tex != 0);
    if (!tex)
        return;
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                    it->filter == LIMEN_FILTER_NEAREST ? GL_NEAREST
                    : it->filter == LIMEN_FILTER_LINEAR ? GL_LINEAR
                                                        : GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER,
                    it->filter == LIMEN_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR);
    glUniform2fv(g->u.repeat, 1, it->repeat);
}

/* A scene mesh at level k, part by part, each in its material (limen_material): base colour,
 * base texture (the node's own replaces it), alpha mask, emission; the blended parts last,
 * over the rest (a game would sort them with the other transparent things of the view). */
static void draw_parts(game *g, const item *it, int flat, int k)
{
    const limen_mesh_geometry *m = it->src->mesh;
    const limen_mesh_part *parts = m->lods[k].parts ? m->lods[k].parts : m->parts;
    for (int pass = 0; pass < 2; pass++) {
        for (int p = 0; p < m->part_count; p++) {
            const limen_material *mt = &m->materials[parts[p].material];
            if ((mt->alpha_mode == LIMEN_ALPHA_BLEND) != pass || parts[p].triangle_count < 1)
                continue;
            if (!flat) {
                const limen_image *im = it->src->texture ? it->src->texture : mt->base_texture;
                use_texture(g, it, im ? image_upload(g, im) : 0);
                glUniform4fv(g->u.base, 1, mt->base_color);
                glUniform3fv(g->u.emissive, 1, mt->emissive);
                glUniform1f(g->u.cutoff, mt->alpha_mode == LIMEN_ALPHA_MASK ? mt->alpha_cutoff
                                                                              : -1.0f);
            }
            if (pass && !flat) {
                glEnable(GL_BLEND);
                glDepthMask(GL_FALSE);
            }
            glDrawElements(GL_TRIANGLES, 3 * parts[p].triangle_count, GL_UNSIGNED_INT,
                           (void *)(sizeof(GLuint) *
                                    (size_t)(it->geo->first[k] + 3 * parts[p].first_triangle)));
            if (pass && !flat) {
                glDisable(GL_BLEND);
                glDepthMask(GL_TRUE);
            }
        }
    }
    glUniform4f(g->u.base, 1, 1, 1, 1);
    glUniform3f(g->u.emissive, 0, 0, 0);
    glUniform1f(g->u.cutoff, -1);
}

/* One node; flat: unlit colour `albedo` (masks, seals, fills). */
static void draw_item(game *g, const item *it, int flat, const float albedo[3])
{
    glUniformMatrix4fv(g->u.model, 1, GL_FALSE, it->model);
    glUniform3fv(g->u.scale, 1, it->scale);
    glUniform3fv(g->u.albedo, 1, albedo);
    glUniform3fv(g->u.albedo_b, 1, it->color_b);
    glUniform1f(g->u.cell, flat || is_surface(it) ? 0.0f : it->cell);
    glUniform1i(g->u.shape, it->shape);
    glUniform1i(g->u.flat, flat);
    glUniform1i(g->u.uv, it->uv);
    use_texture(g, it, flat ? 0 : it->tex);
    /* mirrors and portals are not cut by the near plane; closed shapes cull back faces (a
     * mesh need not be closed: both its sides show) */
    gl_set(GL_DEPTH_CLAMP, is_surface(it));
    gl_set(GL_CULL_FACE, it->mesh != MESH_QUAD && it->mesh != MESH_FILE);
    int cut = is_surface(it) && g->cut;
    if (cut) {
        glUniform4fv(g->u.clip_plane, 1, g->cut);
        glEnable(GL_CLIP_DISTANCE0);
    }
    if (it->mesh == MESH_FILE) {
        /* the coarsest level whose error stays under limen's default bound in this view */
        int k = limen_view_mesh_lod(g->view, g->h, it->src, 0);
        if (k < 0 || k >= it->geo->levels)
            k = 0;
        glBindVertexArray(it->geo->vao);
        draw_parts(g, it, flat, k);
        glBindVertexArray(g->vao);
    } else {
        const mesh *m = &g->meshes[it->mesh];
        glDrawElements(GL_TRIANGLES, m->count, GL_UNSIGNED_INT,
                       (void *)(sizeof(GLuint) * (size_t)m->first));
    }
    if (cut) {
        glUniform4f(g->u.clip_plane, 0, 0, 0, 1);
        glDisable(GL_CLIP_DISTANCE0);
    }
}

/* A screen-filling quad on the far plane (NDC z = +1 in both NO and ZO), colour times the
 * view's tint; stencil, scissor and the depth test decide where it lands. */
static void draw_far_plane(game *g, const limen_view *v, const float rgb[3])
{
    static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    item far = { .mesh = MESH_QUAD, .kind = LIMEN_NODE_MIRROR, .scale = { 1, 1, 1 },
                 .model = { 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 } };
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, identity);
    glUniform3fv(g->u.tint, 1, v->tint);
    /* a plane that keeps everything as well as the disable: llvmpipe (Mesa 22.3) was seen
     * to go on clipping by the last plane after glDisable(GL_CLIP_DISTANCE0) */
    glUniform4f(g->u.clip_plane, 0, 0, 0, 1);
    glDisable(GL_CLIP_DISTANCE0);
    g->cut = NULL;                              /* (use_view sets it again) */
    draw_item(g, &far, 1, rgb);                 /* a "surface": depth clamped at far */
}

/* A surface's unlit pass (mark, seal, fill). */
static void draw_flat_surface(game *g, const limen_view *v, const item *it, const float rgb[3])
{
    if (g->flat_surface)
        g->flat_surface(g, v, it, rgb);
    else
        draw_item(g, it, 1, rgb);
}

/* Shape `it` cut at world plane `keep` (NULL: whole), its world matrix first carried by
 * `carry` (a portal's matrix) where not NULL. */
static void draw_cut(game *g, const item *it, const float *carry, const float *keep)
{
    item copy = *it;
    if (carry)
        mat4_mul(carry, it->model, copy.model);
    if (keep) {
        glUniform4fv(g->u.cut, 1, keep);
        glEnable(GL_CLIP_DISTANCE1);
    }
    draw_item(g, &copy, 0, copy.color);
    if (keep) {
        glUniform4f(g->u.cut, 0, 0, 0, 1);
        glDisable(GL_CLIP_DISTANCE1);
    }
}

/* View `index`'s shapes: those limen_plan_things lists (found through the scene's spatial
 * index when the plan was built; a superset of what shows), each cut at the portal it is
 * passing through, then the copies of those coming out of the portals' partners. */
static void draw_shapes(game *g, int index)
{
    const limen_clone *clones;
    const limen_node *things;
    int nclones = limen_plan_clones(g->drawing, &clones);
    int n = limen_plan_things(g->drawing, index, &things);
    for (int k = 0; k < n; k++) {
        const item *it = find_item(g, things[k]);
        if (!it)
            continue;
        const float *keep = NULL;
        for (int c = 0; c < nclones && !keep; c++)
            if (clones[c].node.id == it->node.id)
                keep = clones[c].keep;
        draw_cut(g, it, NULL, keep);
    }
    for (int c = 0; c < nclones; c++) {
        const item *it = find_item(g, clones[c].node);
        if (it)
            draw_cut(g, it, clones[c].matrix, clones[c].copy_keep);
    }
}

static void draw_view(game *g, int index)
{
    const limen_view *v = limen_plan_view(g->drawing, index);
    const int st = v->stencil;
    glScissor(v->scissor[0], v->scissor[1], v->scissor[2], v->scissor[3]);
    glStencilFunc(GL_EQUAL, st, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    if (v->depth > 0) {
        /* this view's pixels still hold the parent's depth: reset it to the far plane */
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthFunc(GL_ALWAYS);
        draw_far_plane(g, v, g->background);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_LESS);
    }
    use_view(g, v);
    draw_shapes(g, index);
    if (v->depth > 0) {
        /* the background (tinted) where no shape landed: depth is still at the far plane */
        glDepthFunc(GL_EQUAL);
        draw_far_plane(g, v, g->background);
        glDepthFunc(GL_LESS);
        use_view(g, v);
    }

    const limen_view_surface *surf;
    int n = limen_plan_view_surfaces(g->drawing, index, &surf);
    for (int k = 0; k < n; k++) {
        const item *it = find_item(g, surf[k].node);
        if (!it)
            continue;
        if (surf[k].state == LIMEN_SURFACE_BACK) {
            draw_item(g, it, 0, it->back);      /* lit, matte */
            continue;
        }
        if (surf[k].state == LIMEN_SURFACE_FILL) {
            draw_flat_surface(g, v, it, it->fill);
            continue;
        }
        /* RECURSE. Mark: the surface's visible pixels go from st to st + 1. */
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_FALSE);
        glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
        draw_flat_surface(g, v, it, it->fill);
        glDepthMask(GL_TRUE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

        draw_view(g, surf[k].child);            /* draws where stencil == st + 1 */

        /* Seal: back in this view, the surface's own depth over the child's pixels and
         * their stencil back to st. (The child's colours carry its tint already.) */
        glScissor(v->scissor[0], v->scissor[1], v->scissor[2], v->scissor[3]);
        use_view(g, v);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glStencilFunc(GL_EQUAL, st + 1, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_DECR);
        glDepthFunc(GL_ALWAYS);
        draw_flat_surface(g, v, it, it->fill);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_LESS);
        glStencilFunc(GL_EQUAL, st, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    }
}

/* ============================================================ 6. one frame */

/* Draws plan p (planned for this game's size and the convention range) of scene s; rgb
 * (w*h*3, top row first) gets the frame. The context is made current first because these
 * tests also run limen's own renderer, which has a context of its own. */
static int game_draw(game *g, limen_scene *s, const limen_plan *p, limen_depth_range range,
                     unsigned char *rgb)
{
    if (make_current(g) || range == LIMEN_DEPTH_ZO_REVERSED ||
        (range == LIMEN_DEPTH_ZO && !g->clip_control))
        return -1;      /* (reversed depth would need a float depth buffer) */
    if (g->clip_control)
        g->clip_control(GL_LOWER_LEFT,
                        range == LIMEN_DEPTH_ZO ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    g->drawing = p;
    g->scene = s;
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->w, g->h);
    glUseProgram(g->prog);
    glBindVertexArray(g->vao);
    read_scene(g, s);

    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glClearColor(g->background[0], g->background[1], g->background[2], 1.0f);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_STENCIL_TEST);
    glEnable(GL_SCISSOR_TEST);
    glCullFace(GL_BACK);
    draw_view(g, 0);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glFrontFace(GL_CCW);

    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int y = 0; y < g->h; y++)              /* OpenGL's rows run bottom-up */
        glReadPixels(0, g->h - 1 - y, g->w, 1, GL_RGB, GL_UNSIGNED_BYTE,
                     rgb + 3 * (size_t)g->w * y);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        fprintf(stderr, "  OpenGL error 0x%x\n", e);
    return e == GL_NO_ERROR ? 0 : -1;
}

