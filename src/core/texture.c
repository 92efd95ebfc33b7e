/* texture.c - image files on quads, boxes and meshes: albedo = texel * colour. One copy per
 * scene of each file, however many nodes show it, with its mipmap levels made here (box
 * filtered, rounded to bytes), so that the renderer uploads exactly the texels the tracer
 * reads. Sampling (limen__texture_filter) is the ray tracer's half of the contract; the
 * renderer's is GL_LINEAR_MIPMAP_LINEAR (or GL_LINEAR, GL_NEAREST) with GL_REPEAT over the
 * same levels. */
#include <errno.h>
#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/mesh.h"
#include "core/texture.h"

#define MAX_SIDE 16384

/* Asset serials are unique in the process, so that a renderer drawing several scenes never
 * takes one scene's texture or mesh for another's. */
uint64_t limen__next_serial(void)
{
    static _Atomic uint64_t next = 1;
    return atomic_fetch_add(&next, 1);
}

limen_status limen__file_key(limen_scene *s, const char *path, char key[LIMEN__FILE_KEY],
                             struct stat *st)
{
    char real[PATH_MAX];
    if (!realpath(path, real) || stat(real, st) != 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(st->st_mode))
        return limen__fail(s, LIMEN_ERR_IO, "%s: not a regular file", path);
    snprintf(key, LIMEN__FILE_KEY, "%s@%lld.%ld", real, (long long)st->st_mtim.tv_sec,
             (long)st->st_mtim.tv_nsec);
    return LIMEN_OK;
}

static void texture_free(limen__texture *t)
{
    if (!t)
        return;
    free(t->rgb);
    free(t->alpha);
    free(t->mips);
    free(t);
}

/* ------------------------------------------------------------------ mipmap levels */

/* One axis of a box filter: n source samples (stride apart) onto m <= n, destination i
 * averaging the source interval [i n/m, (i + 1) n/m) weighted by overlap (a texel split
 * between two destinations counts half to each, as happens at odd sizes). */
static void shrink_axis(const float *src, int n, size_t stride, float *dst, int m,
                        size_t dstride)
{
    double r = (double)n / m;
    for (int i = 0; i < m; i++) {
        double a = i * r, b = (i + 1) * r, sum = 0;
        for (int k = (int)floor(a); k < n && k < b; k++) {
            double w = fmin(b, k + 1.0) - fmax(a, (double)k);
            if (w > 0)
                sum += w * src[(size_t)k * stride];
        }
        dst[(size_t)i * dstride] = (float)(sum / r);
    }
}

static int half(int n)
{
    return n > 1 ? n / 2 : 1;
}

/* Levels 1 on of t, each half the last (at least 1 texel), until 1 x 1: what GL calls a
 * complete mipmap. False: out of memory. */
static bool make_levels(limen__texture *t)
{
    size_t total = 0;
    int n = 1;
    for (int w = t->w, h = t->h; w > 1 || h > 1; n++) {
        w = half(w);
        h = half(h);
        total += (size_t)w * (size_t)h * 3;
    }
    t->levels[0] = (limen_image_level){ t->w, t->h, t->rgb };
    t->nlevels = n;
    if (n == 1)
        return true;
    t->mips = malloc(total);
    float *row = malloc(sizeof(float) * (size_t)t->w * (size_t)t->h * 3);
    float *col = malloc(sizeof(float) * (size_t)t->h * (size_t)t->w * 3);
    if (!t->mips || !row || !col) {
        free(row);
        free(col);
        free(t->mips);
        t->mips = NULL;
        return false;
    }
    unsigned char *at = t->mips;
    for (int k = 1; k < n; k++) {
        const limen_image_level *up = &t->levels[k - 1];
        int w = half(up->width), h = half(up->height), W = up->width, H = up->height;
        /* each level from the bytes of the one above, as the renderer could */
        for (size_t i = 0; i < (size_t)W * H * 3; i++)
            col[i] = up->rgb[i];
        for (int y = 0; y < H; y++)
            for (int c = 0; c < 3; c++)
                shrink_axis(col + (size_t)y * W * 3 + c, W, 3, row + (size_t)y * w * 3 + c, w, 3);
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                shrink_axis(row + (size_t)x * 3 + c, H, (size_t)w * 3, col + (size_t)x * 3 + c,
                            h, (size_t)w * 3);
        for (size_t i = 0; i < (size_t)w * h * 3; i++)
            at[i] = (unsigned char)lrint(fmin(255.0, fmax(0.0, col[i])));
        t->levels[k] = (limen_image_level){ w, h, at };
        at += (size_t)w * h * 3;
    }
    free(row);
    free(col);
    return true;
}

