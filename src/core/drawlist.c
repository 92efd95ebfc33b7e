/* drawlist.c - one frame as a list of commands (limen.h, "draw list"; docs/DESIGN.md, "The
 * draw list"): the API-neutral half of drawing a planned view tree. It walks the plan as a
 * renderer would, keeping the pipeline state it would have set in `st`, and writes each draw
 * as a command with that state: the stencil method (drawlist_stencil.c: every view in the
 * frame, on the pixels the stencil buffer gives it) and the texture method
 * (drawlist_texture.c: each nested view into a target of its depth). The surfaces' polygons are clipped here in double precision, the views' things
 * culled and sorted nearest first, meshes sharing geometry batched (drawlist_batch.c), and
 * the triangle budget spent, so that a backend only executes. */
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "core/drawlist.h"
#include "core/lmath.h"
#include "core/plan.h"
#include "core/shapes.h"

static const float keep_all[4] = { 0, 0, 0, 1 };

static void polygon_parts(limen_drawlist *dl, const dl_view *v, const limen__spoly *sp,
                          const float rgb[3], bool fixed, float z, limen_draw_image image,
                          const float map[4], int target);

/* ------------------------------------------------------------------ list storage */

limen_status limen_drawlist_create(limen_drawlist **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    *out = calloc(1, sizeof **out);
    return *out ? LIMEN_OK : LIMEN_ERR_NOMEM;
}

void limen_drawlist_destroy(limen_drawlist *dl)
{
    if (!dl)
        return;
    free(dl->cmd);
    free(dl->pass);
    free(dl->vert);
    free(dl->inst);
    free(dl->order);
    free(dl->clone_of);
    limen__dl_batches_free(dl);
    free(dl);
}

int limen_drawlist_commands(const limen_drawlist *dl, const limen_draw_cmd **out)
{
    if (out)
        *out = dl && dl->ncmd ? dl->cmd : NULL;
    return dl ? dl->ncmd : 0;
}

int limen_drawlist_passes(const limen_drawlist *dl, const limen_draw_pass **out)
{
    if (out)
        *out = dl && dl->npass ? dl->pass : NULL;
    return dl ? dl->npass : 0;
}

int limen_drawlist_vertices(const limen_drawlist *dl, const float (**out)[3])
{
    if (out)
        *out = dl && dl->nvert ? (const float(*)[3])dl->vert : NULL;
    return dl ? dl->nvert : 0;
}

int limen_drawlist_instances(const limen_drawlist *dl, const limen_draw_instance **out)
{
    if (out)
        *out = dl && dl->ninst ? dl->inst : NULL;
    return dl ? dl->ninst : 0;
}

int limen_drawlist_lights(const limen_drawlist *dl, const limen_draw_light **out, float *ambient)
{
    if (out)
        *out = dl && dl->nlights ? dl->lights : NULL;
    if (ambient)
        *ambient = dl ? dl->ambient : 0;
    return dl ? dl->nlights : 0;
}

const char *limen_drawlist_error(const limen_drawlist *dl)
{
    return dl ? dl->err : "no draw list";
}

