/*
 * limen.h - portal-and-mirror scene graph with a headless OpenGL renderer.
 *
 * USAGE, STEP BY STEP
 *
 *   1. Create a scene (zero in a desc field means "default"):
 *          limen_scene *s;
 *          limen_scene_create(&(limen_scene_desc){0}, &s);
 *   2. Add nodes and set their properties; every call returns LIMEN_OK (0) or
 *      an error code, with a readable message in limen_scene_error(s):
 *          limen_node ball;
 *          limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball);
 *          limen_node_set_position(s, ball, (float[3]){0, 1, 0});
 *          limen_node_set_dims(s, ball, (float[3]){0.5f, 0, 0});   // radius
 *      Or load a Lua scene script (limen_script_load, below) that does the same.
 *   3. Create a renderer (OSMesa by default, EGL surfaceless on request, or the
 *      game's own context: LIMEN_BACKEND_HOST, below) and render frames; read the
 *      pixels or write a PNG:
 *          limen_renderer *r;
 *          limen_renderer_create(&(limen_renderer_desc){.width = 640,
 *                                .height = 480}, &r);
 *          limen_render_frame(r, s, NULL, NULL);
 *          limen_renderer_write_png(r, "out.png");
 *   4. limen_renderer_destroy(r); limen_scene_destroy(s);
 *
 * CONVENTIONS
 *   - Right-handed world, +Y up. A camera looks down its local -Z with +Y up.
 *   - Matrices are float[16], column-major, column vectors: v' = M v
 *     (element (row i, column j) is m[j*4 + i]), as in OpenGL and cglm.
 *   - A plane is float[4] (n.x, n.y, n.z, d) with |n| = 1 and n.p + d = 0 on
 *     it; n.p + d > 0 is its front. Planes transform as (M^-1)^T C.
 *   - Angles are radians in this API (degrees only in Lua scene scripts).
 *   - Colours are linear RGB in [0, 1]; no gamma anywhere.
 *   - Shading of every surface (renderer and ray tracer alike):
 *        colour = albedo * (ambient + (1 - ambient) * sum_i light_i * w_i * max(0, n.l_i))
 *     with point lights and no shadows, clamped to [0, 1]. w_i = 1 for a light without a
 *     range (the default: no attenuation); for one of range R at distance d,
 *        w_i = clamp(1 - (d/R)^4, 0, 1)^2
 *     which starts at 1, falls smoothly and reaches 0 (with zero slope) at d = R.
 *     albedo is the node's colour (or checker colour), times its texture's texel where it
 *     has one (see limen_node_set_texture); on a mesh, times its part's material too:
 *        albedo = base colour x base texel x vertex colour x the node's colour
 *     and a material's emissive colour is added after the clamp, the sum clamped again
 *     (see limen_material: alpha masks and blending there too).
 *   - Mirrors, portals and quads lie on their local z = 0, face local +Z,
 *     local +Y up, extent w x h centred on the origin.
 *
 * The library never prints and never exits. It keeps no global state: each
 * scene, renderer and script carries its own error message (limen_scene_error,
 * limen_renderer_error, limen_script_error).
 *
 * THREADS
 *   A scene belongs to one thread at a time: a call that takes a (non-const) limen_scene *
 *   (an edit, but also planning, tracing, ray casts and rendering, which refresh its world
 *   matrices and may set its message) must not overlap any other call on that scene.
 *   Calls that take a const limen_scene * only read it (they never write, not even the
 *   error message), so any number of threads may make them at once while no other call
 *   runs. Different scenes, renderers and scripts are independent.
 *
 * NAMES: limen_<subject>_<verb>. A property that has a setter is read by
 * limen_<subject>_get_<property>; a derived value by its noun (limen_node_world_matrix).
 * Old names kept for one release are at the end of this file, marked deprecated.
 */
#ifndef LIMEN_H
#define LIMEN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define LIMEN_API __attribute__((visibility("default")))
#else
#define LIMEN_API
#endif

/* ---------------------------------------------------------------- version */

/* The version, written here alone: the Makefile reads these three lines for the shared
 * library's file name and soname (liblimen.so.MAJOR), the pkg-config file, the CMake
 * package (find_package(limen X.Y)) and the LuaRocks rockspec (make rockspec). */
#define LIMEN_VERSION_MAJOR 0
#define LIMEN_VERSION_MINOR 1
#define LIMEN_VERSION_PATCH 0
/* One number that grows with every release: MAJOR * 10000 + MINOR * 100 + PATCH (0.1.0 ->
 * 100), for #if LIMEN_VERSION_NUMBER >= 100. */
#define LIMEN_VERSION_NUMBER \
    (LIMEN_VERSION_MAJOR * 10000 + LIMEN_VERSION_MINOR * 100 + LIMEN_VERSION_PATCH)
#define LIMEN__STR(x) #x                                         /* (internal) */
#define LIMEN__XSTR(x) LIMEN__STR(x)                             /* (internal) */
/* "MAJOR.MINOR.PATCH" of the header: "0.1.0". */
#define LIMEN_VERSION                                                                      \
    LIMEN__XSTR(LIMEN_VERSION_MAJOR) "." LIMEN__XSTR(LIMEN_VERSION_MINOR) "."              \
    LIMEN__XSTR(LIMEN_VERSION_PATCH)

/* The version of the library linked in, which may differ from the header's LIMEN_VERSION
 * when a program runs against a newer shared library: "0.1.0". */
LIMEN_API const char *limen_version(void);
/* The same as LIMEN_VERSION_NUMBER counts it, for the library linked in. */
LIMEN_API int limen_version_number(void);

/* ---------------------------------------------------------------- errors */

typedef enum limen_status {
    LIMEN_OK = 0,
    LIMEN_ERR_ARG,          /* invalid argument: NULL, NaN/Inf, negative size, unknown kind */
    LIMEN_ERR_DEGENERATE,   /* cannot be formed: collinear points, zero normal, eye on plane */
    LIMEN_ERR_NOMEM,        /* out of memory or out of node slots */
    LIMEN_ERR_HANDLE,       /* node handle is stale, null or of the wrong kind */
    LIMEN_ERR_CYCLE,        /* parent chain would form a cycle */
    LIMEN_ERR_SCRIPT,       /* a Lua scene script failed */
    LIMEN_ERR_GL,           /* no OpenGL context, or OpenGL reported a failure */
    LIMEN_ERR_IO,           /* a file could not be read or written */
    LIMEN_ERR_UNSUPPORTED,  /* the backend or the context lacks a feature */
    LIMEN_STATUS_COUNT      /* the number of statuses (not one itself) */
} limen_status;

LIMEN_API const char *limen_status_string(limen_status st);    /* "invalid argument", ... */

/* ---------------------------------------------------------------- maths */

typedef enum limen_depth_range {
    LIMEN_DEPTH_NO = 0,     /* OpenGL: z/w in [-1, 1], near at -1 */
    LIMEN_DEPTH_ZO,         /* Direct3D, Vulkan: z/w in [0, 1], near at 0 */
    LIMEN_DEPTH_ZO_REVERSED,/* near at 1, far at 0; pair with a float depth buffer */
    LIMEN_DEPTH_RANGE_COUNT /* the number of conventions (not one itself) */
} limen_depth_range;

/* Plane through a, b, c; front side is where (b-a)x(c-a) points. Collinear -> DEGENERATE. */
LIMEN_API limen_status limen_plane_from_points(const float a[3], const float b[3],
                                               const float c[3], float plane[4]);
/* Plane through p with normal n (any length > 0; normalised). Zero n -> DEGENERATE. */
LIMEN_API limen_status limen_plane_from_point_normal(const float p[3], const float n[3],
                                                     float plane[4]);
/* plane' = (M^-1)^T plane, renormalised so |n'| = 1. Singular M -> DEGENERATE. */
LIMEN_API limen_status limen_plane_transform(const float m[16], const float plane[4],
                                             float out[4]);
/* Reflection about a plane: I - 2 n n^T with translation -2 d n. det = -1. Zero n ->
 * DEGENERATE (the plane need not be normalised). */
LIMEN_API limen_status limen_mirror_matrix(const float plane[4], float m[16]);
/* Portal A -> B: W_B * R_y(180 deg) * W_A^-1. Carries what enters A's front out of B's front. */
LIMEN_API limen_status limen_portal_matrix(const float world_a[16], const float world_b[16],
                                           float m[16]);
/* View matrix of an eye looking at center. eye == center or up parallel -> DEGENERATE. */
LIMEN_API limen_status limen_look_at(const float eye[3], const float center[3],
                                     const float up[3], float view[16]);
/* Perspective projection; fovy in radians (vertical). fovy outside (0, pi), aspect <= 0,
 * near <= 0 or far <= near -> ARG. */
LIMEN_API limen_status limen_perspective(float fovy, float aspect, float znear, float zfar,
                                         limen_depth_range range, float proj[16]);
/* Oblique near-plane projection (Lengyel): replaces proj's near plane by clip_view, a plane
 * in view space whose front is what stays visible. With the plane normalised (|n| = 1),
 * clip_view[3] is minus the eye's distance in front of it; it must be below
 * -1e-6 * (near distance), and some of the frustum must lie in front of the plane: otherwise
 * DEGENERATE and out is left unchanged. NaN/Inf or NULL -> ARG. */
LIMEN_API limen_status limen_oblique_projection(const float proj[16], const float clip_view[4],
                                                limen_depth_range range, float out[16]);
/* Near and far planes of a projection's frustum (Gribb-Hartmann), in view space, normalised,
 * facing the inside of the frustum. NULL outputs -> ARG. */
LIMEN_API limen_status limen_projection_planes(const float proj[16], limen_depth_range range,
                                               float near_plane[4], float far_plane[4]);

/* Keeps the part of a convex polygon where plane . p >= 0 (Sutherland-Hodgman, in double):
 * in and out hold n and cap homogeneous points (x, y, z, w), 4 doubles each, and must not
 * overlap; plane is any 4-vector (a world plane for world points, a clip-space one such as
 * (-1, 0, 0, 1) for clip-space points). Returns the points written, at most cap (n + 1 are
 * enough): fewer than 3 means nothing is left. n < 3, cap < 1 or NULL -> 0. */
LIMEN_API int limen_clip_polygon(const double *in, int n, const double plane[4], double *out,
                                 int cap);

/* ---------------------------------------------------------------- scene */

/* NUMBERS. Every setter checks its numbers, and the Lua bindings pass scripts' values
 * through the same setters, so C and Lua accept the same scenes: coordinates (positions,
 * directions, local matrix elements, displacements) from -LIMEN_MAX_MAGNITUDE to
 * LIMEN_MAX_MAGNITUDE; sizes, scales, near and far distances and checker cells from
 * LIMEN_MIN_SIZE to LIMEN_MAX_MAGNITUDE, positive (a scale of -1, or a local matrix with a
 * negative determinant, would mirror the node and turn its faces inside out); light
 * intensities up to LIMEN_MAX_MAGNITUDE. A float holds up to 3.4e38 and the maths multiplies
 * four such numbers, so within these bounds it stays finite. Out of range -> LIMEN_ERR_ARG.
 * What parents compose is checked where a scene is planned, traced or cast into: a camera,
 * mirror or portal whose world scale (the product along its parent chain) leaves
 * [LIMEN_MIN_SIZE, LIMEN_MAX_MAGNITUDE] is refused by all three with one message. */
#define LIMEN_MAX_MAGNITUDE 1e9f
#define LIMEN_MIN_SIZE 1e-9f

typedef struct limen_scene limen_scene;

/* A node handle: slot index (low 32 bits, plus one) and the slot's generation (high 32
 * bits). A handle to a destroyed node is refused with LIMEN_ERR_HANDLE, for good: freed
 * slots are reused first freed, first reused, and a slot whose generation would wrap is
 * retired, so no later node ever gets an old handle. The zero handle means "no node".
 * ABI change: 64 bits (it was 32, with a 12-bit generation that came round again). */
typedef struct limen_node { uint64_t id; } limen_node;

typedef enum limen_node_kind {
    LIMEN_NODE_GROUP = 0,   /* transform only */
    LIMEN_NODE_BOX,         /* dims = (size x, size y, size z), centred on the origin */
    LIMEN_NODE_SPHERE,      /* dims = (radius, -, -), centred on the origin */
    LIMEN_NODE_CYLINDER,    /* dims = (radius, height, -), axis +Y from y = 0 to y = height, capped */
    LIMEN_NODE_QUAD,        /* dims = (w, h, -) on local z = 0, facing +Z, one-sided lighting */
    LIMEN_NODE_MIRROR,      /* dims = (w, h, -) like a quad */
    LIMEN_NODE_PORTAL,      /* dims = (w, h, -) like a quad; paired with another portal */
    LIMEN_NODE_LIGHT,       /* point light at the node's origin; colour = intensity per channel */
    LIMEN_NODE_CAMERA,      /* eye at the origin, looking down local -Z */
    LIMEN_NODE_MESH,        /* triangles in the node's local frame (limen_mesh_load, below) */
    LIMEN_NODE_KIND_COUNT
} limen_node_kind;

/* ---------------------------------------------------------------- node kinds */