limen_status limen__texture_decode(limen_scene *s, const unsigned char *buf, size_t len,
                                   const char *name, limen__texture **out)
{
    *out = NULL;
    int w = 0, h = 0;
    unsigned char *rgb = limen__image_decode(buf, len, &w, &h);
    if (!rgb)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as an image (PNG or JPEG): %s",
                           name, limen__image_why());
    if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE) {
        free(rgb);
        return limen__fail(s, LIMEN_ERR_ARG, "%s: %dx%d pixels (1 to %d a side)", name, w, h,
                           MAX_SIDE);
    }
    limen__texture *t = calloc(1, sizeof *t);
    if (!t) {
        free(rgb);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", name);
    }
    t->w = w;
    t->h = h;
    t->rgb = rgb;
    if (!make_levels(t)) {
        texture_free(t);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory for its mipmap levels", name);
    }
    /* the levels add a third at most */
    t->bytes = sizeof *t + (size_t)w * (size_t)h * 3 + (size_t)w * (size_t)h;
    t->serial = limen__next_serial();
    t->pub = (limen_image){ .id = t->serial, .width = w, .height = h, .rgb = rgb,
                            .level_count = t->nlevels, .levels = t->levels };
    t->refs = 1;
    snprintf(t->name, sizeof t->name, "%s", name);
    *out = t;
    return LIMEN_OK;
}

limen_status limen__texture_from_rgba(limen_scene *s, const unsigned char *rgba, int w, int h,
                                      const char *name, limen__texture **out)
{
    *out = NULL;
    size_t n = (size_t)w * (size_t)h;
    bool opaque = true;
    for (size_t i = 0; i < n && opaque; i++)
        opaque = rgba[i * 4 + 3] == 255;
    limen__texture *t = calloc(1, sizeof *t);
    unsigned char *rgb = malloc(n * 3), *alpha = opaque ? NULL : malloc(n);
    if (!t || !rgb || (!opaque && !alpha)) {
        free(t);
        free(rgb);
        free(alpha);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", name);
    }
    for (size_t i = 0; i < n; i++) {
        memcpy(rgb + i * 3, rgba + i * 4, 3);
        if (alpha)
            alpha[i] = rgba[i * 4 + 3];
    }
    t->w = w;
    t->h = h;
    t->rgb = rgb;
    t->alpha = alpha;
    /* mipmap levels for an opaque image; one with alpha keeps only its own (its alpha has
     * no levels: the renderer and the tracer both sample the full image) */
    t->levels[0] = (limen_image_level){ w, h, rgb };
    t->nlevels = 1;
    if (!alpha && !make_levels(t)) {
        texture_free(t);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory for its mipmap levels", name);
    }
    t->bytes = sizeof *t + n * (alpha ? 4 : 3) + (alpha ? 0 : n);
    t->serial = limen__next_serial();
    t->pub = (limen_image){ .id = t->serial, .width = w, .height = h, .rgb = rgb, .alpha = alpha,
                            .level_count = t->nlevels, .levels = t->levels };
    t->refs = 1;
    snprintf(t->name, sizeof t->name, "%s", name);
    *out = t;
    return LIMEN_OK;
}

static limen_status keep(limen_scene *s, limen__texture *t)
{
    if (limen__assets_add(&s->textures, &s->ntextures, &s->texture_cap, t))
        return LIMEN_OK;
    texture_free(t);
    return limen__fail(s, LIMEN_ERR_NOMEM, "texture: out of memory");
}

