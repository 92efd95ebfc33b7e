/* gl_internal.h - the renderer's state, shared by its files (render.c: set-up and frames;
 * views.c: drawing a view tree, and its texture method; stencil.c: its stencil method). */
#ifndef LIMEN_GL_INTERNAL_H
#define LIMEN_GL_INTERNAL_H

#include <stdbool.h>

#include <cglm/cglm.h>

#include "limen.h"
#include "gl/glapi.h"
#include "gl/mesh.h"

/* A silhouette may stray this far (pixels) from the true curved shape. */
#define LOD_TOLERANCE_PX 0.2f
#define LIMEN__MAX_LEVELS 256

typedef struct uniforms {
    GLint model, normal_mat, view_proj, eye, clip_plane, clip_plane2, albedo, albedo_b, cell,
        scale, tint, tex, tex_map, ambient, light_pos, light_col, light_inv_r2, uv_repeat;
    GLint base, emissive, cutoff, emissive_on, blend;     /* materials (gl/batch.c) */
} uniforms;

/* Shader variants (shader.c): what a draw shades. */
enum { LIMEN__MODE_LIT = 0, LIMEN__MODE_FLAT = 1, LIMEN__MODE_TEXTURE = 2 };
/* ... the normals of a lit draw: the vertices' (flat per face), the true sphere's or
 * cylinder's, or a mesh's vertex normals interpolated (smooth) ... */
enum { LIMEN__SHAPE_FACE = 0, LIMEN__SHAPE_SPHERE = 1, LIMEN__SHAPE_CYLINDER = 2,
       LIMEN__SHAPE_SMOOTH = 3 };
/* ... and where an albedo texture's coordinates come from (limen.h): none, a plane's unit
 * point, a box face's two other axes, a mesh's own. */
enum { LIMEN__UV_NONE = 0, LIMEN__UV_PLANE = 1, LIMEN__UV_BOX = 2, LIMEN__UV_MESH = 3 };
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

/* An offscreen target for the texture method: one per recursion level. */
typedef struct limen__target {
    GLuint fbo, tex, depth_rb;
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

    GLuint vao, vbo, ibo;
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
    limen__meshes meshes;

    GLuint fbo, color_rb, depth_rb;         /* the frame (multisampled if msaa); host: the
                                             * game's framebuffer, no renderbuffers */
    GLuint resolve_fbo, resolve_rb;         /* single-sampled copy when msaa */
    GLuint q_fragments;
    GLuint *q_pool;                         /* occlusion queries around shading passes */
    int q_cap, q_used;
    bool q_active;
    bool counting;              /* this frame's stats were asked for: queries count it */
    limen__target levels[LIMEN__MAX_LEVELS];
    float levels_scale;                     /* texture scale the targets were made for */

    GLuint prev_fbo, prev_tex;              /* the previous frame, for LIMEN_FILL_PREVIOUS */
    bool have_prev;

    struct limen__draw_key *order;          /* a view's things, nearest first */
    int order_cap;
    limen_node *things;                     /* a view's candidates from the scene's index */
    int things_cap;
    limen_scene *scene;                     /* the scene of the frame being drawn */
    int draw_calls;                         /* this frame's (limen_frame_stats) */
    uint64_t triangles;
    uint64_t mesh_tris_left;                /* of the frame's budget.triangles */
    bool instanced;                         /* variants read the model from instances */
    bool material;                          /* ... and a mesh part's material (gl/batch.c) */
    bool blend_pass;                        /* mesh draws draw their blended parts only */
    GLuint inst_vbo;                        /* per-instance values (gl/batch.c) */
    struct limen__instance *inst;
    int inst_cap;
    struct limen__batch *batches;           /* a view's meshes in batches (gl/batch.c) */
    struct limen__batch_item *batch_items;
    int batch_cap;

    struct limen__gpu_asset *assets;        /* mesh buffers and textures (gl/assets.c) */
    int nassets, assets_cap;

    limen_plan *plan;                       /* what to draw: the view tree of the frame ... */
    limen_drawables *draw;                  /* ... and the nodes, read once per frame */
    int *clone_of, clone_of_cap;            /* per drawable: its limen_clone, or -1 */
    float background[3], ambient;           /* the scene's, as the drawables read them */
    limen_render_opts opts;
    unsigned char *rgba;                    /* read-back buffer */
    bool have_frame;
};

#define GL(fn) r->gl.fn

/* The normal matrix of a model matrix: the inverse transpose of its 3x3 part. The one-node
 * draws (uniforms) and the instanced ones (gl/batch.c) both take it from here, so a node
 * shades the same either way. */
static inline void limen__normal_matrix(mat4 model, mat3 out)
{
    glm_mat4_pick3(model, out);
    glm_mat3_inv(out, out);
    glm_mat3_transpose(out);
}

/* Depth clamping for a lit draw in view v, the same for one node and for a batch: mirrors
 * and portals are not cut by the near plane (a camera closer to one than its near distance
 * still sees through it, and the ray tracer agrees); and in a view cut by a user clip plane
 * (the eye too near its exit surface for an oblique near plane) the clip plane alone cuts:
 * its own near plane would also drop what lies just in front of the exit. */
static inline bool limen__depth_clamped(const limen_view *v, bool surface)
{
    return surface || (v->clip == LIMEN_CLIP_PLANE && v->depth > 0);
}

/* Floats per instance (gl/batch.c): model matrix, normal matrix, albedo. */
#define LIMEN__INSTANCE_FLOATS 28