static limen_status dl_fail(limen_drawlist *dl, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static limen_status dl_fail(limen_drawlist *dl, limen_status st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(dl->err, sizeof dl->err, fmt, ap);
    va_end(ap);
    dl->ncmd = dl->npass = dl->nvert = dl->ninst = dl->nlights = 0;
    return st;
}

/* A new command of the current pass and state, the rest zero; NULL when out of memory (the
 * build then fails). */
limen_draw_cmd *limen__dl_emit(limen_drawlist *dl, limen_draw_op op)
{
    if (dl->nomem || !limen__reserve((void **)&dl->cmd, &dl->cmd_cap, dl->ncmd + 1,
                                     sizeof *dl->cmd)) {
        dl->nomem = true;
        return NULL;
    }
    limen_draw_cmd *c = &dl->cmd[dl->ncmd++];
    memset(c, 0, sizeof *c);
    c->op = op;
    c->pass = dl->cur_pass;
    c->state = dl->st;
    return c;
}

/* Room for n more instances; NULL when out of memory. */
limen_draw_instance *limen__dl_instances(limen_drawlist *dl, int n)
{
    if (dl->nomem || !limen__reserve((void **)&dl->inst, &dl->inst_cap, dl->ninst + n,
                                     sizeof *dl->inst)) {
        dl->nomem = true;
        return NULL;
    }
    return &dl->inst[dl->ninst];
}

/* ------------------------------------------------------------------ depth range */

/* The test a draw that must be nearer than what is there uses, and the one for at least as
 * near: LESS and LEQUAL, or their reverse where depth is reversed (the one place this is
 * decided). */
limen_compare limen__dl_less(const limen_drawlist *dl)
{
    return dl->range == LIMEN_DEPTH_ZO_REVERSED ? LIMEN_COMPARE_GREATER : LIMEN_COMPARE_LESS;
}

limen_compare limen__dl_lequal(const limen_drawlist *dl)
{
    return dl->range == LIMEN_DEPTH_ZO_REVERSED ? LIMEN_COMPARE_GEQUAL : LIMEN_COMPARE_LEQUAL;
}

/* NDC depth of the far plane (what a clear writes). */
float limen__dl_far_z(const limen_drawlist *dl)
{
    return dl->range == LIMEN_DEPTH_ZO_REVERSED ? 0.0f : 1.0f;
}

/* ------------------------------------------------------------------ views */

/* What the kinds table says of a drawable's kind (nothing for one it does not know). */
static const limen_kind_info *kind_of(const limen_drawable *d)
{
    static const limen_kind_info none = { .name = "" };
    const limen_kind_info *k = limen_kind_get(d->kind);
    return k ? k : &none;
}

static bool is_surface(const limen_drawable *d)
{
    return kind_of(d)->surface;
}

/* The drawable of a node the plan names (a surface, a clone); NULL if it has none. */
static const limen_drawable *item_of(const limen_drawlist *dl, limen_node n)
{
    int i = limen_drawables_find(dl->d, n);
    return i >= 0 ? &dl->items[i] : NULL;
}

/* The clip-space transform that stretches the pixel rectangle rect of the image over the
 * whole of [-1, 1]^2. */
void limen__dl_narrow_to(const limen_drawlist *dl, const int rect[4], mat4 out)
{
    float W = (float)dl->width, H = (float)dl->height;
    float x0 = 2.0f * rect[0] / W - 1.0f, x1 = 2.0f * (rect[0] + rect[2]) / W - 1.0f;
    float y0 = 2.0f * rect[1] / H - 1.0f, y1 = 2.0f * (rect[1] + rect[3]) / H - 1.0f;
    glm_mat4_identity(out);
    out[0][0] = 2.0f / (x1 - x0);
    out[1][1] = 2.0f / (y1 - y0);
    out[3][0] = -(x1 + x0) / (x1 - x0);
    out[3][1] = -(y1 + y0) / (y1 - y0);
}

/* View `index` with its projection narrowed by proj_pre (the texture method's target
 * rectangle; identity otherwise), as a new pass that becomes the current one. */
bool limen__dl_view_new(limen_drawlist *dl, int index, mat4 proj_pre, dl_view *v)
{
    const limen_view *pub = limen_plan_view(dl->plan, index);
    v->pub = pub;
    v->index = index;
    memcpy(v->view, pub->view, sizeof v->view);
    memcpy(v->proj, pub->proj, sizeof v->proj);
    glm_mat4_mul(proj_pre, v->proj, v->proj);
    glm_mat4_mul(v->proj, v->view, v->view_proj);
    v->px_scale = pub->proj[5] * 0.5f * (float)dl->height;
    v->img_map[0] = v->img_map[1] = 1.0f;
    v->img_map[2] = v->img_map[3] = -0.0f;
    v->target = 0;
    if (dl->nomem || !limen__reserve((void **)&dl->pass, &dl->pass_cap, dl->npass + 1,
                                     sizeof *dl->pass)) {
        dl->nomem = true;
        return false;
    }
    v->pass = dl->npass++;
    dl->cur_pass = v->pass;
    return true;
}

/* Writes v's pass (after the texture method has set its image map and target). */
void limen__dl_view_pass(limen_drawlist *dl, const dl_view *v)
{
    limen_draw_pass *p = &dl->pass[v->pass];
    p->view = v->index;
    memcpy(p->view_proj, v->view_proj, sizeof p->view_proj);
    memcpy(p->view_mat, v->view, sizeof p->view_mat);
    memcpy(p->eye, v->pub->eye, sizeof p->eye);
    memcpy(p->tint, v->pub->tint, sizeof p->tint);
    p->front_cw = v->pub->front_face_cw != 0;
    p->px_scale = v->px_scale;
    memcpy(p->frag_map, v->img_map, sizeof p->frag_map);
    p->target = v->target;
}

bool limen__dl_view_make(limen_drawlist *dl, int index, dl_view *v)
{
    mat4 id;
    glm_mat4_identity(id);
    if (!limen__dl_view_new(dl, index, id, v))
        return false;
    limen__dl_view_pass(dl, v);
    return true;
}

void limen__dl_surface_flat(limen_drawlist *dl, const dl_view *v, const limen__spoly *sp,
                            const float rgb[3], bool fixed, float z)
{
    polygon_parts(dl, v, sp, rgb, fixed, z, LIMEN_IMAGE_NONE, NULL, 0);
}

/* The planes of what view v can show: its projection's sides narrowed to the pixels it
 * may draw (rect; NULL: all), its near plane (the oblique one where there is one) and its
 * clip plane. A node whose bounding sphere lies wholly outside one of them cannot touch a
 * pixel. */
void limen__dl_view_cull(const limen_drawlist *dl, dl_view *v, const int *rect)
{
    double m[16], planes[6][4], ndc[4];
    for (int k = 0; k < 16; k++)
        m[k] = v->view_proj[k / 4][k % 4];
    if (rect) {
        ndc[0] = 2.0 * rect[0] / dl->width - 1, ndc[1] = 2.0 * (rect[0] + rect[2]) / dl->width - 1;
        ndc[2] = 2.0 * rect[1] / dl->height - 1, ndc[3] = 2.0 * (rect[1] + rect[3]) / dl->height - 1;
    }
    limen__frustum_planes(m, rect ? ndc : NULL, dl->range, planes);
    v->ncull = 0;
    for (int i = 0; i < 5; i++) {       /* the sides and the near plane (the far one: none) */
        const double *pl = planes[i];
        double len = sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
        if (!(len > 0))
            continue;
        for (int c = 0; c < 4; c++)
            v->cull[v->ncull][c] = (float)(pl[c] / len);
        v->ncull++;
    }
    if (v->pub->clip == LIMEN_CLIP_PLANE)
        memcpy(v->cull[v->ncull++], v->pub->clip_plane, sizeof(float) * 4);
}

/* Whether drawable n (carried by a clone's portal matrix where carry is not NULL) lies
 * wholly outside one of v's cull planes. */
static bool outside(const dl_view *v, const limen_drawable *n, const float *carry)
{
    double rad = n->radius;
    vec3 cf = { n->centre[0], n->centre[1], n->centre[2] };
    if (carry) {
        mat4 m;
        memcpy(m, carry, sizeof m);
        glm_mat4_mulv3(m, cf, 1.0f, cf);
        rad *= glm_vec3_norm(m[0]);
    }
    for (int i = 0; i < v->ncull; i++)
        if (glm_vec3_dot((float *)v->cull[i], cf) + v->cull[i][3] < -(float)rad)
            return true;
    return false;
}

/* Whether the view must cut what lies behind its exit surface: every nested view but those
 * of the CLIP_NONE baseline. */
static bool exit_cuts(const dl_view *v)
{
    return v->pub->depth > 0 && v->pub->clip != LIMEN_CLIP_NONE;
}

/* Makes v the current pass, with its clip plane where it has one. */
void limen__dl_view_apply(limen_drawlist *dl, const dl_view *v)
{
    dl->cur_pass = v->pass;
    bool plane = v->pub->clip == LIMEN_CLIP_PLANE;
    dl->st.clip_on = plane;
    memcpy(dl->st.clip, plane ? v->pub->clip_plane : keep_all, sizeof dl->st.clip);
}

/* Clip distance 1: the cut of a shape passing through a portal (NULL: none). */
static void set_cut(limen_drawlist *dl, const float *plane)
{
    dl->st.cut_on = plane != NULL;
    memcpy(dl->st.cut, plane ? plane : keep_all, sizeof dl->st.cut);
}

/* Depth clamping for a lit draw in view v: mirrors and portals are not cut by the near plane
 * (a camera closer to one than its near distance still sees through it, and the ray tracer
 * agrees); and in a view cut by a user clip plane (the eye too near its exit surface for an
 * oblique near plane) the clip plane alone cuts: its own near plane would also drop what
 * lies just in front of the exit. */
bool limen__dl_depth_clamped(const limen_view *v, bool surface)
{
    return surface || (v->clip == LIMEN_CLIP_PLANE && v->depth > 0);
}

/* ------------------------------------------------------------------ surfaces as polygons */

/* polygons of up to 31 vertices in arrays of 32 */
static int clip4(double in[][4], int n, const double pl[4], double out[][4])
{
    return limen_clip_polygon(&in[0][0], n, pl, &out[0][0], 31);
}

static void to_ndc(double p[][4], int n, float out[][3], int *count)
{
    *count = n < 3 ? 0 : n;
    for (int i = 0; i < *count; i++)
        for (int k = 0; k < 3; k++)
            out[i][k] = (float)(p[i][k] / p[i][3]);
}

/* The surface polygon clipped to the view's exit plane (in every nested view: with depth
 * clamping an oblique near plane would not cut it), to the frustum's four sides (so that the
 * GPU clips nothing: its float clipping fails when the surface nearly touches the eye, w a
 * few float steps of x), then split at the near and far planes. */
void limen__dl_surface_parts(const limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                          limen__spoly *sp)
{
    double a[32][4], b[32][4], c[32][4];
    const double lx[4] = { -0.5, 0.5, 0.5, -0.5 }, ly[4] = { -0.5, -0.5, 0.5, 0.5 };
    const float *w = node->world;
    for (int i = 0; i < 4; i++) {
        for (int k = 0; k < 3; k++)
            a[i][k] = (double)w[k] * lx[i] * node->dims[0] +
                      (double)w[4 + k] * ly[i] * node->dims[1] + w[12 + k];
        a[i][3] = 1;
    }
    int n = 4;
    if (exit_cuts(v)) {
        const double cp[4] = { v->pub->clip_plane[0], v->pub->clip_plane[1],
                               v->pub->clip_plane[2], v->pub->clip_plane[3] };
        n = clip4(a, n, cp, b);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    for (int i = 0; i < n; i++) {
        double q[4];
        for (int row = 0; row < 4; row++)
            q[row] = (double)v->view_proj[0][row] * a[i][0] + (double)v->view_proj[1][row] * a[i][1] +
                     (double)v->view_proj[2][row] * a[i][2] + (double)v->view_proj[3][row] * a[i][3];
        memcpy(a[i], q, sizeof q);
    }
    static const double sides[4][4] = { { -1, 0, 0, 1 }, { 1, 0, 0, 1 }, { 0, -1, 0, 1 }, { 0, 1, 0, 1 } };
    for (int k = 0; k < 4 && n >= 3; k++) {
        n = clip4(a, n, sides[k], b);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    int m = 0;
    for (int i = 0; i < n; i++)
        if (a[i][3] > 0)
            memcpy(b[m++], a[i], sizeof(double) * 4);
    n = m;
    memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    memset(sp->n, 0, sizeof sp->n);
    sp->nxy = n < 3 ? 0 : n;
    for (int i = 0; i < sp->nxy; i++)
        sp->xy[i][0] = a[i][0] / a[i][3], sp->xy[i][1] = a[i][1] / a[i][3];
    /* near and far planes (inside >= 0) and the depths clamping gives beyond them */
    double np[4] = { 0, 0, 1, 1 }, fp[4] = { 0, 0, -1, 1 };
    sp->z[0] = -1, sp->z[1] = 1;
    if (dl->range == LIMEN_DEPTH_ZO) {
        np[3] = 0, sp->z[0] = 0;
    } else if (dl->range == LIMEN_DEPTH_ZO_REVERSED) {
        double t1[4] = { 0, 0, -1, 1 }, t2[4] = { 0, 0, 1, 0 };
        memcpy(np, t1, sizeof np), memcpy(fp, t2, sizeof fp);
        sp->z[0] = 1, sp->z[1] = 0;
    }
    if (n < 3)
        return;
    double nn[4] = { -np[0], -np[1], -np[2], -np[3] }, fn[4] = { -fp[0], -fp[1], -fp[2], -fp[3] };
    to_ndc(c, clip4(a, n, nn, c), sp->p[0], &sp->n[0]);
    to_ndc(c, clip4(a, n, fn, c), sp->p[1], &sp->n[1]);
    int k = clip4(a, n, np, c);
    to_ndc(b, clip4(c, k, fp, b), sp->p[2], &sp->n[2]);
}

/* The parts of sp as POLYGON commands in colour rgb (times the tint where `tinted`), at their
 * own depth or all at z where fixed, with an image where `image` is not NONE. The same floats
 * serve every pass over a surface, so its depth, its mark, its seal and the nested view's
 * region cover the same pixels. */
static void polygon_parts(limen_drawlist *dl, const dl_view *v, const limen__spoly *sp,
                          const float rgb[3], bool fixed, float z, limen_draw_image image,
                          const float map[4], int target)
{
    float c[3] = { rgb[0], rgb[1], rgb[2] };
    if (image == LIMEN_IMAGE_NONE) {
        const float *t = v->pub->tint;
        c[0] = rgb[0] * t[0], c[1] = rgb[1] * t[1], c[2] = rgb[2] * t[2];
    }
    for (int part = 0; part < 3; part++) {
        int n = sp->n[part];
        if (n < 3)
            continue;
        if (dl->nomem || !limen__reserve((void **)&dl->vert, &dl->vert_cap, dl->nvert + n,
                                         sizeof *dl->vert)) {
            dl->nomem = true;
            return;
        }
        float pz = fixed ? z : part < 2 ? sp->z[part] : 0;
        float (*out)[3] = &dl->vert[dl->nvert];
        for (int i = 0; i < n; i++) {
            out[i][0] = sp->p[part][i][0];
            out[i][1] = sp->p[part][i][1];
            out[i][2] = !fixed && part == 2 ? sp->p[part][i][2] : pz;
        }
        limen_draw_cmd *cmd = limen__dl_emit(dl, LIMEN_DRAW_POLYGON);
        if (!cmd)
            return;
        cmd->first = dl->nvert;
        cmd->count = n;
        dl->nvert += n;
        memcpy(cmd->color, c, sizeof c);
        cmd->image = image;
        if (map)
            memcpy(cmd->image_map, map, sizeof cmd->image_map);
        cmd->target = target;
        /* NDC already clipped: clamped depth, both sides, no clip distances */
        cmd->state.depth_clamp = 1;
        cmd->state.cull_back = 0;
        cmd->state.clip_on = cmd->state.cut_on = 0;
        memcpy(cmd->state.clip, keep_all, sizeof keep_all);
        memcpy(cmd->state.cut, keep_all, sizeof keep_all);
    }
}

/* A surface's flat pass in one colour (mark, seal, depth, fill) from its parts (computed
 * here where sp is NULL). */
void limen__dl_surface_fill(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                         const float *rgb, const limen__spoly *sp)
{
    limen__spoly own;
    if (!sp) {
        limen__dl_surface_parts(dl, v, node, &own);
        sp = &own;
    }
    polygon_parts(dl, v, sp, rgb, false, 0, LIMEN_IMAGE_NONE, NULL, 0);
}

/* A surface showing an image (a child's target, the previous frame) times rgb. */
void limen__dl_surface_image(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                          const float *rgb, limen_draw_image image, const float map[4],
                          int target)
{
    limen__spoly sp;
    limen__dl_surface_parts(dl, v, node, &sp);
    polygon_parts(dl, v, &sp, rgb, false, 0, image, map, target);
}

/* ------------------------------------------------------------------ things */

/* The tolerance (pixels) within which a curved shape's silhouette must stay of the true
 * shape (the ray tracer's). */
#define SILHOUETTE_PX 0.2f

/* The coarsest tessellation of the unit shapes' (core/shapes.c) whose polygon stays within
 * tol_px of a circle of radius_px. */
static int segments_for(float radius_px, float tol_px)
{
    for (int k = LIMEN__UNIT_LEVELS - 1; k > 0; k--) {
        /* largest gap between the pushed-out sphere and the true one, either way */
        double c = cos(M_PI / limen__unit_segments[k]);
        double sag = radius_px * (1.0 - c * c) / (1.0 + c * c);
        if (sag <= tol_px)
            return limen__unit_segments[k];
    }
    return limen__unit_segments[0];
}

/* A curved shape's segments in view v at world matrix w, from its projected size: the
 * largest world-space stretch of its axes times its radius (the largest half-extent of its
 * unit box, stretched by its dims: a ball's radius, a cylinder's radius or half height),
 * over the view distance of its centre (0 for a shape without tessellations). Multisampled,
 * a silhouette's error band holds msaa samples per pixel of its area, each changing its
 * pixel by 1/msaa of the contrast, so it takes a band msaa times thinner to leave as few
 * pixels off the area-averaged truth as one sample per pixel leaves. */
static int shape_segments(const limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                          const float w[16])
{
    const limen_kind_info *k = kind_of(node);
    if (limen__unit_levels(k->unit) < 2)
        return 0;
    float radius = 0;
    for (int a = 0; a < 3; a++)
        radius = fmaxf(radius, 0.5f * (k->hi[a] - k->lo[a]) *
                                   (k->scale[a] >= 0 ? node->dims[k->scale[a]] : 1.0f));
    mat4 world, view;
    memcpy(world, w, sizeof world);
    memcpy(view, v->view, sizeof view);
    float stretch = fmaxf(glm_vec3_norm(world[0]),
                          fmaxf(glm_vec3_norm(world[1]), glm_vec3_norm(world[2])));
    float world_r = radius * stretch;
    vec4 centre = { world[3][0], world[3][1], world[3][2], 1.0f };
    vec4 vc;
    glm_mat4_mulv(view, centre, vc);
    /* a view matrix through scaled portals scales distances: measure in its own units */
    float view_scale = glm_vec3_norm(view[0]);
    float dist = -vc[2];
    world_r *= view_scale;
    int msaa = dl->desc.msaa;
    float tol = msaa > 1 ? SILHOUETTE_PX / (float)msaa : SILHOUETTE_PX;
    if (dist > world_r * 1.01f)
        return segments_for(world_r * v->px_scale / (dist - world_r), tol);
    return limen__unit_segments[0];
}

/* One shape lit at a world matrix (a copy carried through a portal has its own). */
static void shape_at(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                     const float world[16], const float *albedo)
{
    if (node->kind == LIMEN_NODE_MESH) {
        limen__dl_mesh(dl, v, node, world, albedo);
        return;
    }
    const limen_kind_info *k = kind_of(node);
    limen_draw_instance *inst = k->unit ? limen__dl_instances(dl, 1) : NULL;
    limen_draw_cmd *c = inst ? limen__dl_emit(dl, LIMEN_DRAW_SHAPE) : NULL;
    if (!c)
        return;
    c->item = (int)(node - dl->items);
    memcpy(c->world, world, sizeof c->world);
    c->segments = shape_segments(dl, v, node, world);
    c->lod = c->segments ? limen__unit_level(c->segments) : 0;
    for (int a = 0; a < 3; a++)
        c->scale[a] = k->scale[a] >= 0 ? node->dims[k->scale[a]] : 1.0f;
    /* and as an instance of the unit geometry: world times the stretch (by column), albedo */
    for (int i = 0; i < 16; i++)
        inst->world[i] = world[i] * (i < 12 ? c->scale[i / 4] : 1.0f);
    memcpy(inst->color, albedo, sizeof inst->color);
    c->first = dl->ninst++;
    c->count = 1;
    memcpy(c->color, albedo, sizeof c->color);
    /* In an oblique view the near plane is the exit plane, and clamping would keep what of a
     * surface lies beyond it (a neighbour poking through a mirror shows its back there):
     * the view's clip plane cuts it instead, as in a plane view. */
    if (is_surface(node) && exit_cuts(v) && v->pub->clip == LIMEN_CLIP_OBLIQUE) {
        c->state.clip_on = 1;
        memcpy(c->state.clip, v->pub->clip_plane, sizeof c->state.clip);
    }
    c->state.depth_clamp = limen__dl_depth_clamped(v->pub, is_surface(node));
    /* closed shapes hide their back faces; flat ones are seen from both sides */
    c->state.cull_back = kind_of(node)->closed != 0;
}

static void thing_lit(limen_drawlist *dl, const dl_view *v, const limen_drawable *node,
                      const float *albedo)
{
    shape_at(dl, v, node, node->world, albedo);
}

static int by_distance(const void *a, const void *b)
{
    const limen__dl_key *x = a, *y = b;
    int c = (x->dist > y->dist) - (x->dist < y->dist);
    return c ? c : (x->node > y->node) - (x->node < y->node);
}

/* A shape (not a surface, not a light) that view v may show. */
static bool shows(const dl_view *v, const limen_drawable *d)
{
    return d->visible && kind_of(d)->shape && !outside(v, d, NULL);
}

/* The shapes view v can show, nearest first (so that, without a depth-only pass, what lies
 * behind fails the depth test before it is shaded; ties in list order), in dl->order: of
 * the things the plan keeps for the view (limen_plan_things), those within v's cull planes.
 * Returns the count, or -1 when out of memory. */
static int view_order(limen_drawlist *dl, const dl_view *v)
{
    const limen_node *things;
    int nt = limen_plan_things(dl->plan, v->index, &things);
    if (!limen__reserve((void **)&dl->order, &dl->order_cap, nt, sizeof *dl->order)) {
        dl->nomem = true;
        return -1;
    }
    int n = 0;
    for (int k = 0; k < nt; k++) {
        int i = limen_drawables_find(dl->d, things[k]);
        if (i < 0 || !shows(v, &dl->items[i]))
            continue;
        const float *c = dl->items[i].centre, *eye = v->pub->eye;
        double dx = (double)c[0] - eye[0], dy = (double)c[1] - eye[1], dz = (double)c[2] - eye[2];
        dl->order[n++] = (limen__dl_key){ (float)(dx * dx + dy * dy + dz * dz), i };
    }
    if (n > 1)
        qsort(dl->order, (size_t)n, sizeof *dl->order, by_distance);
    return n;
}

/* Drawable i, cut at its portal where it passes through one. */
static void draw_thing(limen_drawlist *dl, const dl_view *v, int i)
{
    int c = dl->clone_of[i];
    if (c >= 0)
        set_cut(dl, dl->clones[c].keep);
    thing_lit(dl, v, &dl->items[i], dl->items[i].color);
    if (c >= 0)
        set_cut(dl, NULL);
}

/* The copies of what has gone into a portal, coming out of its partner (limen_plan_clones),
 * each cut at the partner's plane; only meshes with blended parts where blended (the blend
 * pass). */
static void draw_clones(limen_drawlist *dl, const dl_view *v, bool blended)
{
    for (int c = 0; c < dl->nclones; c++) {
        const limen_clone *cl = &dl->clones[c];
        const limen_drawable *node = item_of(dl, cl->node);
        if (!node || (blended && (node->kind != LIMEN_NODE_MESH || !node->mesh ||
                                  !node->mesh->has_blend)) ||
            outside(v, node, cl->matrix))
            continue;
        mat4 carry, own, world;
        memcpy(carry, cl->matrix, sizeof carry);
        memcpy(own, node->world, sizeof own);
        glm_mat4_mul(carry, own, world);
        set_cut(dl, cl->copy_keep);
        shape_at(dl, v, node, (const float *)world, node->color);
        set_cut(dl, NULL);
    }
}

/* fresh: nothing is in the view's depth yet (it sees no surface). Then the nearest thing,
 * drawn first, passes the depth test wherever it lands if it is a shape (each is convex,
 * closed ones without their back faces; a mesh need not be): it only writes depth, which
 * a rasterizer can do without reading it. */
static void draw_geometry(limen_drawlist *dl, const dl_view *v, bool fresh)
{
    int n = view_order(dl, v);
    if (n < 0)
        return;
    /* meshes that share geometry go in batches, each drawn where its nearest member stands */
    int nb = n > 0 ? limen__dl_batches_plan(dl, v, n) : 0, b = 0;
    if (nb < 0)
        return;
    const limen_drawable *items = dl->items;
    bool first_free = fresh && n > 0 && items[dl->order[0].node].kind != LIMEN_NODE_MESH;
    for (int k = 0; k < n; k++) {
        int i = dl->order[k].node;
        if (items[i].kind == LIMEN_NODE_MESH && dl->clone_of[i] < 0) {
            if (b < nb && limen__dl_batch_first(dl, b) == k)
                limen__dl_batch_draw(dl, v, b++);
            continue;
        }
        if (k == 0 && first_free)
            dl->st.depth_test = LIMEN_COMPARE_ALWAYS;
        draw_thing(dl, v, i);
        if (k == 0 && first_free)
            dl->st.depth_test = limen__dl_less(dl);
    }
    draw_clones(dl, v, false);
}

/* View v's meshes' blended parts, farthest first, over what it drew (both methods call it
 * once a view's picture, its surfaces' included, is complete). */
void limen__dl_blended(limen_drawlist *dl, const dl_view *v)
{
    if (!dl->blends)
        return;
    int n = view_order(dl, v);
    dl->st.blend = 1;
    dl->st.depth_write = 0;
    dl->blend_pass = true;
    dl->st.counted = 1;
    for (int k = n - 1; k >= 0; k--) {
        int i = dl->order[k].node;
        const limen_drawable *d = &dl->items[i];
        if (d->kind == LIMEN_NODE_MESH && d->mesh && d->mesh->has_blend)
            draw_thing(dl, v, i);
    }
    draw_clones(dl, v, true);
    dl->st.counted = 0;
    dl->blend_pass = false;
    dl->st.depth_write = 1;
    dl->st.blend = 0;
}

/* The previous frame's picture of a surface where recursion stops: the rectangle of the
 * shallowest view through it, stretched onto the surface's rectangle here. False where there
 * is no such picture. */
static bool draw_previous(limen_drawlist *dl, const dl_view *v, const limen_view_surface *vs,
                          const limen_drawable *n)
{
    if (dl->desc.fill != LIMEN_FILL_PREVIOUS || !dl->desc.have_previous)
        return false;
    const limen_view *best = NULL;
    for (int i = 1; i < limen_plan_count(dl->plan); i++) {
        const limen_view *u = limen_plan_view(dl->plan, i);
        if (u->through.id == vs->node.id && (!best || u->depth < best->depth))
            best = u;
    }
    if (!best)
        return false;
    const int *rt = vs->rect, *r1 = best->scissor;
    float kx = (float)r1[2] / (float)rt[2], ky = (float)r1[3] / (float)rt[3];
    float W = (float)dl->width, H = (float)dl->height;
    float map[4] = {
        v->img_map[0] * kx / W,
        v->img_map[1] * ky / H,
        ((v->img_map[2] - (float)rt[0]) * kx + (float)r1[0]) / W,
        ((v->img_map[3] - (float)rt[1]) * ky + (float)r1[1]) / H,
    };
    limen__dl_surface_image(dl, v, n, v->pub->tint, LIMEN_IMAGE_PREVIOUS, map, 0);
    return true;
}

/* The surfaces a view sees that end there: a mirror's back, or a fill where recursion
 * stopped. */
static void draw_terminal_surface(limen_drawlist *dl, const dl_view *v,
                                  const limen_view_surface *vs)
{
    const limen_drawable *n = item_of(dl, vs->node);
    if (!n)
        return;
    if (vs->state == LIMEN_SURFACE_BACK)
        thing_lit(dl, v, n, n->back);
    else if (vs->state == LIMEN_SURFACE_FILL && !draw_previous(dl, v, vs, n))
        limen__dl_surface_fill(dl, v, n, n->fill, NULL);
}

/* The view's opaque things: the surfaces that end here (flat, cheap to shade twice), then
 * the geometry. */
void limen__dl_opaque(limen_drawlist *dl, const dl_view *v, const limen_view_surface *vs, int n)
{
    for (int k = 0; k < n; k++)
        if (vs[k].state != LIMEN_SURFACE_RECURSE)
            draw_terminal_surface(dl, v, &vs[k]);
    draw_geometry(dl, v, n == 0);
}

/* The drawable of a surface that a view recurses into; NULL for the others. */
const limen_drawable *limen__dl_recursed(const limen_drawlist *dl, const limen_view_surface *vs)
{
    return vs->state == LIMEN_SURFACE_RECURSE ? item_of(dl, vs->node) : NULL;
}

/* ------------------------------------------------------------------ building */

static void find_clones(limen_drawlist *dl)
{
    for (int i = 0; i < dl->nitems; i++)
        dl->clone_of[i] = -1;
    for (int c = 0; c < dl->nclones; c++) {
        int i = limen_drawables_find(dl->d, dl->clones[c].node);
        if (i >= 0)
            dl->clone_of[i] = c;
    }
}

/* The lights that shade: the first visible LIGHT items. */
static void find_lights(limen_drawlist *dl)
{
    dl->nlights = 0;
    for (int i = 0; i < dl->nitems && dl->nlights < LIMEN_MAX_LIGHTS; i++) {
        const limen_drawable *d = &dl->items[i];
        if (!kind_of(d)->light || !d->visible)
            continue;
        limen_draw_light *l = &dl->lights[dl->nlights++];
        *l = (limen_draw_light){ .zero = 0 };
        memcpy(l->pos, d->world + 12, sizeof l->pos);
        memcpy(l->color, d->color, sizeof l->color);
        /* 1/R^2: the shader's falloff takes (d/R)^2 as d^2 times it; 0 weighs 1 */
        l->inv_range2 = d->range > 0 ? 1.0f / (d->range * d->range) : 0.0f;
    }
}

static bool scene_blends(const limen_drawlist *dl)
{
    for (int i = 0; i < dl->nitems; i++)
        if (dl->items[i].visible && dl->items[i].kind == LIMEN_NODE_MESH && dl->items[i].mesh &&
            dl->items[i].mesh->has_blend)
            return true;
    return false;
}

limen_status limen_drawlist_build(limen_drawlist *dl, const limen_plan *p, const limen_drawables *d,
                                  const limen_drawlist_desc *desc)
{
    if (!dl)
        return LIMEN_ERR_ARG;
    dl->err[0] = '\0';
    dl->ncmd = dl->npass = dl->nvert = dl->ninst = 0;
    if (!p || limen_plan_count(p) < 1)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: %s", p ? "the plan was not built"
                                                              : "no plan");
    if (!d)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: no drawables");
    limen_drawlist_desc in = desc ? *desc : (limen_drawlist_desc){ 0 };
    if ((unsigned)in.method > LIMEN_METHOD_NAIVE)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: unknown method %d", (int)in.method);
    if ((unsigned)in.fill > LIMEN_FILL_PREVIOUS)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: unknown fill %d", (int)in.fill);
    if ((unsigned)in.range > LIMEN_DEPTH_ZO_REVERSED)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: unknown depth range %d", (int)in.range);
    if (in.width < 0 || in.height < 0)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: size %dx%d", in.width, in.height);
    if (in.width == 0 || in.height == 0)
        in.width = p->width, in.height = p->height;
    /* the plan's scissors and projections are for its own image and range */
    if (in.width != p->width || in.height != p->height)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: a %dx%d frame of a plan for %dx%d",
                       in.width, in.height, p->width, p->height);
    if (in.range != p->range)
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: depth range %d, but the plan's is %d",
                       (int)in.range, (int)p->range);
    dl->desc = limen_drawlist_desc_defaults(&in);
    dl->desc.limits.lod_pixels = in.limits.lod_pixels;   /* as limen_view_mesh_lod reads it */
    if (!(dl->desc.texture_scale > 0 && dl->desc.texture_scale <= 1))
        return dl_fail(dl, LIMEN_ERR_ARG, "draw list: texture scale must be in (0, 1] (got %g)",
                       dl->desc.texture_scale);
    dl->plan = p;
    dl->d = d;
    dl->width = dl->desc.width;
    dl->height = dl->desc.height;
    dl->range = dl->desc.range;
    dl->nitems = limen_drawables_items(d, &dl->items);
    dl->nclones = limen_plan_clones(p, &dl->clones);
    dl->nomem = false;
    dl->blend_pass = false;
    if (!limen__reserve((void **)&dl->clone_of, &dl->clone_cap, dl->nitems, sizeof *dl->clone_of))
        return dl_fail(dl, LIMEN_ERR_NOMEM, "draw list: out of memory");
    find_clones(dl);
    limen_drawables_environment(d, dl->background, &dl->ambient);
    find_lights(dl);
    dl->blends = scene_blends(dl);
    dl->tris_left = (uint64_t)dl->desc.limits.budget.triangles;

    /* the state of a frame's start: the whole frame, writing colour and depth, nearer wins */
    memset(&dl->st, 0, sizeof dl->st);
    dl->st.scissor[2] = dl->width, dl->st.scissor[3] = dl->height;
    dl->st.color_write = dl->st.depth_write = 1;
    dl->st.stencil_write_mask = 0xFF;
    dl->st.depth_test = limen__dl_less(dl);
    memcpy(dl->st.clip, keep_all, sizeof keep_all);
    memcpy(dl->st.cut, keep_all, sizeof keep_all);
    dl->cur_pass = 0;
    limen_draw_cmd *c = limen__dl_emit(dl, LIMEN_DRAW_CLEAR);
    if (c)
        memcpy(c->color, dl->background, sizeof c->color);

    if (dl->desc.method == LIMEN_METHOD_STENCIL) {
        limen__dl_stencil(dl);
    } else {
        limen__dl_texture(dl);
    }
    if (dl->nomem)
        return dl_fail(dl, LIMEN_ERR_NOMEM, "draw list: out of memory");
    return LIMEN_OK;
}