/* Where a kind's texture coordinates come from (limen_node_set_texture says how each maps). */
typedef enum limen_uv_rule {
    LIMEN_UV_NONE = 0,          /* takes no texture (limen_node_set_texture refuses it) */
    LIMEN_UV_PLANE,             /* a plane's: (x/w + 0.5, y/h + 0.5) over its extent */
    LIMEN_UV_BOX,               /* a box face's: its two other axes in order */
    LIMEN_UV_MESH,              /* the mesh's own */
    LIMEN_UV_COUNT              /* the number of rules (not one itself) */
} limen_uv_rule;

/* The unit shapes that kinds draw as, scaled by their dims (limen_kind_info.unit). */
typedef enum limen_unit_shape {
    LIMEN_UNIT_NONE = 0,        /* none: draws nothing, or its own triangles (MESH) */
    LIMEN_UNIT_BOX,             /* [-0.5, 0.5]^3 */
    LIMEN_UNIT_BALL,            /* radius 1 about the origin */
    LIMEN_UNIT_CYLINDER,        /* radius 1 about +Y, from y = 0 to y = 1, capped */
    LIMEN_UNIT_SQUARE,          /* [-0.5, 0.5]^2 on z = 0, facing +Z */
    LIMEN_UNIT_COUNT            /* the number of unit shapes (not one itself) */
} limen_unit_shape;

/* What every layer knows of a node kind, from one table (core, renderer, tracer, bindings;
 * a game's own renderer may read it too). A kind that draws as a unit shape (unit) is that
 * shape, whose local box is [lo, hi], with local axis a stretched by dims[scale[a]] (by 1
 * where scale[a] < 0): a SPHERE is the ball of radius 1 scaled by (r, r, r), a CYLINDER the
 * one of radius 1 and height 1 on y = 0..1 scaled by (r, h, r), a QUAD the square
 * [-0.5, 0.5]^2 on z = 0 scaled by (w, h, 1). */
typedef struct limen_kind_info {
    const char *name;           /* "box": as Lua and messages spell it ("plane" for a QUAD) */
    int size;                   /* how many of dims it reads (limen_node_set_dims); 0: none */
    float dims[3];              /* the dims limen_node_create gives it */
    int shape;                  /* 1: shows a lit surface: BOX, SPHERE, CYLINDER, QUAD, MESH */
    int surface;                /* 1: a mirror or portal (limen_surface_get) */
    int light;                  /* 1: lights the scene (LIGHT) */
    limen_unit_shape unit;      /* the unit shape it draws as, scaled by dims; NONE: not one */
    int flat;                   /* 1: on local z = 0, facing +Z; passes no portal; a flat shape's
                                 * checker is in xy (limen_node_set_checker) */
    int closed;                 /* 1: a solid: back faces hidden (BOX, SPHERE, CYLINDER) */
    int round;                  /* bounding sphere about its box's centre: 0 through the box's
                                 * corners, 1 round about local axis `axis`, 2 a ball */
    int axis;                   /* round == 1: 0, 1, 2 for x, y, z (a circle across the others) */
    limen_uv_rule uv;           /* its texture coordinates; LIMEN_UV_NONE: takes no texture */
    int scale[3];               /* unit shapes: the dims index that stretches each local axis */
    float lo[3], hi[3];         /* unit shapes: the unit shape's local box */
} limen_kind_info;

LIMEN_API const limen_kind_info *limen_kind_get(limen_node_kind k);    /* NULL out of range */
/* The local box (lo, hi) of a unit shape of kind k and the given dims (as limen_node_get_dims
 * gives them): what limen_node_get_bounds carries through the world matrix. LIMEN_ERR_ARG
 * for a kind that is no unit shape (GROUP, LIGHT, CAMERA; a MESH's box is its triangles',
 * limen_mesh_info.lo and hi) and for NULL arguments. */
LIMEN_API limen_status limen_kind_bounds(limen_node_kind k, const float dims[3], float lo[3],
                                         float hi[3]);

typedef struct limen_scene_desc {
    int max_nodes;          /* live nodes at most; 0 -> no limit but memory (the pool grows) */
} limen_scene_desc;

LIMEN_API limen_status limen_scene_create(const limen_scene_desc *desc, limen_scene **out);
LIMEN_API void limen_scene_destroy(limen_scene *s);                    /* NULL is fine */
/* The message of the last failed call that takes a (non-const) limen_scene *; "" when none.
 * Calls taking a const limen_scene * only read: a bad handle is their status or return
 * value, and they leave this message as it was. */
LIMEN_API const char *limen_scene_error(const limen_scene *s);
LIMEN_API limen_status limen_scene_set_background(limen_scene *s, const float rgb[3]);
LIMEN_API limen_status limen_scene_set_ambient(limen_scene *s, float ambient); /* [0, 1] */
LIMEN_API void limen_scene_get_background(const limen_scene *s, float rgb[3]);
LIMEN_API float limen_scene_get_ambient(const limen_scene *s);
LIMEN_API limen_status limen_scene_set_camera(limen_scene *s, limen_node camera);
LIMEN_API limen_node limen_scene_get_camera(const limen_scene *s);    /* zero handle if none */
LIMEN_API int limen_scene_node_count(const limen_scene *s);            /* live nodes */
/* Fills out[0..max) with the live nodes in creation order (the order lights and shapes are
 * drawn in); returns how many there are (which may exceed max). Costs the live count, not
 * the pool's size. */
LIMEN_API int limen_scene_nodes(const limen_scene *s, limen_node *out, int max);
/* The files the scene's meshes and textures were read from (resolved paths), for a host
 * that watches them: `limen view` reloads the script when one changes. Copies the
 * i-th (from 0) into path and returns LIMEN_OK; LIMEN_ERR_ARG past the last, or where it does
 * not fit in size bytes. Only reads the scene. */
LIMEN_API limen_status limen_scene_get_file(const limen_scene *s, int i, char *path,
                                            size_t size);
/* Recompute world matrices now (done implicitly by every call that needs them). */
LIMEN_API limen_status limen_scene_update(limen_scene *s);

/* Nodes. Defaults: at the origin, unrotated, unit scale, white, visible, no parent. */
LIMEN_API limen_status limen_node_create(limen_scene *s, limen_node_kind kind,
                                         const char *name, limen_node *out);
/* Destroys the node; its children are re-parented to its parent. */
LIMEN_API limen_status limen_node_destroy(limen_scene *s, limen_node n);
LIMEN_API int limen_node_valid(const limen_scene *s, limen_node n);   /* 1 if live */
LIMEN_API limen_status limen_node_find(const limen_scene *s, const char *name, limen_node *out);
LIMEN_API const char *limen_node_get_name(const limen_scene *s, limen_node n); /* NULL if stale */
LIMEN_API limen_node_kind limen_node_get_kind(const limen_scene *s, limen_node n);
/* Where the node was made (for example "scenes/hall.lua:12"); used in later messages. */
LIMEN_API limen_status limen_node_set_label(limen_scene *s, limen_node n, const char *label);

/* Hierarchy: world = parent_world * local. A zero parent detaches. Cycles are refused. */
LIMEN_API limen_status limen_node_set_parent(limen_scene *s, limen_node n, limen_node parent);
LIMEN_API limen_node limen_node_get_parent(const limen_scene *s, limen_node n);

/* Local transform: local = T(position) * R(rotation) * F(facing) * S(scale), where R rotates
 * about X first, then Y, then Z (R = Rz * Ry * Rx), and F turns local +Z to `normal` and
 * local +Y towards `up`. A local matrix set directly replaces all four until the next
 * call of one of these setters. */
LIMEN_API limen_status limen_node_set_position(limen_scene *s, limen_node n, const float p[3]);
LIMEN_API limen_status limen_node_set_rotation(limen_scene *s, limen_node n, const float xyz[3]);
/* up may be NULL: +Y, or -Z when the normal is (anti)parallel to Y. */
LIMEN_API limen_status limen_node_set_facing(limen_scene *s, limen_node n, const float normal[3],
                                             const float up[3]);
LIMEN_API limen_status limen_node_set_scale(limen_scene *s, limen_node n, const float xyz[3]);
LIMEN_API limen_status limen_node_set_local_matrix(limen_scene *s, limen_node n, const float m[16]);
/* Places the node at eye and turns its -Z towards target (cameras, lights). */
LIMEN_API limen_status limen_node_look_at(limen_scene *s, limen_node n, const float eye[3],
                                          const float target[3], const float up[3]);
LIMEN_API limen_status limen_node_get_position(const limen_scene *s, limen_node n, float p[3]);
LIMEN_API limen_status limen_node_get_rotation(const limen_scene *s, limen_node n, float xyz[3]);
LIMEN_API limen_status limen_node_get_scale(const limen_scene *s, limen_node n, float xyz[3]);
LIMEN_API limen_status limen_node_get_local_matrix(limen_scene *s, limen_node n, float m[16]);
LIMEN_API limen_status limen_node_world_matrix(limen_scene *s, limen_node n, float m[16]);

/* Appearance and shape. */
LIMEN_API limen_status limen_node_set_dims(limen_scene *s, limen_node n, const float dims[3]);
LIMEN_API limen_status limen_node_get_dims(const limen_scene *s, limen_node n, float dims[3]);
/* Albedo of shapes; colour (intensity) of a light. Components >= 0, <= 1 for albedo. */
LIMEN_API limen_status limen_node_set_color(limen_scene *s, limen_node n, const float rgb[3]);
LIMEN_API limen_status limen_node_get_color(const limen_scene *s, limen_node n, float rgb[3]);
/* Checker pattern in the node's local xy (quads) or xyz (other shapes): cells of size
 * `cell`, colour a where floor(x/cell)+floor(y/cell) is even, b where odd. cell 0 turns it off. */
LIMEN_API limen_status limen_node_set_checker(limen_scene *s, limen_node n, const float a[3],
                                              const float b[3], float cell);
/* cell is 0 when the node has no checker (then a is its colour). */
LIMEN_API limen_status limen_node_get_checker(const limen_scene *s, limen_node n, float a[3],
                                              float b[3], float *cell);
LIMEN_API limen_status limen_node_set_visible(limen_scene *s, limen_node n, int visible);
/* A light's range R (see CONVENTIONS): beyond it the light adds nothing. 0 = no range. */
LIMEN_API limen_status limen_light_set_range(limen_scene *s, limen_node light, float range);
LIMEN_API float limen_light_get_range(const limen_scene *s, limen_node light); /* 0 if none */
LIMEN_API int limen_node_get_visible(const limen_scene *s, limen_node n);

/* Materials: a mesh is made of parts (limen_mesh_part), each a range of its triangles in
 * one material. What is shaded (renderer and ray tracer alike):
 *     albedo = base_color x base texture's texel x vertex colour x the node's colour
 *     alpha  = base_color[3] x the texel's alpha x the vertex colour's alpha
 * the albedo lit as CONVENTIONS says, then the emissive colour (emissive x its texture's
 * texel) added and the sum clamped to [0, 1]. MASK: where alpha < alpha_cutoff nothing is
 * drawn (rays pass through). BLEND: colour = alpha x this + (1 - alpha) x what lies behind,
 * blended parts drawn after the opaque ones, farthest first. A node's texture (limen_node_set_
 * texture) replaces every part's base texture. The metallic, roughness, normal and occlusion
 * fields are read from the file and listed for a game's own renderer, not shaded. */
typedef enum limen_alpha_mode {
    LIMEN_ALPHA_OPAQUE = 0,     /* alpha ignored */
    LIMEN_ALPHA_MASK,           /* drawn where alpha >= alpha_cutoff */
    LIMEN_ALPHA_BLEND,          /* composited over what lies behind */
    LIMEN_ALPHA_COUNT           /* the number of modes (not one itself) */
} limen_alpha_mode;

struct limen_image;

typedef struct limen_material {
    const char *name;           /* the file's name for it, "" if none */
    float base_color[4];        /* linear RGBA factor (glTF baseColorFactor; MTL Kd, d) */
    const struct limen_image *base_texture;  /* or NULL (none, or not found: a warning) */
    int base_texcoord;          /* the file's texture-coordinate set for it (0 or 1), and */
    float base_transform[6];    /* its 2x3 transform (column-major: u' = t0 u + t2 v + t4,
                                 * v' = t1 u + t3 v + t5; KHR_texture_transform), both already
                                 * applied to limen_mesh_geometry.uvs: listed, not to reapply */
    limen_alpha_mode alpha_mode;
    float alpha_cutoff;         /* MASK: default 0.5 */
    float emissive[3];          /* linear RGB factor, added after shading */
    const struct limen_image *emissive_texture;  /* or NULL; sampled at the same uvs */
    int double_sided;           /* the file's flag (limen lights both sides regardless) */
    const struct limen_image *metallic_roughness_texture;   /* listed, not shaded: */
    const struct limen_image *normal_texture;               /* ... NULL where none */
    const struct limen_image *occlusion_texture;
    float metallic, roughness, normal_scale, occlusion_strength;
} limen_material;

typedef struct limen_mesh_part {
    int first_triangle, triangle_count;     /* a range of the mesh's (or level's) triangles */
    int material;                           /* index into the mesh's materials */
} limen_mesh_part;