limen_status limen__texture_load(limen_scene *s, const char *path, size_t max_bytes,
                                 size_t *charged, limen__texture **out)
{
    *out = NULL;
    *charged = 0;
    char key[LIMEN__FILE_KEY];
    struct stat st;
    limen_status rc = limen__file_key(s, path, key, &st);
    if (rc)
        return rc;
    for (int i = 0; i < s->ntextures; i++) {
        limen__texture *t = s->textures[i];
        if (strcmp(t->key, key) == 0) {
            t->refs++;
            *out = t;
            return LIMEN_OK;
        }
    }
    if (st.st_size == 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: empty file", path);
    if ((uint64_t)st.st_size > max_bytes && (s->mem_wanted = (uint64_t)st.st_size))
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: a file of %.1f MiB, more than the %.1f MiB "
                           "allowed", path, st.st_size / 1048576.0, max_bytes / 1048576.0);
    FILE *f = fopen(path, "rb");
    unsigned char *buf = f ? malloc((size_t)st.st_size) : NULL;
    size_t got = buf ? fread(buf, 1, (size_t)st.st_size, f) : 0;
    if (f)
        fclose(f);
    if (!buf || got != (size_t)st.st_size) {
        free(buf);
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot read: %s", path,
                           f ? "short read" : strerror(errno));
    }
    /* the decoded size, from the header, before decoding */
    int w, h;
    if (limen__image_info(buf, got, &w, &h) && (uint64_t)w * (uint64_t)h * 3 > max_bytes) {
        s->mem_wanted = (uint64_t)w * (uint64_t)h * 3;
        free(buf);
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: %dx%d pixels need %.1f MiB, more than the "
                           "%.1f MiB allowed", path, w, h, (double)w * h * 3 / 1048576.0,
                           max_bytes / 1048576.0);
    }
    limen__texture *t;
    rc = limen__texture_decode(s, buf, got, path, &t);
    free(buf);
    if (rc)
        return rc;
    snprintf(t->key, sizeof t->key, "%s", key);
    if ((rc = keep(s, t)))
        return rc;
    *charged = t->bytes;
    *out = t;
    return LIMEN_OK;
}

void limen__texture_release(limen_scene *s, limen__texture *t)
{
    if (!t || --t->refs > 0)
        return;
    limen__assets_remove(s->textures, &s->ntextures, t);
    texture_free(t);
}

void limen__textures_destroy(limen_scene *s)
{
    for (int i = 0; i < s->ntextures; i++)
        texture_free(s->textures[i]);
    free(s->textures);
    s->textures = NULL;
    s->ntextures = s->texture_cap = 0;
}

static int wrap(long i, int n)
{
    long m = i % n;
    return (int)(m < 0 ? m + n : m);
}

/* Bilinear in one level, repeating. */
static void bilinear(const limen_image_level *l, double u, double v, double out[3])
{
    double x = u * l->width - 0.5, y = v * l->height - 0.5;
    if (!isfinite(x) || !isfinite(y) || fabs(x) > 1e15 || fabs(y) > 1e15)
        x = y = 0;
    double fx0 = floor(x), fy0 = floor(y);
    double fx = x - fx0, fy = y - fy0;
    int i0 = wrap((long)fx0, l->width), i1 = wrap((long)fx0 + 1, l->width);
    int j0 = wrap((long)fy0, l->height), j1 = wrap((long)fy0 + 1, l->height);
    /* j counts rows from the bottom; the image is stored top row first */
    const unsigned char *r0 = l->rgb + (size_t)(l->height - 1 - j0) * (size_t)l->width * 3;
    const unsigned char *r1 = l->rgb + (size_t)(l->height - 1 - j1) * (size_t)l->width * 3;
    for (int k = 0; k < 3; k++) {
        double a = r0[i0 * 3 + k] + fx * (r0[i1 * 3 + k] - r0[i0 * 3 + k]);
        double b = r1[i0 * 3 + k] + fx * (r1[i1 * 3 + k] - r1[i0 * 3 + k]);
        out[k] = (a + fy * (b - a)) / 255.0;
    }
}

/* The texel that holds (u, v), repeating. */
static void nearest_texel(const limen_image_level *l, double u, double v, double out[3])
{
    double x = floor(u * l->width), y = floor(v * l->height);
    if (!isfinite(x) || !isfinite(y) || fabs(x) > 1e15 || fabs(y) > 1e15)
        x = y = 0;
    int i = wrap((long)x, l->width), j = wrap((long)y, l->height);
    const unsigned char *p = l->rgb + ((size_t)(l->height - 1 - j) * (size_t)l->width + i) * 3;
    for (int k = 0; k < 3; k++)
        out[k] = p[k] / 255.0;
}

void limen__texture_sample(const limen__texture *t, double u, double v, double out[3])
{
    bilinear(&t->levels[0], u, v, out);
}

double limen__texture_lod(const limen__texture *t, const double duv[4])
{
    double ax = duv[0] * t->w, ay = duv[1] * t->h, bx = duv[2] * t->w, by = duv[3] * t->h;
    double rho2 = fmax(ax * ax + ay * ay, bx * bx + by * by);
    if (!isfinite(rho2))
        return INFINITY;
    return rho2 > 0 ? 0.5 * log2(rho2) : -INFINITY;
}