/* One of a view's things: its squared distance from the eye (to its bounding sphere's
 * centre) and its index in the drawables. */
struct limen__draw_key {
    float dist;
    int node;
};

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

/* ------------------------------------------------------------------ drawing views (views.c) */

/* One view as the renderer draws it. */
typedef struct rview {
    const limen_view *pub;
    int index;
    mat4 view, proj, view_proj;
    float px_scale;             /* pixels per unit at distance 1 (for levels of detail) */
    float img_map[4];           /* image pixel = gl_FragCoord * xy + zw in the target */
    vec4 cull[16];              /* world-space planes of the narrowed frustum (inside >= 0),
                                 * and (stencil method) of the view's pixels */
    int ncull;
} rview;

/* A surface as the screen sees it: its polygon clipped in double and split into the parts
 * depth clamping puts at the near and far planes and the part between, in NDC (x, y and,
 * for the middle part, z). The same floats serve every pass over the surface, so its depth,
 * its mark, its seal and the nested view's region cover the same pixels. */
typedef struct limen__spoly {
    int n[3];                   /* vertices of the near, far and middle parts */
    float p[3][32][3];
    float z[2];                 /* NDC depth of the near and far planes */
    double xy[32][2];           /* the whole polygon (the parts' union) in NDC x, y */
    int nxy;
} limen__spoly;

/* A view's matrices (proj_pre: the texture method's narrowing, identity otherwise), its cull
 * planes (rect: the pixels it may draw, NULL for all), and its state bound for drawing. */
void limen__rview_make(limen_renderer *r, int index, mat4 proj_pre, rview *v);
void limen__rview_cull(limen_renderer *r, rview *v, const int *rect);
void limen__rview_apply(limen_renderer *r, const rview *v);
/* The scene's lights, once per frame. */
void limen__lights_set(limen_renderer *r);
/* A surface's polygon as view v sees it, in parts (computed where sp is NULL for the flat
 * pass); the flat pass of a surface (MODE_FLAT or MODE_TEXTURE) and of parts in one colour,
 * at their own depth or all at z where fixed. */
void limen__surface_parts(const limen_renderer *r, const rview *v, const limen_drawable *node,
                          limen__spoly *sp);
void limen__surface_flat(limen_renderer *r, const rview *v, const limen_drawable *node,
                         int mode, const float *albedo, const limen__spoly *sp);
void limen__flat_parts(limen_renderer *r, const rview *v, const limen__spoly *sp,
                       const float rgb[3], bool fixed, float z);
/* The view's opaque things (the surfaces that end there, then the geometry), shaded. */
void limen__draw_opaque(limen_renderer *r, const rview *v, const limen_view_surface *vs, int n);
/* The drawable of a surface that a view recurses into; NULL for the others. */
const limen_drawable *limen__recursed(const limen_renderer *r, const limen_view_surface *vs);
/* GL_LESS and GL_LEQUAL, or their reverse where depth is reversed. */
GLenum limen__depth_less(const limen_renderer *r);
GLenum limen__depth_lequal(const limen_renderer *r);

/* Draws the planned tree of r->plan and r->draw into the frame buffer (bound by the caller,
 * cleared). */
limen_status limen__draw_stencil(limen_renderer *r);       /* stencil.c */
limen_status limen__draw_texture(limen_renderer *r);       /* views.c */
void limen__targets_free(limen_renderer *r);

/* gl/mesh.c: which unit mesh, and how it is scaled, for a node seen through a view (its
 * view matrix and pixels per unit at distance 1, for the level of detail); shape: the
 * normals it needs (LIMEN__SHAPE_*). False if the node is not drawn with one. */
bool limen__unit_mesh(limen_renderer *r, const vec4 *view, float px_scale, const limen_drawable *node,
                      mat4 world, limen__range *range, vec3 scale, int *shape);

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
/* gl/views.c: view v's meshes' blended parts, farthest first, over what it drew (both
 * methods call it once a view's picture, its surfaces' included, is complete). */
void limen__draw_blended(limen_renderer *r, const rview *v);
/* Whether some visible mesh has blended parts (then the stencil method counts depth). */
bool limen__scene_blends(const limen_renderer *r);
void limen__gpu_assets_sweep(limen_renderer *r);
void limen__gpu_assets_free(limen_renderer *r);

/* gl/batch.c: meshes drawn instanced. limen__batches_plan groups the meshes among a view's
 * things (order[0..n), nearest first; not those cut at a portal) that show the same
 * geometry at the same level of detail alike, each group starting where its nearest member
 * stands; returns the number of groups (-1: out of memory, draw each alone).
 * limen__batch_first gives where group b starts in order, limen__batch_draw draws it, and
 * limen__mesh_draw draws one mesh node at a world matrix (a copy carried through a portal,
 * a node cut at one). Each binds the unit meshes' arrays again after. limen__batches_free
 * frees their memory (the instance buffer goes with the context). */
int limen__batches_plan(limen_renderer *r, const limen_view *v, const limen_drawable *items,
                        const struct limen__draw_key *order, int n);
int limen__batch_first(const limen_renderer *r, int b);
void limen__batch_draw(limen_renderer *r, const limen_view *v, const limen_drawable *items, int b);
void limen__mesh_draw(limen_renderer *r, const limen_view *v, const limen_drawable *d,
                      const float world[16], const float albedo[3]);
void limen__batches_free(limen_renderer *r);

#endif