/* Meshes: triangles in the node's local frame, drawn with the node's transform and colour
 * (checker too: cells of the local point, x+y+z). A mesh node shows nothing until it has
 * triangles. Both sides are lit (the normal turned toward the eye, as for quads). Normals:
 * where the data has them they are interpolated across each triangle; without them each
 * triangle shows its face normal ((p1-p0) x (p2-p0), i.e. counter-clockwise from the front),
 * unless smooth is set, which interpolates area-weighted vertex normals. Nodes that load the
 * same file share one copy of it (per scene); each node keeps its own transform and colour.
 * Bad data (no triangles, a vertex that is not finite, an index out of range, points or lines,
 * a file that cannot be read) is refused with a message naming the file. */
typedef struct limen_mesh_data {
    const float *positions;     /* vertex_count * 3 */
    const float *normals;       /* vertex_count * 3, or NULL (face normals, or smooth) */
    const float *uvs;           /* vertex_count * 2, or NULL: texture coordinates */
    int vertex_count;
    const uint32_t *indices;    /* triangle_count * 3, each < vertex_count */
    int triangle_count;
    const float *colors;        /* vertex_count * 4 (linear RGBA vertex colours), or NULL */
    int part_count;             /* 0: one part of all the triangles in a white material */
    const limen_mesh_part *parts;   /* part_count ranges covering every triangle once */
    int material_count;         /* materials the parts index; their textures are ignored */
    const limen_material *materials;    /* (name, colours, alpha and emissive are taken) */
} limen_mesh_data;

typedef struct limen_mesh_info {
    int vertex_count, triangle_count;
    int has_normals, has_uvs;   /* what the data came with */
    int smooth;                 /* the node's flag */
    float lo[3], hi[3];         /* local bounding box */
    int shared_by;              /* nodes that show this geometry */
    int lod_count;              /* levels of detail (limen_mesh_geometry.lods), >= 1 */
    size_t bytes;               /* memory it holds */
} limen_mesh_info;

/* Textures on planes (QUAD), boxes and meshes: albedo = texel * colour (the checker's
 * colours where it has one). A PNG or JPEG file, its bytes taken as linear RGB (no gamma,
 * like every colour here); one copy per scene however many nodes use the file. Sampling,
 * the same in the renderer and the ray tracer: as limen_node_set_texture_filter says
 * (trilinear over mipmap levels by default), repeating (u and v wrap); texel (i, j) of a
 * level width x height has its centre at ((i + 0.5) / width,
 * (j + 0.5) / height), j counting rows from the image's bottom (v = 0) up (v = 1). Texture
 * coordinates: a plane's (x/w + 0.5, y/h + 0.5) over its extent; a box face's two other
 * axes in order (face x: (y, z), face y: (z, x), face z: (x, y)), each mapped from
 * [-size/2, size/2] to [0, 1]; a mesh's own (with none, (0, 0)). A mesh file's base-colour
 * texture (glTF, or map_Kd in an OBJ's MTL; embedded or beside the file) is used unless the
 * node has one of its own. path NULL removes the node's texture. */
LIMEN_API limen_status limen_node_set_texture(limen_scene *s, limen_node n, const char *path);
/* Tiling: the node's texture coordinates (a plane's, a box face's or a mesh's own, as above)
 * are multiplied by repeat = (u, v) before sampling, so that a plane or box face shows the
 * image u times across and v times up (and a mesh's coordinates are scaled alike); each a
 * positive number from 1e-9 to 1e9. Default (1, 1). Any node may carry it; it shows where
 * the node has a texture. */
LIMEN_API limen_status limen_node_set_texture_repeat(limen_scene *s, limen_node n,
                                                     const float repeat[2]);
LIMEN_API limen_status limen_node_get_texture_repeat(const limen_scene *s, limen_node n,
                                                     float repeat[2]);

/* Texture filtering: how a node's texture is sampled, the same in the renderer and the ray
 * tracer. Every image gets mipmap levels when it is read: each level half the one above
 * (width and height divided by 2, rounded down, at least 1) down to 1 x 1, each texel the
 * box-filtered (area-weighted) average of the texels above it, rounded to 8 bits
 * (limen_image.levels). The level of detail of a pixel is lambda = log2(rho), rho the longer
 * of the steps that the texture coordinates (times repeat, in texels of the full image) take
 * to the next pixel across and up: OpenGL's rule. The ray tracer finds those steps from each
 * pixel's ray differentials, carried through mirror reflections and portal transforms. */
typedef enum limen_texture_filter {
    LIMEN_FILTER_TRILINEAR = 0, /* default: lambda <= 0, bilinear in the full image; else
                                 * bilinear in levels floor(lambda) and the next, blended by
                                 * its fraction (GL_LINEAR_MIPMAP_LINEAR); past the last, it */
    LIMEN_FILTER_LINEAR,        /* bilinear between the four nearest texels of the full image */
    LIMEN_FILTER_NEAREST,       /* the full image's texel that holds the point (GL_NEAREST) */
    LIMEN_FILTER_COUNT          /* the number of filters (not one itself) */
} limen_texture_filter;
/* Any node may carry it; it shows where the node has a texture. Lua: filter = "trilinear",
 * "linear" or "nearest". */
LIMEN_API limen_status limen_node_set_texture_filter(limen_scene *s, limen_node n,
                                                     limen_texture_filter filter);
LIMEN_API limen_status limen_node_get_texture_filter(const limen_scene *s, limen_node n,
                                                     limen_texture_filter *filter);

/* Loads a file through assimp (OBJ, glTF 2.0 .gltf/.glb, PLY, FBX, STL, ...): polygons are
 * triangulated, the file's node transforms applied, all its meshes merged into one part per
 * material (limen_material). Its textures (PNG, JPEG, TGA, BMP, PSD, GIF, HDR clamped to
 * [0, 1], or held in the file: GLB, FBX) are read as the file names them; one absent there,
 * named by an absolute path or outside the file's folder is looked for by its base name
 * beside the file (any case), and one not found leaves its parts their colour: both with a
 * warning (limen_scene_warning), never a refusal. Points and lines are skipped with a
 * warning; a file left with no triangles is refused. Where the node already has a texture
 * (set before loading), the file's are not read. */
LIMEN_API limen_status limen_mesh_load(limen_scene *s, limen_node mesh, const char *path);
/* Copies triangles from arrays (the caller keeps its own). */
LIMEN_API limen_status limen_mesh_set_triangles(limen_scene *s, limen_node mesh,
                                                const limen_mesh_data *data);
LIMEN_API limen_status limen_mesh_set_smooth(limen_scene *s, limen_node mesh, int smooth);
/* Zeros before any triangles. A const reader: LIMEN_ERR_HANDLE for a handle that is not a
 * live mesh and LIMEN_ERR_ARG for a NULL out, without a message. */
LIMEN_API limen_status limen_mesh_get(const limen_scene *s, limen_node mesh,
                                      limen_mesh_info *out);

/* Warnings: what loading files noticed without refusing them (a texture missing or found
 * elsewhere, points and lines skipped), one line each, "file: warning: text", in order. */
LIMEN_API int limen_scene_warning_count(const limen_scene *s);     /* 0 for NULL */
LIMEN_API const char *limen_scene_warning(const limen_scene *s, int i); /* NULL out of range */
LIMEN_API void limen_scene_clear_warnings(limen_scene *s);         /* forgets them all */

/* Mirrors and portals ("surfaces"). Defaults: tint white, back mid-grey (0.5), fill black,
 * max_depth 8. A mirror seen from behind is a matte quad of its back colour; a portal seen
 * from behind is not drawn. Where recursion stops, a surface shows its fill colour. */
LIMEN_API limen_status limen_surface_set_tint(limen_scene *s, limen_node n, const float rgb[3]);
LIMEN_API limen_status limen_surface_set_back(limen_scene *s, limen_node n, const float rgb[3]);
LIMEN_API limen_status limen_surface_set_fill(limen_scene *s, limen_node n, const float rgb[3]);
LIMEN_API limen_status limen_surface_set_max_depth(limen_scene *s, limen_node n, int max_depth);
LIMEN_API limen_status limen_surface_get(const limen_scene *s, limen_node n, float tint[3],
                                         float back[3], float fill[3], int *max_depth);
                                         /* any output may be NULL */
/* Pairs two portals both ways (unpairing their old partners). A portal with itself, or two
 * ends whose width/height ratios differ by more than 0.1%, are refused: what enters A leaves
 * B scaled by width_B / width_A. An unpaired portal shows its fill colour. */
LIMEN_API limen_status limen_portal_link(limen_scene *s, limen_node a, limen_node b);
LIMEN_API limen_node limen_portal_get_partner(const limen_scene *s, limen_node portal);
/* The 4x4 matrix carrying points that enter surface n (at its front) to where they are seen:
 * the reflection for a mirror, W_B * S(k) * R_y(180) * W_A^-1 for a portal. */
LIMEN_API limen_status limen_surface_matrix(limen_scene *s, limen_node n, float m[16]);

/* Moving through portals. */
typedef struct limen_move_result {
    int crossed;                /* portals passed through during the move (0 if none) */
    limen_node portal;          /* the last portal entered (zero if none) */
    float matrix[16];           /* product of the portal matrices passed (identity if none):
                                 * carry velocities and other vectors with its 3x3 part */
} limen_move_result;

/* Moves node n by the world-space displacement d. Where the straight path of the node's
 * origin passes through a paired portal's rectangle from its front, the node comes out of the
 * partner: its world transform (position, orientation, scale) is carried by the portal
 * matrix and the rest of the displacement goes on from there (up to 8 portals in one move).
 * Passing beside a rectangle, or through a portal from behind, moves it plainly. out may be
 * NULL. */
LIMEN_API limen_status limen_node_move(limen_scene *s, limen_node n, const float d[3],
                                       limen_move_result *out);

/* Cameras: vertical fov in radians, near < far, both from LIMEN_MIN_SIZE to
 * LIMEN_MAX_MAGNITUDE. Defaults: 60 degrees, 0.05, 100. */
LIMEN_API limen_status limen_camera_set_lens(limen_scene *s, limen_node cam, float fovy,
                                             float znear, float zfar);
LIMEN_API limen_status limen_camera_get_lens(const limen_scene *s, limen_node cam, float *fovy,
                                             float *znear, float *zfar);
/* The scene camera's view and projection for an image of the given aspect ratio. */
LIMEN_API limen_status limen_camera_matrices(limen_scene *s, float aspect, limen_depth_range range,
                                             float view[16], float proj[16]);

/* ---------------------------------------------------------------- what to draw */

/* A renderer draws a frame from two public lists, the same for limen's own renderer and a
 * game's: the plan of the view tree (below) and the drawables, a snapshot of the nodes that
 * draw or light, read in one call per frame instead of a getter per field. Shapes are the
 * unit meshes of limen_node_kind scaled by dims; mirrors and portals are quads whose colours
 * follow limen_surface_get (the tints are already folded into limen_view.tint); lights shade
 * as CONVENTIONS says, the first LIMEN_MAX_LIGHTS visible ones in list order. The list grows
 * with the library (meshes and textures joined as a kind and fields; more may come): read
 * items through the pointer it gives, never allocate a limen_drawable. */
#define LIMEN_MAX_LIGHTS 8      /* lights that shade: the first visible LIGHT items */

/* A mesh's triangles as a renderer reads them (limen_drawable.mesh): shared by every node
 * that shows the same file, valid while one does. */
/* Levels of detail between runs and on another thread: the levels made are stored in the
 * user's cache folder ($LIMEN_CACHE_DIR, else $XDG_CACHE_HOME/limen, else ~/.cache/limen;
 * at most $LIMEN_CACHE_MB megabytes, 256 by default; LIMEN_CACHE=off stores and reads
 * none), keyed by the mesh's content, and read back when the same mesh is made again. A
 * mesh of 100,000 triangles or more whose levels are not stored has the full mesh as its
 * only level at first: its levels are made on a thread of limen's own, which reads only the
 * mesh, and appear at a later call that reads the scene's world (rendering, planning,
 * tracing, ray casts, limen_drawables_build, limen_scene_update), with a new
 * limen_mesh_geometry.id; a const call never sees them change. */
/* A level of detail of a mesh: a simplified triangle list over the same vertices (so the
 * same normals and texture coordinates), made once when the mesh is created (meshoptimizer),
 * each level about half the triangles of the one before. */
typedef struct limen_mesh_lod {
    const uint32_t *indices;    /* triangle_count * 3, into the mesh's vertices */
    int triangle_count;
    float error;                /* the largest distance between this level's surface and the
                                 * full mesh's, measured (not the simplifier's estimate), in the
                                 * mesh's local units; 0 for level 0 */
    const limen_mesh_part *parts;   /* the mesh's part_count parts as ranges of this level's
                                 * triangles (a level keeps each triangle in its part) */
    const struct limen_mesh_geometry *baked;  /* NULL, or this level with a texture of its
                                 * own: where a textured mesh's charts stop its levels, the
                                 * coarser ones are simplified by position alone and each
                                 * given its own vertices, texture coordinates and one
                                 * material whose base (and emissive) texture is baked from
                                 * the mesh's (the colour of the full surface nearest each
                                 * texel). Draw baked (its vertices, its lods[0], its parts
                                 * and materials) in place of indices: indices (the same
                                 * triangles over the mesh's vertices) show the mesh's texture
                                 * blended across its charts. error bounds where a point's
                                 * colour comes from too. Made for opaque meshes whose
                                 * materials have textures of their own (not a node's) */
} limen_mesh_lod;