void limen__texture_filter(const limen__texture *t, limen_texture_filter f, double u, double v,
                           const double duv[4], double out[3])
{
    if (f == LIMEN_FILTER_NEAREST) {
        nearest_texel(&t->levels[0], u, v, out);
        return;
    }
    double lod = f == LIMEN_FILTER_TRILINEAR && duv ? limen__texture_lod(t, duv) : 0;
    /* magnified (lod <= 0): the full image; past the last level: the last */
    int last = t->nlevels - 1;
    if (!(lod > 0)) {
        bilinear(&t->levels[0], u, v, out);
        return;
    }
    if (lod >= last) {
        bilinear(&t->levels[last], u, v, out);
        return;
    }
    int a = (int)floor(lod);
    double fr = lod - a, lo[3], hi[3];
    bilinear(&t->levels[a], u, v, lo);
    bilinear(&t->levels[a + 1], u, v, hi);
    for (int k = 0; k < 3; k++)
        out[k] = lo[k] + fr * (hi[k] - lo[k]);
}

double limen__texture_sample_alpha(const limen__texture *t, double u, double v)
{
    if (!t || !t->alpha)
        return 1.0;
    double x = u * t->w - 0.5, y = v * t->h - 0.5;
    if (!isfinite(x) || !isfinite(y) || fabs(x) > 1e15 || fabs(y) > 1e15)
        x = y = 0;
    double fx0 = floor(x), fy0 = floor(y);
    double fx = x - fx0, fy = y - fy0;
    int i0 = wrap((long)fx0, t->w), i1 = wrap((long)fx0 + 1, t->w);
    int j0 = wrap((long)fy0, t->h), j1 = wrap((long)fy0 + 1, t->h);
    const unsigned char *r0 = t->alpha + (size_t)(t->h - 1 - j0) * (size_t)t->w;
    const unsigned char *r1 = t->alpha + (size_t)(t->h - 1 - j1) * (size_t)t->w;
    double a = r0[i0] + fx * (r0[i1] - r0[i0]);
    double b = r1[i0] + fx * (r1[i1] - r1[i0]);
    return (a + fy * (b - a)) / 255.0;
}

/* ------------------------------------------------------------------ API */

limen_status limen__node_texture(limen_scene *s, limen_node n, const char *path,
                                 size_t max_bytes, size_t *charged)
{
    *charged = 0;
    limen__node *node = limen__node_get(s, n);
    if (!node)
        return limen__fail(s, LIMEN_ERR_HANDLE, "texture: %s node handle",
                           n.id ? "stale or foreign" : "null");
    if (node->kind != LIMEN_NODE_QUAD && node->kind != LIMEN_NODE_BOX &&
        node->kind != LIMEN_NODE_MESH)
        return limen__fail(s, LIMEN_ERR_HANDLE, "texture: '%s' is not a plane, box or mesh",
                           limen__node_title(node));
    limen__texture *t = NULL;
    if (path) {
        limen_status st = limen__texture_load(s, path, max_bytes, charged, &t);
        if (st)
            return st;
    }
    limen__texture_release(s, node->texture);
    node->texture = t;
    return LIMEN_OK;
}

limen_status limen_node_set_texture(limen_scene *s, limen_node n, const char *path)
{
    if (!s)
        return LIMEN_ERR_ARG;
    size_t charged;
    return limen__node_texture(s, n, path, SIZE_MAX, &charged);
}

/* ------------------------------------------------------------------ the files behind assets */

/* The path part of a file key ("path@seconds.nanoseconds"), or NULL for an asset that came
 * from no file of its own; *len its length. */
static const char *key_path(const char *key, size_t *len)
{
    const char *at = strrchr(key, '@');
    if (!key[0] || !at)
        return NULL;
    *len = (size_t)(at - key);
    return key;
}

limen_status limen_scene_get_file(const limen_scene *s, int i, char *path, size_t size)
{
    if (!s || !path || i < 0)
        return LIMEN_ERR_ARG;
    int n = 0;
    for (int k = 0; k < s->nmeshes + s->ntextures; k++) {
        const char *key = k < s->nmeshes ? ((const limen__mesh *)s->meshes[k])->key
                                         : ((const limen__texture *)s->textures[k - s->nmeshes])->key;
        size_t len;
        if (!key_path(key, &len) || n++ != i)
            continue;
        if (len >= size)
            return LIMEN_ERR_ARG;
        memcpy(path, key, len);
        path[len] = '\0';
        return LIMEN_OK;
    }
    return LIMEN_ERR_ARG;
}
