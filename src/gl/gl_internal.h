/* gl_internal.h - the renderer's state, shared by its files (render.c: set-up and frames;
 * backend.c: executing a frame's draw list; targets.c: the texture method's targets;
 * assets.c: meshes and textures on the GPU; shader.c). */
#ifndef LIMEN_GL_INTERNAL_H
#define LIMEN_GL_INTERNAL_H

#include <limits.h>
#include <stdbool.h>
#include <stdlib.h>

#include <cglm/cglm.h>

#include "limen.h"
#include "gl/glapi.h"

#define LIMEN__MAX_TARGETS 256
#define LIMEN__UNIT_SLOTS 16    /* levels of a unit shape kept (limen_unit_geometry has 11) */

typedef struct limen__vertex { float pos[3], nrm[3]; } limen__vertex;
typedef struct limen__range { uint32_t first, count; } limen__range;   /* in indices */

typedef struct uniforms {
    GLint model, normal_mat, view_proj, eye, clip_plane, clip_plane2, albedo, albedo_b, cell,
        scale, tint, tex, tex_map, ambient, light_pos, light_col, light_inv_r2, uv_repeat;
    GLint base, emissive, cutoff, emissive_on, blend;     /* materials (gl/backend.c) */
} uniforms;

/* Shader variants (shader.c): what a draw shades. */
enum { LIMEN__MODE_LIT = 0, LIMEN__MODE_FLAT = 1, LIMEN__MODE_TEXTURE = 2,
       LIMEN__MODE_SAMPLES = 3 };  /* a multisampled target's sample of the same number */
/* ... the normals of a lit draw: the vertices' (flat per face), the true sphere's or
 * cylinder's, or a mesh's vertex normals interpolated (smooth) ... */
enum { LIMEN__SHAPE_FACE = 0, LIMEN__SHAPE_SPHERE = 1, LIMEN__SHAPE_CYLINDER = 2,
       LIMEN__SHAPE_SMOOTH = 3 };
/* ... and where an albedo texture's coordinates come from (limen.h): none, a plane's unit
 * point, a box face's two other axes, a mesh's own. */
enum { LIMEN__UV_NONE = 0, LIMEN__UV_PLANE = 1, LIMEN__UV_BOX = 2, LIMEN__UV_MESH = 3 };
_Static_assert(LIMEN__UV_PLANE == (int)LIMEN_UV_PLANE && LIMEN__UV_BOX == (int)LIMEN_UV_BOX &&
               LIMEN__UV_MESH == (int)LIMEN_UV_MESH, "a kind's limen_uv_rule is the variant's");
#define LIMEN__MAX_VARIANTS 256

typedef struct limen__variant {
    unsigned key;
    GLuint prog;
    uniforms u;
    unsigned stamp;                         /* the shared values it holds */
} limen__variant;

/* The values every variant reads; a change bumps shared_stamp. */
typedef struct limen__shared {
    float view_proj[16], eye[3], clip_plane[4], cut_plane[4], tint[3], ambient, tex_map[4];
    int nlights;
    float light_pos[LIMEN_MAX_LIGHTS][3], light_col[LIMEN_MAX_LIGHTS][3];
    float light_inv_r2[LIMEN_MAX_LIGHTS];   /* 1 / range^2, 0 for a light without one */
    bool ranged;                /* some light has a range: variants with RANGE */
} limen__shared;

/* An offscreen target for the texture method: one per depth of nesting. */
typedef struct limen__target {
    GLuint fbo, tex, depth_rb;      /* drawn into: tex and depth, or with msaa the
                                     * multisampled color_rb and depth */
    GLuint ms_tex, resolve_fbo;     /* msaa: the samples (a multisample texture), and tex's
                                     * framebuffer they are averaged into where a target
                                     * is sampled at another scale */
    bool dirty;                     /* msaa: drawn since the last resolve */
    int w, h;
} limen__target;