typedef struct limen_mesh_geometry {
    uint64_t id;                /* unique in the process: key a GPU copy on it */
    int vertex_count, triangle_count;
    const float *positions;     /* vertex_count * 3, in the node's local frame */
    const float *normals;       /* vertex_count * 3: the data's own, else area-weighted */
    const float *uvs;           /* vertex_count * 2, or NULL */
    const uint32_t *indices;    /* triangle_count * 3 */
    int lod_count;              /* levels of detail, >= 1; lods[0] is the full mesh (indices) */
    const limen_mesh_lod *lods; /* coarser as k grows, errors growing */
    const float *colors;        /* vertex_count * 4 linear RGBA vertex colours, or NULL */
    int part_count;             /* >= 1; parts[p] ranges over indices (level 0) */
    const limen_mesh_part *parts;
    int material_count;         /* >= 1 */
    const limen_material *materials;
    int has_blend;              /* some part's material is LIMEN_ALPHA_BLEND */
} limen_mesh_geometry;

/* The triangles limen draws a unit shape with (limen_kind_info.unit; the local frame that
 * enum describes, before the kind's scale), for a backend of the draw list to upload once
 * and draw SHAPE commands from: positions and normals (the true shape's), counter-clockwise
 * from outside, one part and one white material, no colours; uvs by the rule of the kinds
 * drawn with it (limen_kind_info.uv: a box face's for BOX, a plane's for SQUARE; none for
 * the curved shapes, which take no texture). A BOX or SQUARE has one level; a BALL or CYLINDER 11, one per
 * tessellation limen_draw_cmd.segments names (level 0: 256 segments around, then 192, 128,
 * 96, 64, 48, 32, 24, 16, 12, 8), its vertices pushed out so that the true surface lies
 * halfway, lods[k].error the largest distance either way (radius 1). Made on the first call
 * for a shape (safe from any thread) and kept, unchanged, until the process ends; NULL for
 * NONE, an unknown value, or when out of memory. */
LIMEN_API const limen_mesh_geometry *limen_unit_geometry(limen_unit_shape shape);

/* One mipmap level of an image: 8-bit RGB, top row first. */
typedef struct limen_image_level {
    int width, height;
    const unsigned char *rgb;
} limen_image_level;

/* An image for a texture (limen_drawable.texture): 8-bit RGB, top row first, sampled as
 * limen_node_set_texture says; valid while a node uses it. */
typedef struct limen_image {
    uint64_t id;                /* unique in the process: key a GPU copy on it */
    int width, height;
    const unsigned char *rgb;
    const unsigned char *alpha; /* width * height alpha values (same order), or NULL: opaque;
                                 * an image with alpha has one level */
    int level_count;            /* mipmap levels (limen_node_set_texture_filter), down to */
    const limen_image_level *levels;  /* 1 x 1; levels[0] is the image itself */
} limen_image;

typedef struct limen_drawable {
    limen_node node;            /* the node */
    limen_node_kind kind;       /* BOX, SPHERE, CYLINDER, QUAD, MIRROR, PORTAL, LIGHT, MESH */
    int visible;                /* 0: hidden, draws and lights nothing (limen_node_get_visible) */
    float world[16];            /* world matrix; the unit mesh's scale (dims) is not in it */
    float dims[3];              /* as limen_node_set_dims */
    float color[3];             /* albedo (the checker's colour a); a light's intensity */
    float checker[3];           /* the checker's colour b */
    float cell;                 /* checker cell size; 0: plain colour */
    float centre[3];            /* world bounding sphere (its centre and radius): what a view */
    float radius;               /* culls against its frustum and sorts nearest first by */
    float tint[3];              /* mirrors and portals (else 0): tint, */
    float back[3];              /* the matte colour of a mirror's back, */
    float fill[3];              /* and the colour where recursion stops */
    const char *name;           /* the node's name, "" if none; points into the scene: */
    const char *label;          /* ... as does where it was made ("" if not known) */
    float range;                /* lights: limen_light_set_range (0: none) */
    const limen_mesh_geometry *mesh;  /* meshes: the triangles (NULL: none yet) */
    int smooth;                 /* meshes: 1 interpolates the vertex normals, 0 takes each
                                 * triangle's face normal (p1-p0) x (p2-p0) */
    const limen_image *texture; /* planes, boxes, meshes: the node's albedo texture, or NULL;
                                 * on a mesh it replaces every part's base texture (a mesh's
                                 * own are in mesh->materials) */
    float texture_repeat[2];    /* limen_node_set_texture_repeat: scales the texture
                                 * coordinates before sampling */
    limen_texture_filter texture_filter;  /* limen_node_set_texture_filter */
} limen_drawable;

typedef struct limen_drawables limen_drawables;

LIMEN_API limen_status limen_drawables_create(limen_drawables **out);
LIMEN_API void limen_drawables_destroy(limen_drawables *d);            /* NULL is fine */
/* Reads the scene (refreshing its world matrices): every live node of a kind above, hidden
 * ones included, in creation order. On failure the message is the scene's and the list is
 * empty. name and label stay valid while their node lives; the rest is a copy. */
LIMEN_API limen_status limen_drawables_build(limen_drawables *d, limen_scene *s);
/* The items; returns their count (0 and NULL for an empty or NULL list). */
LIMEN_API int limen_drawables_items(const limen_drawables *d, const limen_drawable **out);
/* Index of node n's item (for limen_view_surface.node, limen_clone.node), or -1 when it has
 * none (not a drawing kind, or stale). Constant time. */
LIMEN_API int limen_drawables_find(const limen_drawables *d, limen_node n);
/* The scene's background colour and ambient term when the list was built. */
LIMEN_API void limen_drawables_environment(const limen_drawables *d, float background[3],
                                           float *ambient);

/* ---------------------------------------------------------------- scenes from files */

/* A model file's node hierarchy as limen nodes (limen_model_load): each file node becomes a
 * node under the group with the file's name and local matrix, parents before children: a
 * MESH holding its meshes' triangles in its own frame, a part in each one's material, read
 * as limen_mesh_load reads a file's (colours, textures held in the file or found beside it,
 * alpha, emission, vertex colours; a missing image leaves the colour, with a warning), or
 * a GROUP where it has none. A node authored as a surface becomes a
 * MIRROR or PORTAL instead, through glTF extras (Blender exports an object's custom
 * properties as them):
 *     "extras": {"limen": {"mirror": {"max_depth": 4, "tint": [r, g, b]}}}
 *     "extras": {"limen": {"portal": {"partner": "OTHER NODE", "max_depth": 8}}}
 * (every field optional but partner), or by a name ending in "-mirror" (for tools that
 * export no extras). Its mesh must be one flat polygon facing one way, at most 256
 * triangles: the polygon's bounding rectangle in its plane (along the edge that gives the
 * least area) is the surface, its centre, width and height; its front is the side the
 * triangles face counter-clockwise; its height runs along the rectangle's side nearer the
 * parent's +Y. Portals pair with the node named as partner, which must name them back. The
 * file's cameras (at their node, looking as the file says; the first becomes the scene's
 * camera where it has none) and point lights (colour times intensity; a glTF light's range
 * as limen_light_set_range) when asked: the file node that carries one becomes that CAMERA
 * or LIGHT node (a GROUP where it is not asked for). A node
 * name that is not UTF-8 is dropped (the node is unnamed). Any problem (a file that cannot
 * be read, a surface that is not flat, a partner missing or one-sided, a bad extras field)
 * fails with a message naming the file and the node, and leaves the scene as it was. */
typedef struct limen_model_desc {
    int cameras;                /* 1: the file's cameras become CAMERA nodes */
    int lights;                 /* 1: its point lights become LIGHT nodes */
} limen_model_desc;

/* Loads path (glTF .gltf/.glb, and what assimp reads) under group, a live GROUP node the
 * caller made and placed; desc NULL: neither cameras nor lights. */
LIMEN_API limen_status limen_model_load(limen_scene *s, limen_node group, const char *path,
                                        const limen_model_desc *desc);
/* The first node in creation order named name among root's descendants (not root itself);
 * LIMEN_ERR_HANDLE (no message: it only reads) where there is none. */
LIMEN_API limen_status limen_node_find_below(const limen_scene *s, limen_node root,
                                             const char *name, limen_node *out);
/* The world box (lo, hi) of what node n and its descendants show (shapes, surfaces, meshes'
 * triangles; boxes of each one's box through its world matrix). LIMEN_ERR_ARG where they
 * show nothing. */
LIMEN_API limen_status limen_node_get_bounds(limen_scene *s, limen_node n, float lo[3],
                                             float hi[3]);

/* ---------------------------------------------------------------- view planning */

/* How a virtual view cuts away what lies behind its exit surface. */
typedef enum limen_clip_method {
    LIMEN_CLIP_OBLIQUE = 0,     /* oblique near plane (falls back to PLANE where it cannot) */
    LIMEN_CLIP_PLANE,           /* user clip plane: gl_ClipDistance / SV_ClipDistance */
    LIMEN_CLIP_NONE,            /* nothing: objects behind the surface leak (baseline) */
    LIMEN_CLIP_COUNT            /* the number of methods (not one itself) */
} limen_clip_method;

typedef enum limen_view_kind {
    LIMEN_VIEW_CAMERA = 0,      /* the scene camera: the root of the tree */
    LIMEN_VIEW_MIRROR,
    LIMEN_VIEW_PORTAL,
    LIMEN_VIEW_KIND_COUNT       /* the number of kinds (not one itself) */
} limen_view_kind;

/* One view of the tree. Views are stored in draw order: depth first, a parent before its
 * children, children in the order their surfaces should be processed. A nested view first
 * resets depth inside its pixels (stencil == its stencil value, within its scissor), draws,
 * and shows the scene background times its tint where nothing lands. Mirrors and portals
 * are drawn with depth clamping (the near plane must not cut them), so a nested view cuts
 * them at clip_plane even where clip is OBLIQUE: an oblique near plane does not cut clamped
 * geometry, and what of a surface lies behind the exit surface would show. limen's shading,
 * which the ray tracer reproduces: at most LIMEN_MAX_LIGHTS lights (the first visible LIGHT
 * nodes in creation order); sphere normals and cylinder side normals (x, 0, z) from the true
 * shape; checker cells in the node's local units before its own scale, x+y for quads, x+y+z
 * for other shapes. */
typedef struct limen_view {
    int id;                     /* index in the plan */
    int parent;                 /* -1 for the camera view */
    int depth;                  /* 0 for the camera view */
    int first_child;            /* -1 if none */
    int next_sibling;           /* -1 if none */
    limen_view_kind kind;
    limen_node through;         /* the surface this view looks through (zero for the camera) */
    float view[16];             /* world -> eye, virtual camera (parent view * X^-1) */
    float proj[16];             /* projection over the whole image; oblique if clip is OBLIQUE */
    float eye[3];               /* world-space position of the virtual eye */
    float clip_plane[4];        /* world space; front = what the view may draw; 0 for camera */
    limen_clip_method clip;     /* what this view uses (PLANE where OBLIQUE could not be formed) */
    int front_face_cw;          /* 1 after an odd number of mirrors: flip the winding */
    int scissor[4];             /* x, y, w, h in pixels, origin bottom-left (OpenGL) */
    int stencil;                /* stencil reference = depth (pixels of this view) */
    float tint[3];              /* product of the mirror tints from the camera to this view */
} limen_view;

/* What a view must draw for one mirror or portal it sees (in the order listed). */
typedef enum limen_surface_state {
    LIMEN_SURFACE_RECURSE = 0,  /* front-facing with a child view: mark its pixels with
                                 * stencil + 1, draw the child, seal with its depth. (Tints are
                                 * not applied here: every colour of a view is multiplied by
                                 * its limen_view.tint, the product on the way.) */
    LIMEN_SURFACE_FILL,         /* front-facing, recursion stopped: draw its fill colour */
    LIMEN_SURFACE_BACK,         /* a mirror seen from behind: a matte quad of its back colour */
    LIMEN_SURFACE_STATE_COUNT   /* the number of states (not one itself) */
} limen_surface_state;

typedef struct limen_view_surface {
    limen_node node;
    limen_surface_state state;
    int child;                  /* the child view's id for RECURSE, else -1 */
    int rect[4];                /* pixels it may cover in this view: x, y, w, h */
} limen_view_surface;

/* Limits on the view tree, shared by the planner (limen_plan_desc), the renderer
 * (limen_render_opts), the ray tracer (limen_trace_desc) and ray casts (limen_ray_cast).
 * Zero in every field means "default" (limen_limits zero = each surface's own max_depth,
 * oblique clipping, 1024 views, no adaptive stop). The tracer and ray casts read only the
 * depth fields: they model neither clipping nor a view budget nor the adaptive stop. */
