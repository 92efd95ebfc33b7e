/* drawlist.h - the draw list's builder, shared by its files (drawlist.c: the list, views,
 * surfaces and things; drawlist_stencil.c: the stencil method; drawlist_texture.c: the
 * texture method; drawlist_batch.c: meshes, their batches and the triangle budget). */
#ifndef LIMEN_DRAWLIST_H
#define LIMEN_DRAWLIST_H

#include <stdbool.h>
#include <stdint.h>

#include "core/internal.h"
#include "core/reserve.h"

/* One view as the list draws it. */
typedef struct dl_view {
    const limen_view *pub;
    int index;
    int pass;                   /* its limen_draw_pass */
    int target;                 /* 0: the frame; k: target k (texture method) */
    mat4 view, proj, view_proj;
    float px_scale;             /* pixels per unit at distance 1 (for levels of detail) */
    float img_map[4];           /* image pixel = fragment * xy + zw in the target */
    vec4 cull[16];              /* world-space planes of the narrowed frustum (inside >= 0),
                                 * and (stencil method) of the view's pixels */
    int ncull;
} dl_view;

/* A surface as the screen sees it: its polygon clipped in double and split into the parts
 * depth clamping puts at the near and far planes and the part between, in NDC (x, y and,
 * for the middle part, z). */
typedef struct limen__spoly {
    int n[3];                   /* vertices of the near, far and middle parts */
    float p[3][32][3];
    float z[2];                 /* NDC depth of the near and far planes */
    double xy[32][2];           /* the whole polygon (the parts' union) in NDC x, y */
    int nxy;
} limen__spoly;

/* One of a view's things: its squared distance from the eye (to its bounding sphere's
 * centre) and its index in the drawables. */
typedef struct limen__dl_key {
    float dist;
    int node;
} limen__dl_key;

struct limen__dl_batch_item;
struct limen__dl_batch;

struct limen_drawlist {
    limen_draw_cmd *cmd;
    int ncmd, cmd_cap;
    limen_draw_pass *pass;
    int npass, pass_cap;
    float (*vert)[3];
    int nvert, vert_cap;
    limen_draw_instance *inst;
    int ninst, inst_cap;
    limen_draw_light lights[LIMEN_MAX_LIGHTS];
    int nlights;
    float ambient;
    char err[256];

    /* one build's inputs and scratch */
    const limen_plan *plan;
    const limen_drawables *d;
    const limen_drawable *items;
    int nitems;
    const limen_clone *clones;
    int nclones;
    limen_drawlist_desc desc;   /* defaults filled in */
    int width, height;
    limen_depth_range range;
    float background[3];
    bool blends;                /* some visible mesh has blended parts */
    bool blend_pass;            /* meshes draw their blended parts */
    bool nomem;
    uint64_t tris_left;         /* of budget.triangles */
    limen_draw_state st;        /* the state the next command is drawn with */
    int cur_pass;
    limen__dl_key *order;       /* a view's things, nearest first */
    int order_cap;
    int *clone_of;              /* per drawable: its limen_clone, or -1 */
    int clone_cap;
    struct limen__dl_batch_item *bitems;
    int bitems_cap;
    struct limen__dl_batch *batches;
    int batches_cap;
};

limen_draw_cmd *limen__dl_emit(limen_drawlist *dl, limen_draw_op op);
limen_draw_instance *limen__dl_instances(limen_drawlist *dl, int n);
limen_compare limen__dl_less(const limen_drawlist *dl);
bool limen__dl_depth_clamped(const limen_view *v, bool surface);
void limen__dl_surface_parts(const limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                          limen__spoly *sp);
/* drawlist.c, for the stencil method: a view (its pass made current), its pass written, its
 * cull planes (rect: the pixels it may draw, NULL for all), made current with its clip plane;
 * a surface's flat pass in one colour (sp: its parts) and the region fill at the far plane;
 * the view's opaque things; the drawable of a surface it recurses into (NULL otherwise); its
 * blended parts. */
bool limen__dl_view_make(limen_drawlist *dl, int index, dl_view *v);
void limen__dl_view_cull(const limen_drawlist *dl, dl_view *v, const int *rect);
void limen__dl_view_apply(limen_drawlist *dl, const dl_view *v);
void limen__dl_surface_flat(limen_drawlist *dl, const dl_view *v, const limen__spoly *sp,
                            const float rgb[3], bool fixed, float z);
void limen__dl_opaque(limen_drawlist *dl, const dl_view *v, const limen_view_surface *vs, int n);
const limen_drawable *limen__dl_recursed(const limen_drawlist *dl, const limen_view_surface *vs);
void limen__dl_blended(limen_drawlist *dl, const dl_view *v);
float limen__dl_far_z(const limen_drawlist *dl);
limen_compare limen__dl_lequal(const limen_drawlist *dl);

/* drawlist.c, for the texture method: the clip-space transform that stretches the image's
 * pixel rectangle rect over [-1, 1]^2; a view with its projection narrowed by proj_pre, as a
 * new current pass (written by limen__dl_view_pass once its image map and target are set);
 * a surface's flat pass in one colour (sp: its parts, NULL: computed), and the surface
 * showing an image times rgb. */
void limen__dl_narrow_to(const limen_drawlist *dl, const int rect[4], mat4 out);
bool limen__dl_view_new(limen_drawlist *dl, int index, mat4 proj_pre, dl_view *v);
void limen__dl_view_pass(limen_drawlist *dl, const dl_view *v);
void limen__dl_surface_fill(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                            const float *rgb, const limen__spoly *sp);
void limen__dl_surface_image(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                             const float *rgb, limen_draw_image image, const float map[4],
                             int target);

/* drawlist_stencil.c and drawlist_texture.c: the methods' commands. */
void limen__dl_stencil(limen_drawlist *dl);
void limen__dl_texture(limen_drawlist *dl);

/* drawlist_batch.c: one mesh lit at a world matrix (a copy carried through a portal, a node
 * cut at one); the batches of the meshes among a view's things (dl->order[0..n), not those
 * cut at a portal) that show the same geometry at the same level of detail alike, each
 * starting where its nearest member stands (their count; -1 when out of memory), where
 * batch b starts in the order, and batch b drawn. */
void limen__dl_mesh(limen_drawlist *dl, const dl_view *v, const limen_drawable *d,
                    const float world[16], const float albedo[3]);
int limen__dl_batches_plan(limen_drawlist *dl, const dl_view *v, int n);
int limen__dl_batch_first(const limen_drawlist *dl, int b);
void limen__dl_batch_draw(limen_drawlist *dl, const dl_view *v, int b);
void limen__dl_batches_free(limen_drawlist *dl);

#endif