struct limen_renderer {
    const limen__ctx_ops *ops;
    limen__ctx *ctx;
    limen__gl gl;
    int width, height, msaa;
    bool host;                              /* LIMEN_BACKEND_HOST: fbo is the game's */
    int origin[2];                          /* the frame's lower-left corner in fbo */
    limen_depth_range range;
    int depth_bits;                         /* 24: DEPTH24_STENCIL8, 32: DEPTH32F_STENCIL8 */
    bool has_fragment_stats;
    bool ready;                             /* set up completely */
    bool loaded;                            /* gl holds every required entry point */
    char err[512];
    char info[256];

    limen__variant variants[LIMEN__MAX_VARIANTS];
    int nvariants;
    GLuint bound_prog;                      /* the program last bound (0: unknown) */
    limen__shared shared;
    unsigned shared_stamp;
    bool clip0_on, clip1_on;                /* GL_CLIP_DISTANCE0 and 1 as enabled */
    /* The first thing this frame could not draw: a shader variant that did not build, a
     * mesh or texture that could not be uploaded (message in err); LIMEN_OK if none. The
     * frame goes on without it and returns this. */
    limen_status draw_status;
    unsigned faults;                        /* LIMEN__RFAULT_* (tests only) */
    GLuint poly_vao, poly_vbo;              /* surfaces near the eye: CPU-clipped polygons */
    GLuint fill_prog;                       /* flat polygons in NDC */
    GLint u_fill_color;
    uniforms u;                             /* the bound variant's */
    GLuint vao, vbo, ibo;                   /* the unit shapes (limen_unit_geometry) */
    limen__range units[LIMEN_UNIT_COUNT][LIMEN__UNIT_SLOTS];    /* [shape][level] */
    int unit_levels[LIMEN_UNIT_COUNT];

    GLuint fbo, color_rb, depth_rb;         /* the frame (multisampled if msaa); host: the
                                             * game's framebuffer, no renderbuffers */
    GLuint resolve_fbo, resolve_rb;         /* single-sampled copy when msaa */
    GLuint q_fragments;
    GLuint *q_pool;                         /* occlusion queries around shading passes */
    int q_cap, q_used;
    bool q_active;
    bool counting;              /* this frame's stats were asked for: queries count it */
    limen__target targets[LIMEN__MAX_TARGETS];

    GLuint prev_fbo, prev_tex;              /* the previous frame, for LIMEN_FILL_PREVIOUS */
    bool have_prev;

    int draw_calls;                         /* this frame's (limen_frame_stats) */
    uint64_t triangles;
    bool instanced;                         /* variants read the model from instances */
    bool material;                          /* ... and a mesh part's material */
    GLuint inst_vbo;                        /* per-instance values (gl/backend.c) */
    struct limen__instance *inst;
    int inst_cap;
    limen__vertex *poly;                    /* the list's polygons as uploaded */
    int poly_cap;
    limen_draw_state applied;               /* the state set (gl/backend.c) */
    int applied_scissor[4];
    bool applied_valid;

    struct limen__gpu_asset *assets;        /* mesh buffers and textures (gl/assets.c) */
    int nassets, assets_cap;

    limen_plan *plan;                       /* what to draw: the view tree of the frame ... */
    limen_drawables *draw;                  /* ... and the nodes, read once per frame ... */
    limen_drawlist *list;                   /* ... and the frame's commands */
    float background[3];                    /* the scene's, as the drawables read it */
    limen_render_opts opts;
    unsigned char *rgba;                    /* read-back buffer */
    bool have_frame;
};

#define GL(fn) r->gl.fn

/* Makes *p hold at least n elements of size bytes, doubling *cap (src/gl's own growth: it
 * sees no core header); false, *p untouched, when out of memory. */
static inline bool limen__gl_grow(void **p, int *cap, int n, size_t size)
{
    if (n <= *cap)
        return true;
    int c = *cap > 0 ? *cap : 64;
    while (c < n)
        c = c > INT_MAX / 2 ? n : c * 2;
    void *q = realloc(*p, size * (size_t)c);
    if (!q)
        return false;
    *p = q;
    *cap = c;
    return true;
}