typedef enum limen_depth_rule {
    LIMEN_DEPTH_RULE_OWN = 0,   /* each surface's own max_depth (default; `depth` unused) */
    LIMEN_DEPTH_RULE_CAP,       /* the lesser of a surface's max_depth and `depth`: lowers
                                 * deep surfaces, never raises shallow ones (CLI --depth) */
    LIMEN_DEPTH_RULE_OVERRIDE,  /* `depth` for every surface, in place of its own: raises
                                 * and lowers (CLI --depth-override) */
    LIMEN_DEPTH_RULE_COUNT      /* the number of rules (not one itself) */
} limen_depth_rule;

/* What one frame may cost, whoever made the scene (scripts come from modders): a budget that
 * the planner spends breadth first like max_views. A view that would overspend it is not
 * created and its surface shows the fill colour (counted in limen_plan_truncated, the
 * limits it met in limen_plan_work.budgets_hit). Zero fields take the defaults, which no
 * scene of the gallery meets; negative ones are refused. */
typedef struct limen_frame_budget {
    int64_t view_pixels;        /* sum of the views' scissor areas, the root's included: the
                                 * pixels the renderer may shade more than once;
                                 * 0 -> 64 x width x height */
    int64_t surface_tests;      /* views x mirrors and portals: each view tests (and a
                                 * renderer may draw) every visible surface; 0 -> 131072 */
    int64_t triangles;          /* mesh triangles over every view, each mesh at the level of
                                 * detail the view draws it at (limen_view_mesh_lod), counted
                                 * over limen_plan_things; 0 -> LIMEN_BUDGET_TRIANGLES_DEFAULT.
                                 * The camera's view is always drawn: where it alone holds more,
                                 * the renderer draws its meshes in order up to the budget and
                                 * drops the rest (counted as one truncation) */
} limen_frame_budget;

#define LIMEN_BUDGET_TRIANGLES_DEFAULT ((int64_t)8 << 20)   /* 8 Mi triangles a frame */

enum {                          /* limen_plan_work.budgets_hit */
    LIMEN_BUDGET_VIEWS = 1,             /* max_views */
    LIMEN_BUDGET_VIEW_PIXELS = 2,
    LIMEN_BUDGET_SURFACE_TESTS = 4,
    LIMEN_BUDGET_TRIANGLES = 8          /* budget.triangles */
};

typedef struct limen_limits {
    limen_clip_method clip;     /* default OBLIQUE */
    limen_depth_rule depth_rule;/* default OWN */
    int depth;                  /* 0..255, levels of views below the camera, for CAP and
                                 * OVERRIDE (0: the camera view only, no recursion) */
    int max_views;              /* view budget (0 -> 1024); levels fill breadth first */
    float adaptive;             /* > 0: stop where a view could change no pixel by more than
                                 * this (in [0,1] colour units, e.g. 8/255): where the product
                                 * of the mirror tints on the way falls below it */
    limen_frame_budget budget;  /* what the frame may cost (planner and renderer); zero ->
                                 * defaults */
    float lod_pixels;           /* meshes: each view draws the coarsest level of detail whose
                                 * error projects to at most this many pixels
                                 * (limen_view_mesh_lod); 0 -> LIMEN_LOD_DEFAULT;
                                 * LIMEN_LOD_FULL: always the full mesh. The tracer uses
                                 * the full mesh unless limen_trace_desc asks for a level. */
} limen_limits;

#define LIMEN_LOD_FULL (-1.0f)  /* limen_limits.lod_pixels: no levels of detail */
/* The default bound, an eighth of a pixel: a coarser level moves the surface by less than
 * that, but it also shades with fewer normals than the full mesh, and the picture's error
 * grows with the bound. Chosen against the area-averaged truth (README: 1,000 bunnies at
 * 640x480 are 0.48% off the 16-sample truth at this bound, 2.5% at 1/4 pixel; at msaa 4,
 * 0.83% off the 4-sample truth): the coarsest bound within 1% of both. */
#define LIMEN_LOD_DEFAULT 0.125f

/* Which surfaces a view keeps. */
typedef enum limen_cull {
    LIMEN_CULL_SURFACE = 0,     /* default: a surface must cover a pixel of the parent's
                                 * narrowed frustum; the child's scissor is what it covers */
    LIMEN_CULL_FRUSTUM,         /* the baseline of LIMEN_METHOD_NAIVE, for comparison: only
                                 * each virtual camera's whole frustum, full-image scissors */
    LIMEN_CULL_COUNT            /* the number of rules (not one itself) */
} limen_cull;

typedef struct limen_plan_desc {
    int width, height;          /* image size in pixels (0 -> 640 x 480) */
    limen_depth_range range;    /* clip-space convention of proj */
    limen_limits limits;        /* zero: the defaults (see limen_limits) */
    limen_cull cull;            /* default SURFACE */
    int multisample;            /* nonzero: a surface counts where it meets any part of a
                                 * pixel, not only its centre, and a view's scissor holds
                                 * every such pixel (a renderer at msaa sets it: its samples
                                 * lie off the centre) */
} limen_plan_desc;

typedef struct limen_plan limen_plan;

LIMEN_API limen_status limen_plan_create(limen_plan **out);
LIMEN_API void limen_plan_destroy(limen_plan *p);                       /* NULL is fine */
/* Plans the view tree of the scene's camera. On failure the message is the scene's. */
LIMEN_API limen_status limen_plan_build(limen_plan *p, limen_scene *s, const limen_plan_desc *d);
LIMEN_API int limen_plan_count(const limen_plan *p);
LIMEN_API const limen_view *limen_plan_view(const limen_plan *p, int i); /* NULL if out of range */
/* The surfaces view i sees (a portal seen from behind and the view's own exit surface are
 * not listed: they draw nothing); returns their count (*out is NULL when it is 0). */
LIMEN_API int limen_plan_view_surfaces(const limen_plan *p, int i, const limen_view_surface **out);
/* The level of detail (an index into d->mesh->lods) that view v draws mesh drawable d at, in
 * an image `height` pixels tall: the coarsest level whose error, scaled by the node's world
 * matrix and seen from the view's eye at the nearest point of d's bounding sphere, projects
 * to at most `pixels` (limen_limits.lod_pixels: 0 -> LIMEN_LOD_DEFAULT, LIMEN_LOD_FULL ->
 * level 0). Level 0
 * where the eye is inside the sphere, and for anything but a mesh with levels. */
LIMEN_API int limen_view_mesh_lod(const limen_view *v, int height, const limen_drawable *d,
                                  float pixels);
/* The shapes (boxes, spheres, cylinders, quads, meshes; visible ones) that view i may show: those
 * whose world bounds meet the view's pyramid from its eye through its scissor rectangle and,
 * below the camera, lie partly in front of its clip plane. limen_plan_build finds them
 * through the scene's spatial index, in time that follows what the view holds, not what the
 * scene holds, and keeps them in the plan, so a renderer can draw only these (plus the view's
 * surfaces and the copies in limen_plan_clones) without the scene. A superset: a shape listed
 * may still be hidden. Sets *out to the view's handles, in node order (owned by the plan, valid
 * until its next build; NULL when there are none, or i is out of range), and returns how many. */
LIMEN_API int limen_plan_things(const limen_plan *p, int i, const limen_node **out);
/* A closed shape (box, sphere, cylinder, mesh) passing through a portal, its centre over the
 * rectangle: it is drawn twice in every view, itself cut at the portal's plane and a copy
 * carried by the portal matrix, cut at the partner's plane. */
typedef struct limen_clone {
    limen_node node;            /* the shape */
    limen_node portal;          /* the portal it is passing into */
    float matrix[16];           /* the copy's world matrix = matrix * the shape's world */
    float keep[4];              /* world plane: the shape keeps what is in front (>= 0) */
    float copy_keep[4];         /* world plane: the copy keeps what is in front of the partner */
} limen_clone;

LIMEN_API int limen_plan_clones(const limen_plan *p, const limen_clone **out);
/* Views that hit the budget or a depth limit and so were not created (their surfaces show
 * the fill colour). */
LIMEN_API int limen_plan_truncated(const limen_plan *p);
/* What the plan spent of its budget. */
typedef struct limen_plan_work {
    int views;                  /* limen_plan_count */
    int truncated;              /* limen_plan_truncated */
    int64_t view_pixels;        /* sum of the views' scissor areas */
    int64_t surface_tests;      /* view x surface tests made */
    unsigned budgets_hit;       /* LIMEN_BUDGET_* bits of the budgets that stopped a view */
    int64_t triangles;          /* mesh triangles of the views kept (budget.triangles' count) */
} limen_plan_work;
LIMEN_API void limen_plan_get_work(const limen_plan *p, limen_plan_work *out);
/* Writes the plan as JSON ({"views": [...]}); returns LIMEN_ERR_IO if it cannot. Each view
 * lists, besides its matrices and surfaces, the meshes it may show (limen_plan_things)
 * with the level of detail it draws each at under the plan's lod_pixels and height
 * (limen_view_mesh_lod): "meshes": [{"node": "statue", "lod": 3, "triangles": 212, "parts":
 * [{"first": 0, "count": 212, "material": 0}], "materials": [{"name", "base_color",
 * "base_texture" (whether it has one), "alpha_mode" ("opaque", "mask", "blend"),
 * "alpha_cutoff", "emissive", "emissive_texture"}]}]: that level's parts ("baked": true
 * where the level is baked, limen_mesh_lod.baked: its own part and material). It reads the scene
 * (names, meshes) as the plan left it: write it before the scene changes. */
LIMEN_API limen_status limen_plan_write_json(const limen_plan *p, const limen_scene *s,
                                             const char *path);

/* ---------------------------------------------------------------- renderer */

typedef struct limen_renderer limen_renderer;

typedef enum limen_backend {
    LIMEN_BACKEND_OSMESA = 0,   /* Mesa's off-screen software renderer (llvmpipe) */
    LIMEN_BACKEND_EGL,          /* EGL surfaceless; a GPU where there is one */
    LIMEN_BACKEND_HOST,         /* the caller's own OpenGL context (a game's window) */
    LIMEN_BACKEND_COUNT         /* the number of backends (not one itself) */
} limen_backend;

/* LIMEN_BACKEND_HOST: drawing into the game's context.
 *   The game owns the window and an OpenGL 3.3+ core context, makes it current on the
 *   calling thread before every limen_renderer_* call, and passes its function loader
 *   (SDL_GL_GetProcAddress; cast eglGetProcAddress or glfwGetProcAddress to this type).
 *   limen creates no context: it draws the planned tree into `framebuffer` (0: the default
 *   one, a window's back buffer) over the viewport (x, y, width, height), clearing that
 *   rectangle first, with either method. The framebuffer needs a depth buffer, and 8
 *   stencil bits for the stencil method (SDL_GL_STENCIL_SIZE 8); without them a frame fails
 *   with LIMEN_ERR_UNSUPPORTED and says so (it does not switch methods behind your back).
 *   msaa must be 0: a multisampled host framebuffer is drawn multisampled as it is.
 *   What limen's objects are: programs, buffers, vertex arrays, queries, and for the texture
 *   method (and LIMEN_FILL_PREVIOUS) textures, renderbuffers and framebuffers of its own.
 *   GL state: every call restores what it changes, so the game's next draw is unaffected:
 *   bound program, vertex array (with its element buffer), array buffer, draw and read
 *   framebuffers, renderbuffer, viewport, scissor box and test, depth test/func/mask/clear
 *   value/clamp/range, stencil test and both faces' func/ref/masks/ops/clear value, colour mask
 *   and clear value, blend, cull face and mode, front face, polygon mode and offset fill,
 *   clip distances 0-7, clip control (origin, depth mode), multisample, framebuffer sRGB,
 *   logic op, sample coverage/alpha-to-coverage/mask, rasterizer discard, primitive
 *   restart, active texture unit, texture unit 0's 2D texture and sampler, pixel pack and
 *   unpack buffers and pack alignment/row length/skips. While it draws limen turns off
 *   blend, sRGB writes, polygon offset, logic op, coverage, discard and restart, fills
 *   polygons, and unbinds samplers and pixel buffers from what it uses.
 *   Two things it cannot give back: errors pending in glGetError when limen is called are
 *   read and dropped (so that limen reports only its own), and the game must not have an
 *   occlusion or pipeline-statistics query active during a frame (limen counts with them).
 *   Whose context: the renderer belongs to the context current at create (a context below
 *   3.3 is refused there: "needs OpenGL 3.3 core, this context is 2.1"). Any later call made
 *   while another context is current is refused with a message that says so and touches
 *   nothing in that context; limen_renderer_destroy then frees limen's memory only and
 *   leaves its GL objects to its own context, which frees them when the game destroys it
 *   (destroy the renderer with its context current to free them sooner). */
typedef void *(*limen_gl_loader)(const char *name);

typedef struct limen_renderer_desc {
    limen_backend backend;          /* default OSMesa */
    int width, height;              /* 0 -> 640 x 480 (host: the viewport's size) */
    int msaa;                       /* samples per pixel; 0 or 1 -> off (host: 0); each
                                     * sample shaded at its position where GL 4.0 allows */
    limen_depth_range depth_range;  /* default NO */
    int depth_bits;                 /* 24 (integer) or 32 (float); 0 -> 24, or 32 for
                                     * ZO_REVERSED, where a float buffer is the point (host:
                                     * limen's offscreen targets; the frame has the host's) */
    limen_gl_loader gl_loader;      /* host: the game's loader (required) */
    unsigned framebuffer;           /* host: framebuffer object to draw into; 0: default */
    int x, y;                       /* host: lower-left corner of the viewport in it */
} limen_renderer_desc;

