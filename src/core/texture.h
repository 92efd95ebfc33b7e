/* texture.h - images on surfaces: decoded once per scene (shared by the nodes and meshes that
 * use the same file) and sampled the same way by the ray tracer and by OpenGL. Not part of
 * the public API. */
#ifndef LIMEN_CORE_TEXTURE_H
#define LIMEN_CORE_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "limen.h"

#define LIMEN__FILE_KEY_SIZE 4160
#define LIMEN__MAX_LEVELS 16     /* mipmap levels of a 16384-texel side, and one spare */

typedef struct limen__texture {
    int refs;                   /* nodes and meshes using it */
    char key[LIMEN__FILE_KEY_SIZE];  /* limen__file_key, or "" */
    char name[512];             /* the path as given, for messages */
    int w, h;
    unsigned char *rgb;         /* w * h * 3, top row first (as the file) */
    unsigned char *alpha;       /* w * h, or NULL: opaque (a model's own textures) */
    unsigned char *mips;        /* levels 1 on, one block (limen__texture_levels) */
    int nlevels;                /* levels[0] is rgb itself */
    limen_image_level levels[LIMEN__MAX_LEVELS];
    size_t bytes;
    uint64_t serial;            /* unique in the process: the renderer keys its copy on it */
    limen_image pub;            /* what limen_drawable.texture shows of it */
} limen__texture;

/* Loads an image file (PNG or JPEG), or finds it already loaded in the scene, with a new
 * reference; refuses one that would hold more than max_bytes. *charged: bytes newly held. */
limen_status limen__texture_load(limen_scene *s, const char *path, size_t max_bytes,
                                 size_t *charged, limen__texture **out);
/* An image held in memory (a mesh file's embedded texture), not shared. */
limen_status limen__texture_decode(limen_scene *s, const unsigned char *buf, size_t len,
                                   const char *name, limen__texture **out);
/* A model's texture from decoded RGBA8 texels (core/import.h), not shared; the alpha plane
 * is kept only where some texel is not opaque. */
limen_status limen__texture_from_rgba(limen_scene *s, const unsigned char *rgba, int w, int h,
                                      const char *name, limen__texture **out);
void limen__texture_release(limen_scene *s, limen__texture *t);
/* A texture of rgb (w * h * 3, top row first; taken, freed on failure) with its mipmap
 * levels, held by no scene (a baked level's: core/lod_bake.c), which limen__texture_free
 * frees; NULL when out of memory. */
limen__texture *limen__texture_own(unsigned char *rgb, int w, int h, const char *name);
void limen__texture_free(limen__texture *t);
void limen__textures_destroy(limen_scene *s);
/* Bilinear, repeating, in the full image, texel centres at ((i + 0.5) / w, (j + 0.5) / h)
 * with v from the bottom row up: what GL_LINEAR with GL_REPEAT does. In [0, 1]. */
void limen__texture_sample(const limen__texture *t, double u, double v, double out[3]);
/* The level of detail OpenGL picks for a pixel whose texture coordinates change by
 * duv = (du/dx, dv/dx, du/dy, dv/dy) from one pixel to the next: log2 of the longer of the
 * two steps measured in texels of the full image; +inf where they are not finite. */
double limen__texture_lod(const limen__texture *t, const double duv[4]);
/* Sampling as limen_texture_filter says (GL_NEAREST, GL_LINEAR, or GL_LINEAR_MIPMAP_LINEAR
 * over t's levels at limen__texture_lod's level); duv NULL: the full image (level 0). */
void limen__texture_filter(const limen__texture *t, limen_texture_filter f, double u, double v,
                           const double duv[4], double out[3]);

/* The alpha plane, sampled as limen__texture_sample samples colour; 1 where there is none. */
double limen__texture_sample_alpha(const limen__texture *t, double u, double v);

/* image.c: stb_image on a buffer (RGB), and why it failed. */
unsigned char *limen__image_decode(const unsigned char *buf, size_t len, int *w, int *h);
const char *limen__image_why(void);
/* The same, RGBA (every format stb reads; HDR clamped to [0, 1] linearly). */
unsigned char *limen__image_decode_rgba(const unsigned char *buf, size_t len, int *w, int *h);
/* Size from the header alone; false if it is not an image stb reads. */
bool limen__image_info(const unsigned char *buf, size_t len, int *w, int *h);

/* A file's identity for sharing: its resolved path and modification time (a file changed
 * since it was read is read again). Fails, naming the path, if it is not a regular file. */
#define LIMEN__FILE_KEY LIMEN__FILE_KEY_SIZE
struct stat;
limen_status limen__file_key(limen_scene *s, const char *path, char key[LIMEN__FILE_KEY],
                             struct stat *st);
/* A serial number unique in the process (textures and meshes). */
uint64_t limen__next_serial(void);
/* Sets (path) or clears (NULL) a node's texture; as limen__texture_load. */
limen_status limen__node_texture(limen_scene *s, limen_node n, const char *path,
                                 size_t max_bytes, size_t *charged);

/* The bytes the last mesh or texture load refused for the memory allowed would have taken
 * (0 if none was), and forgets them: a script host turns them into the cap that would do. */
uint64_t limen__scene_take_wanted(limen_scene *s);

#endif