/* The normal matrix of a model matrix: the inverse transpose of its 3x3 part. The one-node
 * draws (uniforms) and the instanced ones (gl/backend.c) both take it from here, so a node
 * shades the same either way. */
static inline void limen__normal_matrix(mat4 model, mat3 out)
{
    glm_mat4_pick3(model, out);
    glm_mat3_inv(out, out);
    glm_mat3_transpose(out);
}

/* Floats per instance (gl/backend.c): model matrix, normal matrix, albedo. */
#define LIMEN__INSTANCE_FLOATS 28

static inline GLenum limen__depth_format(const limen_renderer *r)
{
    return r->depth_bits == 32 ? GL_DEPTH32F_STENCIL8 : GL_DEPTH24_STENCIL8;
}

limen_status limen__rfail(limen_renderer *r, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Notes what a draw could not do (limen_renderer.draw_status): the first of a frame keeps its
 * status and message (fmt NULL: the message is set already). */
void limen__draw_fail(limen_renderer *r, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Faults for tests (src/core/testing.h declares the setter): uploads of meshes and
 * textures fail as if memory ran out. */
enum { LIMEN__RFAULT_UPLOAD = 1 };
void limen__renderer_set_faults(limen_renderer *r, unsigned faults);

/* Occlusion queries around the passes that shade and write colour (the frame's `samples`);
 * masks, depth resets and seals are not counted. */
void limen__samples_begin(limen_renderer *r);
void limen__samples_end(limen_renderer *r);

/* Shader variants (shader.c). limen__variant_use binds the variant for a draw (the lights
 * and clip distances as they are now set), uploads the shared values it lacks and points r->u
 * at its uniforms; false (message in err) where it cannot be built. */
GLuint limen__gl_link(limen_renderer *r, const char *head, const char *vsrc, const char *fsrc);
bool limen__variant_use(limen_renderer *r, int mode, int shape, int checker, int textured);
void limen__variants_free(limen_renderer *r);

/* gl/backend.c: draws the frame's list (r->list over r->draw) into the frame buffer
 * (bound by the caller). gl/targets.c: offscreen target k of w x h (made, or remade at
 * another size; NULL where it cannot be); all of them freed. */
limen_status limen__execute(limen_renderer *r, const limen_drawlist *dl);
limen__target *limen__target_get(limen_renderer *r, int k, int w, int h);
/* Target k's colour as a 2D texture to sample: resolved first where multisampled and drawn
 * since; 0 where there is none. Leaves GL_FRAMEBUFFER bound to `bound`. */
GLuint limen__target_texture(limen_renderer *r, int k, GLuint bound);
void limen__targets_free(limen_renderer *r);
/* gl/targets.c: a w x h RGBA8 texture sampled linear and clamped at its edges, left bound
 * (a target's colour, the previous frame's copy). */
GLuint limen__color_texture(limen_renderer *r, int w, int h);


/* gl/assets.c: a mesh's vertex arrays at a level of detail, bound with the flat or smooth
 * normals (what to draw: first and count of corners, or of indices where indexed; false if
 * it cannot); an image's texture (0 if it cannot); after a frame,
 * dropping what it did not use; everything, at the end. */
bool limen__gpu_mesh_bind(limen_renderer *r, const limen_mesh_geometry *m, bool smooth, int lod,
                          GLint *first, GLsizei *count, bool *indexed);
GLuint limen__gpu_texture(limen_renderer *r, const limen_image *t, limen_texture_filter filter);
/* The same on texture unit `unit` (2: a material's emissive texture). */
GLuint limen__gpu_texture_on(limen_renderer *r, const limen_image *t, int unit,
                             limen_texture_filter filter);
/* The level limen__gpu_mesh_bind draws for `lod` (clamped to the levels it keeps). */
int limen__gpu_mesh_level(const limen_mesh_geometry *m, int lod);
void limen__gpu_assets_sweep(limen_renderer *r);
void limen__gpu_assets_free(limen_renderer *r);

#endif