typedef struct limen_frame_stats {
    double ms;                  /* wall time of the frame, submission to glFinish */
    int views;                  /* views drawn (1 for a scene without mirrors or portals) */
    uint64_t fragments;         /* fragment-shader invocations (pipeline statistics); 0 if unavailable */
    uint64_t samples;           /* samples that passed depth and stencil (occlusion query) */
    uint64_t pixels;            /* width * height */
    int truncated;              /* views not created: limits or the budget (see the plan) */
    int draw_calls;             /* OpenGL draw calls (meshes sharing geometry: one per batch) */
    uint64_t triangles;         /* triangles submitted, meshes at their levels of detail */
} limen_frame_stats;

LIMEN_API limen_status limen_renderer_create(const limen_renderer_desc *desc,
                                             limen_renderer **out);
/* If create fails, *out may still hold a renderer carrying the message; destroy it.
 * OSMesa and EGL renderers make their own context current only within a call: afterwards
 * the context that was current on the thread before (of the same API) is current again. */
LIMEN_API void limen_renderer_destroy(limen_renderer *r);              /* NULL is fine */
LIMEN_API const char *limen_renderer_error(const limen_renderer *r);   /* "" after a successful call */
LIMEN_API const char *limen_renderer_gl_info(const limen_renderer *r); /* GL_RENDERER, GL_VERSION */
LIMEN_API void limen_renderer_get_size(const limen_renderer *r, int *width, int *height);
typedef enum limen_method {
    LIMEN_METHOD_STENCIL = 0,   /* one framebuffer, stencil-nested recursion */
    LIMEN_METHOD_TEXTURE,       /* each view into an offscreen target sampled by its parent */
    LIMEN_METHOD_NAIVE,         /* the baseline of common engines, for comparison: one
                                 * full-resolution offscreen render per surface per level, no
                                 * culling of surfaces outside the narrowed frustum, no scissor
                                 * (its plan is LIMEN_CULL_FRUSTUM's) */
    LIMEN_METHOD_COUNT          /* the number of methods (not one itself) */
} limen_method;

typedef enum limen_fill {
    LIMEN_FILL_COLOR = 0,       /* a surface where recursion stops shows its fill colour */
    LIMEN_FILL_PREVIOUS,        /* ... the previous frame's picture of that surface: its
                                 * shallowest view's rectangle, stretched onto it (the
                                 * fill colour on the first frame) */
    LIMEN_FILL_COUNT            /* the number of fills (not one itself) */
} limen_fill;

typedef struct limen_render_opts {
    limen_method method;        /* default STENCIL */
    limen_fill fill;            /* default COLOR */
    float texture_scale;        /* texture method: resolution of view targets, (0, 1]; 0 -> 1 */
    limen_limits limits;        /* as in limen_plan_desc; zero: the defaults */
} limen_render_opts;

/* Plans and draws one frame of the scene from its camera. opts and stats may be NULL; with
 * stats the call returns when the frame is finished (glFinish), without them once it is
 * submitted (glFlush), so that the next frame's work overlaps its shading (reading it back
 * or swapping waits for it). A mesh
 * or texture that cannot be copied to the GPU (memory out) fails the frame with
 * LIMEN_ERR_NOMEM and a message naming it, rather than a frame that lacks it; a later frame
 * tries again. */
LIMEN_API limen_status limen_render_frame(limen_renderer *r, limen_scene *s,
                                          const limen_render_opts *opts,
                                          limen_frame_stats *stats);
/* LIMEN_BACKEND_HOST: draw from now on into `framebuffer` over the viewport (x, y, width,
 * height), for example after the window was resized (with the game's context current).
 * Other backends -> LIMEN_ERR_UNSUPPORTED. */
LIMEN_API limen_status limen_renderer_set_viewport(limen_renderer *r, unsigned framebuffer,
                                                   int x, int y, int width, int height);
/* The plan of the last frame (owned by the renderer; valid until the next frame). */
LIMEN_API const limen_plan *limen_renderer_plan(const limen_renderer *r);
/* Copies the last frame as 8-bit RGB, top row first: width * height * 3 bytes. (Host: read
 * back from the viewport of its framebuffer's read buffer, before the game draws over it or
 * swaps; a multisampled host framebuffer -> LIMEN_ERR_UNSUPPORTED.) */
LIMEN_API limen_status limen_renderer_read_rgb(limen_renderer *r, unsigned char *rgb);
LIMEN_API limen_status limen_renderer_write_png(limen_renderer *r, const char *path);

/* ---------------------------------------------------------------- draw list */

/* One frame as a flat list of commands (docs/DESIGN.md, "The draw list"), for a renderer of
 * your own or limen's OpenGL one, which draws exactly this list. The core turns a built plan
 * and the drawables of the same scene into commands for one frame and one method (stencil or
 * texture), each self-contained: what to draw and the pipeline state to draw it with,
 * already resolved for the depth range (reversed depth: GREATER where the plain range says
 * LESS). A backend walks the list in order and does what each command says: it needs no
 * scene, no plan logic, no clipping and no sorting. What it draws is geometry it uploads
 * once, keyed on limen_mesh_geometry.id: a MESHES command's mesh (limen_drawable.mesh) and
 * a SHAPE command's unit shape (limen_unit_geometry of limen_kind_get(kind)->unit), both at
 * the command's level and both as instances from limen_drawlist_instances
 * (examples/own_renderer.c draws the two with one function).
 *     limen_drawlist *dl;  limen_drawlist_create(&dl);
 *     limen_drawlist_desc dd = { .width = w, .height = h, .method = LIMEN_METHOD_STENCIL };
 *     limen_drawlist_build(dl, plan, drawables, &dd);
 *     const limen_draw_cmd *c;  int n = limen_drawlist_commands(dl, &c);
 *     for (int i = 0; i < n; i++) ... c[i].op, c[i].state, passes[c[i].pass] ... */

typedef enum limen_compare {        /* a depth test: the fragment's depth OP the stored one */
    LIMEN_COMPARE_ALWAYS = 0,       /* passes (the test stays on: depth is still written) */
    LIMEN_COMPARE_LESS,             /* nearer than what is there (plain depth ranges) */
    LIMEN_COMPARE_LEQUAL,           /* at least as near (a surface over its own depth) */
    LIMEN_COMPARE_EQUAL,            /* exactly there (a background at the far plane) */
    LIMEN_COMPARE_GREATER,          /* nearer, where depth is reversed (ZO_REVERSED) */
    LIMEN_COMPARE_GEQUAL,           /* at least as near, where depth is reversed */
    LIMEN_COMPARE_COUNT             /* the number of tests (not one itself) */
} limen_compare;

typedef enum limen_stencil_op {     /* what a pixel that passes stencil and depth does */
    LIMEN_STENCIL_KEEP = 0,         /* leaves it */
    LIMEN_STENCIL_INVERT,           /* the bits of write_mask flip (to a child's value) */
    LIMEN_STENCIL_DECR,             /* one less: back to the parent's value (a seal) */
    LIMEN_STENCIL_OP_COUNT          /* the number of ops (not one itself) */
} limen_stencil_op;

/* The pipeline state of one command. A backend sets all of it for every command (or only
 * what changed since the last: the list makes no promise either way). */
typedef struct limen_draw_state {
    int scissor[4];             /* x, y, w, h: pixels of the frame (origin bottom-left) the
                                 * command may touch; texture method: of its target */
    unsigned char color_write;  /* 0: write no colour */
    unsigned char depth_write;  /* 0: write no depth */
    unsigned char depth_clamp;  /* 1: clamp depth instead of clipping at near and far */
    unsigned char cull_back;    /* 1: cull back faces (front: the pass's front_cw winding) */
    unsigned char blend;        /* 1: src alpha, one minus src alpha */
    unsigned char stencil_test; /* 1: draw only where stencil == stencil_ref (all 8 bits) */
    unsigned char stencil_ref;  /* the value stencil_test compares with */
    unsigned char stencil_write_mask; /* the stencil bits stencil_pass (and CLEAR) may change */
    limen_stencil_op stencil_pass; /* what a pixel passing stencil and depth does to stencil */
    limen_compare depth_test;   /* always on; ALWAYS where nothing may fail it */
    unsigned char clip_on;      /* clip distance 0: keep what has clip . p >= 0 (world p) */
    unsigned char cut_on;       /* clip distance 1: keep what has cut . p >= 0 (world p) */
    unsigned char counted;      /* a shading pass: its samples count in limen_frame_stats */
    float clip[4];              /* world plane of clip_on */
    float cut[4];               /* world plane of cut_on (a shape passing through a portal) */
} limen_draw_state;

/* A pass: the camera a run of commands draws with (a view of the plan, its projection
 * narrowed to a texture target's rectangle in the texture method). */
typedef struct limen_draw_pass {
    int view;                   /* the plan's view (limen_plan_view) */
    float view_proj[16];        /* world -> clip, as drawn (narrowing included) */
    float view_mat[16];         /* world -> eye, the view's (for levels of detail) */
    float eye[3];               /* world-space eye (for shading) */
    float tint[3];              /* SHAPE and MESHES colours are multiplied by it */
    int front_cw;               /* 1: clockwise front faces */
    float px_scale;             /* pixels per unit of (size / distance) at the image centre */
    float frag_map[4];          /* image pixel = frag_map.xy * fragment.xy + frag_map.zw,
                                 * fragment: the pixel in its target (frame origin 0, 0) */
    int target;                 /* 0: the frame; k > 0: offscreen target k (texture method) */
} limen_draw_pass;

typedef enum limen_draw_op {
    LIMEN_DRAW_TARGET = 0,      /* texture method: draw into `target` from now on (0: the
                                 * frame; k: target k of target_w x target_h pixels, colour
                                 * RGBA8 sampled linear and clamped, plus depth-stencil), over
                                 * the viewport `viewport` in it */
    LIMEN_DRAW_CLEAR,           /* clear within state.scissor: depth to the far value of the
                                 * range where state.depth_write, colour to `color` where
                                 * state.color_write, stencil to 0 where
                                 * state.stencil_write_mask (the frame's first clear) */
    LIMEN_DRAW_POLYGON,         /* a triangle fan of list vertices [first, first + count):
                                 * x, y, z in normalized device coordinates, already clipped
                                 * (clip nothing: its state's clip_on and cut_on are always
                                 * 0), in flat `color` (tint included); with `image`
                                 * not NONE: the image's texel at uv = image_map.xy *
                                 * fragment.xy + image_map.zw (fragment: the pixel in the
                                 * target, frame origin 0, 0), times `color` */
    LIMEN_DRAW_SHAPE,           /* drawable `item` (box, sphere, cylinder, quad, or a mirror's
                                 * or portal's quad) at model matrix `world` (the drawable's,
                                 * or a portal copy's: carried; like limen_drawable.world it
                                 * holds not the unit shape's scale, dims) with albedo
                                 * `color`, lit: limen's shading, checker and texture as the
                                 * drawable says. The same as `count` = 1 list instance from
                                 * `first` (world times `scale`, the albedo) of the kind's
                                 * limen_unit_geometry at level `lod`: a backend may draw
                                 * shapes as it draws MESHES */
    LIMEN_DRAW_MESHES,          /* mesh drawable `item` at level of detail `lod` (clamp it to
                                 * the levels you keep), `count` instances from list instance
                                 * `first` (a batch of nodes sharing the geometry), its parts
                                 * `parts` says, lit as SHAPE */
    LIMEN_DRAW_FLUSH,           /* a hint: hand what is queued to the device now */
    LIMEN_DRAW_OP_COUNT         /* the number of ops (not one itself) */
} limen_draw_op;

typedef enum limen_draw_image {
    LIMEN_IMAGE_NONE = 0,           /* a flat colour */
    LIMEN_IMAGE_PREVIOUS,       /* the previous frame's colour (LIMEN_FILL_PREVIOUS) */
    LIMEN_IMAGE_TARGET,         /* target `target`'s colour (texture method) */
    LIMEN_IMAGE_COUNT           /* the number of images (not one itself) */
} limen_draw_image;

typedef enum limen_draw_parts {
    LIMEN_PARTS_OPAQUE = 0,     /* a mesh's opaque and masked parts (all of a plain mesh) */
    LIMEN_PARTS_BLENDED,        /* its blended parts (state.blend is on) */
    LIMEN_PARTS_COUNT           /* the number of choices (not one itself) */
} limen_draw_parts;

typedef struct limen_draw_cmd {
    limen_draw_op op;           /* what to do */
    int pass;                   /* index into the list's passes (the camera it draws with) */
    limen_draw_state state;     /* how */
    int item;                   /* SHAPE, MESHES: an index into limen_drawables_items */
    int lod;                    /* MESHES: level of detail (an index into d->mesh->lods);
                                 * SHAPE: the level of the kind's limen_unit_geometry to draw
                                 * (the one with `segments`; 0 for a box or square) */
    limen_draw_parts parts;     /* MESHES: which parts */
    int first, count;           /* POLYGON: vertices; MESHES, SHAPE: instances */
    float color[3];             /* CLEAR, POLYGON, SHAPE */
    float world[16];            /* SHAPE: model matrix (a portal's copy: carried) */
    float scale[3];             /* SHAPE: the unit shape's stretch along each local axis
                                 * before world (limen_kind_info.scale over the drawable's
                                 * dims): a unit point p is at world * (scale * p) */
    limen_draw_image image;     /* POLYGON */
    float image_map[4];         /* POLYGON with an image: fragment -> uv */
    int target;                 /* TARGET; POLYGON with LIMEN_IMAGE_TARGET: the image's */
    int target_w, target_h;     /* TARGET: the target's size (0 for the frame) */
    int viewport[4];            /* TARGET: x, y, w, h in it */
    int segments;               /* SHAPE: a sphere's or cylinder's segments around (8, 12, 16,
                                 * 24, 32, 48, 64, 96, 128, 192 or 256: the fewest whose
                                 * silhouette stays within 0.2 pixel, 0.2 / msaa where
                                 * multisampled, of the true one); 0 for other shapes */
} limen_draw_cmd;

typedef struct limen_draw_instance {
    float world[16];            /* model matrix */
    float color[3];             /* albedo */
} limen_draw_instance;

typedef struct limen_drawlist limen_drawlist;

typedef struct limen_drawlist_desc {
    int width, height;          /* the frame in pixels: the plan's (0: take it) */
    limen_method method;        /* STENCIL or TEXTURE (NAIVE: TEXTURE, over a plan built
                                 * with LIMEN_CULL_FRUSTUM) */
    limen_fill fill;            /* LIMEN_FILL_PREVIOUS: surfaces where recursion stopped show
                                 * the previous frame where have_previous */
    float texture_scale;        /* texture method: target resolution, (0, 1]; 0 -> 1 */
    int msaa;                   /* samples per pixel the backend draws with (0, 1: one) */
    limen_depth_range range;    /* the plan's clip-space convention (another: refused) */
    limen_limits limits;        /* lod_pixels and budget.triangles; zero: the defaults */
    int have_previous;          /* 1: the backend holds a previous frame */
} limen_drawlist_desc;

LIMEN_API limen_status limen_drawlist_create(limen_drawlist **out);    /* an empty list */
LIMEN_API void limen_drawlist_destroy(limen_drawlist *dl);             /* NULL is fine */
/* Builds the frame's commands from a built plan and the drawables of the same scene (the
 * scene itself is not read), reusing the list's memory. On failure (a NULL or unbuilt plan,
 * a bad desc or one whose size or range is not the plan's, memory) the list is empty and
 * limen_drawlist_error says why. */
LIMEN_API limen_status limen_drawlist_build(limen_drawlist *dl, const limen_plan *p,
                                            const limen_drawables *d,
                                            const limen_drawlist_desc *desc);
/* The commands, in the order to execute them; returns their count. */
LIMEN_API int limen_drawlist_commands(const limen_drawlist *dl, const limen_draw_cmd **out);
/* The passes commands refer to; returns their count. */
LIMEN_API int limen_drawlist_passes(const limen_drawlist *dl, const limen_draw_pass **out);
/* The POLYGON commands' vertices (NDC x, y, z); returns their count. */
LIMEN_API int limen_drawlist_vertices(const limen_drawlist *dl, const float (**out)[3]);
/* The MESHES and SHAPE commands' instances; returns their count. */
LIMEN_API int limen_drawlist_instances(const limen_drawlist *dl,
                                       const limen_draw_instance **out);
/* A light that shades the frame (the first LIMEN_MAX_LIGHTS visible LIGHT drawables), laid
 * out as two vec4 (pos, inv_range2; color, 0) so that an array of them goes to a shader as
 * it is (glUniform4fv of 2 * count, a std140 block). */
typedef struct limen_draw_light {
    float pos[3];               /* world position */
    float inv_range2;           /* 1 / range^2 (limen_light_set_range), 0 for no range */
    float color[3];             /* colour times intensity */
    float zero;                 /* 0 */
} limen_draw_light;
/* The frame's lights (at most LIMEN_MAX_LIGHTS) and the ambient term (where ambient is not
 * NULL), as limen's shading reads them; returns their count. */
LIMEN_API int limen_drawlist_lights(const limen_drawlist *dl, const limen_draw_light **out,
                                    float *ambient);
/* The message of the last failed build ("" after a success). */
LIMEN_API const char *limen_drawlist_error(const limen_drawlist *dl);
/* texture_scale (1, and 1 for NAIVE); width, height and range stay (0: the plan's); the
 * limits for that size (limen_limits_defaults). */
LIMEN_API limen_drawlist_desc limen_drawlist_desc_defaults(const limen_drawlist_desc *desc);

/* ---------------------------------------------------------------- ray casting */

/* The reference ray tracer: the ground truth the renderers are measured against. It
 * intersects the true shapes (exact spheres and cylinders), shades like the renderer (see
 * CONVENTIONS) at pixel centres (or limen_trace_desc.samples points), reflects off mirrors
 * and continues through portals exactly as the planner's view tree does: a mirror or portal
 * is passed only from its front, a portal seen from behind is empty air, a mirror seen from
 * behind is a matte quad of its back colour, the surface just passed is never hit again by
 * the next segment, and a surface beyond a bounce limit shows its fill colour. Double
 * precision throughout. Not modelled: the far plane, the view budget (max_views); MSAA only
 * as limen_trace_desc.samples = 4 (its positions, each sample shaded, as the renderer's msaa
 * frames shade them). Each call reads the scene (refreshing its world matrices) and must not
 * overlap with edits of that scene. */
#define LIMEN_HIT_MAX_SURFACES 64

typedef struct limen_hit {
    int hit;                    /* 1 if the path ends on a node, 0 if it leaves the scene */
    float point[3];             /* world-space point where the path ends on `node` */
    float normal[3];            /* unit normal there, turned to face the incoming segment */
    float distance;             /* world length of the whole path to point; INFINITY if missed */
    limen_node node;            /* shape, back of a mirror, or surface at a limit / unpaired */
    float color[3];             /* what the tracer shows along the ray, tints included */
    int surface_count;          /* mirrors reflected off and portals passed, in order */
    limen_node surfaces[LIMEN_HIT_MAX_SURFACES]; /* the first LIMEN_HIT_MAX_SURFACES of them */
    float seg_origin[3];        /* final segment's start (the origin, or the last exit point) */
    float seg_dir[3];           /* final segment's unit direction (scaled portals rescale it) */
} limen_hit;

/* Casts a world-space ray (dir of any length > 0) through mirrors and portals. limits may
 * be NULL (each surface's own max_depth); only its depth fields apply. No near plane: hits
 * at any t > 0 count. NaN/Inf or zero dir, NULL -> ARG. */
LIMEN_API limen_status limen_ray_cast(limen_scene *s, const float origin[3], const float dir[3],
                                      const limen_limits *limits, limen_hit *out);

typedef struct limen_trace_desc {
    int width, height;          /* image size in pixels (0 -> 640 x 480) */
    limen_limits limits;        /* depth fields only (see limen_limits); zero: the defaults */
    int threads;                /* worker threads; 0 -> the number of online CPUs */
    int samples;                /* rays per pixel, averaged with equal weights (a box filter)
                                 * after clamping each to [0, 1] as a framebuffer does: 0 or
                                 * 1 -> the centre; 4 -> the standard 4x MSAA positions (GL
                                 * window coordinates from the pixel's lower-left corner:
                                 * (0.375, 0.125), (0.875, 0.375), (0.125, 0.625),
                                 * (0.625, 0.875); what llvmpipe's glGetMultisamplefv gives),
                                 * so that a renderer at msaa 4 can be held to it; another
                                 * square k * k up to 256 -> the centres of a k x k grid of
                                 * cells. Anything else -> ARG */
    float lod_pixels;           /* meshes: 0 (or LIMEN_LOD_FULL) the full mesh, the truth;
                                 * > 0: each mesh at the level of detail the camera's view
                                 * draws it at under this bound (limen_view_mesh_lod, as a
                                 * renderer's limen_limits.lod_pixels), so that a level can be
                                 * held to the truth of its own triangles. A mesh seen in a
                                 * mirror or through a portal keeps the camera view's level
                                 * (a renderer chooses per view) */
    int lod_level;              /* meshes: k > 0 traces every mesh at its level k (its
                                 * coarsest where it has fewer), whatever lod_pixels says;
                                 * 0: lod_pixels decides. Negative -> ARG */
} limen_trace_desc;

/* Ray traces the scene from its camera (the root view skips what lies nearer than the
 * camera's near plane, as the rasterizer clips it) into rgb: width * height * 3 bytes,
 * top row first, each channel round(clamp(c) * 255). desc may be NULL. No camera -> ARG. */
LIMEN_API limen_status limen_trace_image(limen_scene *s, const limen_trace_desc *desc,
                                         unsigned char *rgb);

/* ---------------------------------------------------------------- scripts */

/* A Lua 5.4 scene script: `return limen.scene{...}` after adding nodes; an optional
 * `function s.update(t)` animates it. The script owns its scene, and runs in a Lua state of
 * its own, within limits, so that it cannot hang or exhaust the program that runs it:
 *   - Safe mode (the default): no io, no os but the clock, no debug, no C modules, no
 *     bytecode, no __gc metamethods (finalizers would run outside the budget); print goes to
 *     the host's callback (desc.print) or nowhere, never to stdout; no value shows an address
 *     (tostring, print and string.format's %s and %p show "table: #3", a number per value;
 *     math.randomseed() seeds from the clock).
 *   - An instruction budget per call (the load, and each update), for the script as a whole:
 *     Lua VM instructions of every coroutine, plus one per 32 bytes allocated, plus one per 4
 *     bytes of source compiled (the script's own, and load's), plus the work of library
 *     functions that loop over their arguments (string.rep, table.insert, table.sort, s:nodes,
 *     ...); a string pattern whose worst case exceeds what is left is refused before it runs.
 *     A coroutine pays 100 instructions when first resumed (its last instructions before it
 *     ends are not counted one by one).
 *   - A time limit per call that follows from the budget: 100 ns per instruction of it, at
 *     least 1 s (5 s by default), of the calling thread's processor time (a busy machine does
 *     not make a script fail). Only a script whose single instructions are slow meets it
 *     (comparing two long strings is one instruction); the clock is read often enough that a
 *     call ends within a sixteenth of the limit, plus one instruction, after passing it.
 *   - A memory cap on what its Lua state and its scenes' nodes hold. It is hit when an
 *     allocation it refused ends in "not enough memory" (garbage that a collection frees is
 *     no hit). Any cap is safe, down to 0 (then the load fails with a message). A mesh or
 *     an image that would not fit is refused before it is imported or decoded, from what
 *     its file says of its size (a header, a .glb's JSON chunk, an OBJ's face lines counted
 *     in one pass), never by reading the whole file into memory first.
 * A call that exceeds a limit fails with LIMEN_ERR_SCRIPT and a message such as
 *   "scenes/x.lua:3: script exceeded its instruction budget (50000000)",
 *   "scenes/x.lua:3: script exceeded its time limit (5 s, set by its instruction budget)" or
 *   "scenes/x.lua:3: not enough memory (script memory cap 64 MiB)"
 * (with the line where it is known). The script cannot catch it: pcall, xpcall (whose handler
 * does not run for it), coroutine.resume/wrap/close and load pass it on. It stops the script:
 * later updates fail at once with the same message, while its scene stays readable and the
 * script can be destroyed. A trusted script keeps the limits its desc gives, but it can lift
 * the budget with debug.sethook, and its finalizers run unbounded. */
typedef struct limen_script limen_script;

/* Receives what the script prints: one line per print() call, its values separated by tabs,
 * control bytes and invalid UTF-8 escaped (\n, \t, \xNN), cut at 1,023 bytes; no newline.
 * Called during the script's load or update, on that thread; it must not call the script. */
typedef void (*limen_script_print_fn)(void *user, const char *line);

typedef struct limen_script_desc {
    int trusted;                /* 1: full standard library; 0: the safe subset */
    int64_t instruction_budget; /* per load and per update call; 0 -> 50 million, < 0 -> none
                                 * (and no time limit) */
    int64_t memory_cap;         /* bytes; 0 -> 64 MiB, < 0 -> none */
    limen_script_print_fn print; /* where print() goes; NULL: nowhere (safe mode), stdout
                                 * (trusted mode, as stock Lua) */
    void *print_user;           /* passed to print */
} limen_script_desc;

/* Runs the script. On failure *out may still hold a script whose limen_script_error()
 * reads "file:line: message" (or "file: message" where no line applies), on one line;
 * destroy it either way. desc may be NULL (the defaults: safe mode, default limits). */
LIMEN_API limen_status limen_script_load(const char *path, const limen_script_desc *desc,
                                         limen_script **out);
LIMEN_API void limen_script_destroy(limen_script *sc);                 /* NULL is fine */
LIMEN_API const char *limen_script_error(const limen_script *sc);      /* "" when none */
LIMEN_API limen_scene *limen_script_scene(limen_script *sc);           /* owned by the script */
LIMEN_API int limen_script_animated(const limen_script *sc);           /* 1 if it has update */
/* Calls the scene's update(t), t in seconds; a no-op for a still scene. An error leaves the
 * script usable (the next update may succeed), except one from a limit (see above). */
LIMEN_API limen_status limen_script_update(limen_script *sc, double t);
/* The files a script read: 0 is the script itself, then the modules a safe script required
 * from its folder, in the order first required (a host watches them with
 * limen_scene_get_file's, as `limen view` does). Copies the i-th into path; LIMEN_ERR_ARG
 * past the last, or where it does not fit in size bytes. */
LIMEN_API limen_status limen_script_get_file(const limen_script *sc, int i, char *path,
                                             size_t size);
/* After a load or update that failed on the memory cap (an allocation, or a mesh or image
 * the cap had no room for, refused from its header before it is read): the cap in bytes
 * that the refused request would have fitted in, what the script held then plus what it
 * asked for; 0 when the last call failed otherwise or succeeded. Later requests may need
 * more. The limen program prints it as "needs 231.8 MiB: --memory 256". */
LIMEN_API int64_t limen_script_memory_needed(const limen_script *sc);

/* ---------------------------------------------------------------- images */

/* Writes 8-bit RGB (top row first) as PNG. */
LIMEN_API limen_status limen_write_png(const char *path, int width, int height,
                                       const unsigned char *rgb);
/* Writes 8-bit RGB (top row first) in the format the file name asks for: ".png", or ".jpg"
 * / ".jpeg" (JPEG, quality 95), in any case. Any other name -> ARG, writing nothing. */
LIMEN_API limen_status limen_write_image(const char *path, int width, int height,
                                         const unsigned char *rgb);
/* The largest image limen_read_png decodes: 64 million pixels (192 MB as RGB). */
#define LIMEN_IMAGE_MAX_PIXELS (64LL * 1024 * 1024)

/* Reads a PNG (any channel count) as 8-bit RGB; free *rgb with limen_free. An image over
 * LIMEN_IMAGE_MAX_PIXELS is refused from its header, before decoding: LIMEN_ERR_ARG. A file
 * that cannot be read or is not a PNG: LIMEN_ERR_IO. */
LIMEN_API limen_status limen_read_png(const char *path, int *width, int *height,
                                      unsigned char **rgb);
LIMEN_API void limen_free(void *p);

typedef struct limen_diff {
    double bad_share;       /* share of pixels whose largest channel differs by > threshold */
    long bad_pixels;
    double psnr;            /* dB over all channels; INFINITY for identical images */
    int max_delta;          /* largest channel difference anywhere */
} limen_diff;

/* Compares two RGB images of one size. threshold is in 8-bit steps (the project uses 8).
 * heatmap, if not NULL (width * height * 3 bytes), gets a picture of where: the first image
 * in dim grey, pixels over the threshold in red to yellow by their difference. */
LIMEN_API limen_status limen_image_diff(const unsigned char *a, const unsigned char *b,
                                        int width, int height, int threshold, limen_diff *out,
                                        unsigned char *heatmap);

/* ---------------------------------------------------------------- defaults */

/* Zero in a desc field means "default". Each function below returns a copy of *desc (NULL:
 * all zero) with those zeros replaced by the defaults that the call taking it applies (one
 * function per desc, all in src/core/limits.c), so a program can read or print them; fields
 * that are not zero stay as they are (the call checks them, these do not). */
#define LIMEN_DEFAULT_WIDTH 640                     /* image size where a desc gives none */
#define LIMEN_DEFAULT_HEIGHT 480                    /* ... */
#define LIMEN_DEFAULT_MAX_VIEWS 1024                /* limen_limits.max_views */
#define LIMEN_DEFAULT_VIEW_SCREENS 64               /* budget.view_pixels: 64 x width x height */
#define LIMEN_DEFAULT_SURFACE_TESTS 131072          /* budget.surface_tests */
#define LIMEN_DEFAULT_INSTRUCTIONS 50000000         /* limen_script_desc.instruction_budget */
#define LIMEN_DEFAULT_SCRIPT_MEMORY (64LL << 20)    /* limen_script_desc.memory_cap: 64 MiB */

/* max_nodes stays 0 (no limit but memory). */
LIMEN_API limen_scene_desc limen_scene_desc_defaults(const limen_scene_desc *desc);
/* max_views, lod_pixels (LIMEN_LOD_DEFAULT), the frame budget for a width x height image
 * (width or height 0: LIMEN_DEFAULT_WIDTH x LIMEN_DEFAULT_HEIGHT; triangles:
 * LIMEN_BUDGET_TRIANGLES_DEFAULT); depth 0 under LIMEN_DEPTH_RULE_OWN, which ignores it. */
LIMEN_API limen_limits limen_limits_defaults(const limen_limits *limits, int width, int height);
/* width and height (as limen_plan_build: 0 or less -> 640 x 480), then the limits for that
 * size. */
LIMEN_API limen_plan_desc limen_plan_desc_defaults(const limen_plan_desc *desc);
/* width and height (0 or less -> 640 x 480), depth_bits (24, or 32 for ZO_REVERSED); msaa 0
 * or 1 both mean off and stay. */
LIMEN_API limen_renderer_desc limen_renderer_desc_defaults(const limen_renderer_desc *desc);
/* texture_scale (1), and the limits for a renderer of width x height. */
LIMEN_API limen_render_opts limen_render_opts_defaults(const limen_render_opts *opts, int width,
                                                       int height);
/* width and height (0 -> 640 x 480), threads (the online CPUs), the limits for that size. */
LIMEN_API limen_trace_desc limen_trace_desc_defaults(const limen_trace_desc *desc);
/* instruction_budget and memory_cap (0 -> the defaults above; < 0, none, stays). */
LIMEN_API limen_script_desc limen_script_desc_defaults(const limen_script_desc *desc);
/* ---------------------------------------------------------------- collision */

/* Bodies that collide: a sphere (a centre and a radius) or a capsule (a segment and a
 * radius) swept along a straight path through the scene, and nodes that collide and slide.
 *   - What collides: visible boxes (their six faces), spheres, cylinders (capped), planes,
 *     mesh triangles (found through the spatial index and each mesh's hierarchy), mirrors
 *     (both sides: mirrors are walls) and closed portals (unpaired, partner hidden, or past
 *     the depth limit: walls like mirrors). Spheres and cylinders collide as the shape of
 *     their largest world scale (exact under uniform scale). Lights, cameras and groups
 *     do not collide.
 *   - Portals: where the body's centre (a capsule's midpoint) passes through an open portal's
 *     rectangle from its front, the sweep goes on from the partner, the path, the radius and
 *     the segment carried by the portal matrix (scaled by unequal portals), up to the
 *     limits' depth (limen_limits, depth fields; zero: each portal's own max_depth).
 *   - HOLES. While the body's centre (a capsule's midpoint; a sliding node's origin) is in
 *     front of an open portal P (paired, partner visible, within the depth limit), the
 *     prism behind P's rectangle (the points behind P's plane, over the rectangle, as deep
 *     as the body reaches from that centre) is not solid for it: the polygons of boxes,
 *     planes, mirrors and meshes that meet it are cut there, so the wall a portal is placed
 *     on (a millimetre in front) does not stop a body entering the opening, while the wall
 *     around the rectangle (the frame) still stops one too wide for it. Spheres and cylinders are never cut. And what lies in front of P's partner Q
 *     within Q's rectangle's prism collides with the body carried through P (the part that
 *     has gone through): polygons cut to that prism, spheres and cylinders where the
 *     contact point lies in it. So a body halfway through collides on both sides. One
 *     level: the carried body is not carried through a second portal.
 *   - A body that already touches a piece (a face, a triangle, a sphere...) where a path or
 *     a stretch of it between portal planes starts collides with it only if it moves
 *     further in (so that it can slide along it or leave it). Colliders stand still during
 *     a sweep (a node moved between sweeps collides where it now is). */
typedef struct limen_sweep_opts {
    limen_node ignore;          /* this node and its descendants do not collide (zero: none) */
    limen_limits limits;        /* depth fields only; zero: each portal's own max_depth */
} limen_sweep_opts;

typedef struct limen_sweep_result {
    int hit;                    /* 1 if the body touches something on its way */
    float fraction;             /* of the path travelled at the contact (1 when no hit) */
    float centre[3];            /* the body's centre there (in the room it has reached) */
    float point[3];             /* the contact point (same room), 0 when no hit */
    float normal[3];            /* unit, from the point towards the centre, 0 when no hit */
    limen_node node;            /* what it touched (zero when no hit) */
    int portals;                /* portals passed before the contact or the end */
    limen_node portal;          /* the last portal passed (zero if none) */
    float matrix[16];           /* product of their matrices (identity if none): carries
                                 * velocities with its 3x3 part */
    float radius;               /* the radius there (unequal portals scale it) */
    float segment[3];           /* capsules: b - a there (portals turn it); 0 for a sphere */
} limen_sweep_result;

/* Sweeps a sphere of the radius from `from` to `to` (world). opts may be NULL. NaN, Inf or
 * coordinates past 1e9, a radius outside [1e-9, 1e9], NULL -> ARG with a message. */
LIMEN_API limen_status limen_sweep_sphere(limen_scene *s, const float from[3], const float to[3],
                                          float radius, const limen_sweep_opts *opts,
                                          limen_sweep_result *out);
/* Sweeps the capsule of segment a-b and the radius by the displacement d (world); its
 * centre is the segment's midpoint. */
LIMEN_API limen_status limen_sweep_capsule(limen_scene *s, const float a[3], const float b[3],
                                           float radius, const float d[3],
                                           const limen_sweep_opts *opts,
                                           limen_sweep_result *out);

typedef struct limen_slide_result {
    float moved[3];             /* the displacement made, in the frame where it began */
    int contacts;               /* contacts met (each turned the rest of the motion) */
    float normal[3];            /* the last contact's normal (its room), 0 if none */
    int crossed;                /* portals passed */
    limen_node portal;          /* the last one (zero if none) */
    float matrix[16];           /* their product (identity if none): carry velocities */
    float radius;               /* the body's radius at the end (unequal portals scale it) */
    float segment[3];           /* capsules: the segment at the end (portals turn it) */
} limen_slide_result;

/* Collide and slide (Fauerby): moves node n by the world displacement d as a sphere of the
 * radius (world units at its current scale) centred on its origin; at a contact it stops a
 * hair short (1e-4 of the radius), removes the rest's part into the contact plane and goes
 * on, at most 5 times. Continuous: no speed tunnels through a wall or skips a portal.
 * Portals carry it as limen_node_move does (position, orientation, scale). n and its
 * descendants do not collide with it. out may be NULL. */
LIMEN_API limen_status limen_node_slide(limen_scene *s, limen_node n, const float d[3],
                                        float radius, limen_slide_result *out);
/* The same for a capsule: the segment from the node's origin to origin + segment (world,
 * e.g. {0, -0.8, 0} from a person's eyes towards the knees) with the radius. Portals are
 * passed by the origin, as limen_node_move passes them, and turn the segment. */
LIMEN_API limen_status limen_node_slide_capsule(limen_scene *s, limen_node n, const float d[3],
                                                float radius, const float segment[3],
                                                limen_slide_result *out);

/* ---------------------------------------------------------------- deprecated names */

/* Names before the naming rule: errors are read with <subject>_error, and a getter paired
 * with a setter is <subject>_get_<property> (what has no setter is read by its noun:
 * limen_node_world_matrix, limen_renderer_plan). These aliases stay for one release. */
#if defined(__GNUC__)
#define LIMEN_DEPRECATED(use) __attribute__((deprecated("use " use)))
#else
#define LIMEN_DEPRECATED(use)
#endif
LIMEN_DEPRECATED("limen_scene_error")
static inline const char *limen_last_error(const limen_scene *s) { return limen_scene_error(s); }
LIMEN_DEPRECATED("limen_node_get_name")
static inline const char *limen_node_name(const limen_scene *s, limen_node n)
{
    return limen_node_get_name(s, n);
}
LIMEN_DEPRECATED("limen_node_get_local_matrix")
static inline limen_status limen_node_local_matrix(limen_scene *s, limen_node n, float m[16])
{
    return limen_node_get_local_matrix(s, n, m);
}
LIMEN_DEPRECATED("limen_portal_get_partner")
static inline limen_node limen_portal_partner(const limen_scene *s, limen_node portal)
{
    return limen_portal_get_partner(s, portal);
}
LIMEN_DEPRECATED("limen_renderer_get_size")
static inline void limen_renderer_size(const limen_renderer *r, int *width, int *height)
{
    limen_renderer_get_size(r, width, height);
}
/* The things of a view before the plan kept them (limen_plan_things, which needs no scene and
 * no buffer): copies up to max of view i's shapes into out and returns how many there are
 * (more than max when out is too small); -1 when there is no view i or out is NULL with
 * max > 0 (the message in s, which may be NULL). */
LIMEN_DEPRECATED("limen_plan_things")
LIMEN_API int limen_plan_view_things(const limen_plan *p, limen_scene *s, int i, limen_node *out,
                                     int max);

#ifdef __cplusplus
}
#endif
#endif /* LIMEN_H */
