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
#include <unistd.h>

#include "core/confine.h"
#include "core/contain.h"
#include "core/internal.h"
#include "core/kinds.h"
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
    /* decided on the descriptor the scene's way in opens (core/confine.c), never by name */
    char why[160];
    int fd = limen__confine_open(s->load ? s->load->box : NULL, path, st, why, sizeof why);
    if (fd < 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot open: %s", path, why);
    close(fd);
    snprintf(key, LIMEN__FILE_KEY, "%s@%llx.%llx.%lld.%ld", path, (unsigned long long)st->st_dev,
             (unsigned long long)st->st_ino, (long long)st->st_mtim.tv_sec,
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

/* One axis of a box filter, n texels onto m <= n: destination i averages the source
 * interval [i n/m, (i + 1) n/m) weighted by overlap (a texel split between two destinations
 * counts to each by its share, as happens at odd sizes). Its first texel, and the weights
 * (at most 4: the interval is at most 3 texels long) of it and those after. */
typedef struct span {
    int first, count;
    double w[4];
} span;

static span span_of(int i, int n, int m)
{
    double r = (double)n / m, a = i * r, b = (i + 1) * r;
    span sp = { .first = (int)floor(a) };
    for (int k = sp.first; k < n && k < b && sp.count < 4; k++) {
        double w = fmin(b, k + 1.0) - fmax(a, (double)k);
        sp.w[sp.count++] = w > 0 ? w / r : 0;
    }
    return sp;
}

static int half(int n)
{
    return n > 1 ? n / 2 : 1;
}

/* Level `down` from level `up` (half its size), a row at a time: memory for one row of the
 * smaller level. */
static void shrink(const limen_image_level *up, const limen_image_level *down, const span *xs,
                   double *acc)
{
    int W = up->width, H = up->height, w = down->width, h = down->height;
    unsigned char *out = (unsigned char *)down->rgb;
    for (int j = 0; j < h; j++) {
        span ys = span_of(j, H, h);
        memset(acc, 0, sizeof(double) * (size_t)w * 3);
        for (int q = 0; q < ys.count; q++) {
            const unsigned char *src = up->rgb + (size_t)(ys.first + q) * (size_t)W * 3;
            for (int i = 0; i < w; i++)
                for (int c = 0; c < 3; c++) {
                    double sum = 0;
                    for (int p = 0; p < xs[i].count; p++)
                        sum += xs[i].w[p] * src[(size_t)(xs[i].first + p) * 3 + (size_t)c];
                    acc[i * 3 + c] += ys.w[q] * sum;
                }
        }
        for (int i = 0; i < w * 3; i++)
            out[(size_t)j * (size_t)w * 3 + (size_t)i] =
                (unsigned char)lrint(fmin(255.0, fmax(0.0, acc[i])));
    }
}

/* Levels 1 on of t, each half the last (at least 1 texel), until 1 x 1: what GL calls a
 * complete mipmap; each made from the bytes of the one above, as a renderer could. False:
 * out of memory. */
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
    int wmax = half(t->w);
    t->mips = malloc(total);
    span *xs = malloc(sizeof *xs * (size_t)wmax);
    double *acc = malloc(sizeof(double) * (size_t)wmax * 3);
    if (!t->mips || !xs || !acc) {
        free(xs);
        free(acc);
        free(t->mips);
        t->mips = NULL;
        return false;
    }
    unsigned char *at = t->mips;
    for (int k = 1; k < n; k++) {
        const limen_image_level *up = &t->levels[k - 1];
        t->levels[k] = (limen_image_level){ half(up->width), half(up->height), at };
        for (int i = 0; i < t->levels[k].width; i++)
            xs[i] = span_of(i, up->width, t->levels[k].width);
        shrink(up, &t->levels[k], xs, acc);
        at += (size_t)t->levels[k].width * (size_t)t->levels[k].height * 3;
    }
    free(xs);
    free(acc);
    return true;
}

/* Why buf is no image stb reads: unknown, truncated or corrupt (stb's reason). */
static void image_failure(const unsigned char *buf, size_t len, char *why, size_t size)
{
    bool png = len >= 4 && memcmp(buf, "\x89PNG", 4) == 0;
    bool jpeg = len >= 2 && buf[0] == 0xFF && buf[1] == 0xD8;
    int w, h;
    if (!png && !jpeg)
        snprintf(why, size, "unknown format (PNG or JPEG only)");
    else if (!limen__image_info(buf, len, &w, &h))
        snprintf(why, size, "truncated or corrupt %s header (%s)", png ? "PNG" : "JPEG",
                 limen__image_why());
    else
        snprintf(why, size, "truncated or corrupt %s data (%s)", png ? "PNG" : "JPEG",
                 limen__image_why());
}

/* A texture of rgb (taken; freed on failure), w x h, with its mipmap levels; NULL when
 * out of memory, *levels (where not NULL) whether it was the levels that found none. */
static limen__texture *texture_of(unsigned char *rgb, int w, int h, const char *name,
                                  bool *levels)
{
    limen__texture *t = calloc(1, sizeof *t);
    if (levels)
        *levels = t != NULL;
    if (!t) {
        free(rgb);
        return NULL;
    }
    t->w = w;
    t->h = h;
    t->rgb = rgb;
    if (!make_levels(t)) {
        texture_free(t);
        return NULL;
    }
    /* the levels add a third at most */
    t->bytes = sizeof *t + (size_t)w * (size_t)h * 3 + (size_t)w * (size_t)h;
    t->serial = limen__next_serial();
    t->pub = (limen_image){ .id = t->serial, .width = w, .height = h, .rgb = rgb,
                            .level_count = t->nlevels, .levels = t->levels };
    t->refs = 1;
    snprintf(t->name, sizeof t->name, "%s", name);
    return t;
}

static limen_status texture_new(limen_scene *s, unsigned char *rgb, int w, int h,
                                const char *name, limen__texture **out)
{
    bool levels;
    *out = texture_of(rgb, w, h, name, &levels);
    if (!*out)
        return limen__fail(s, LIMEN_ERR_NOMEM, levels ? "%s: out of memory for its mipmap "
                           "levels" : "%s: out of memory", name);
    return LIMEN_OK;
}

/* In the worker: the job is the file's bytes; the answer [w][h][rgb], or why not. */
static int decode_job(limen__block *job, int fd, limen__block *out, char *why, size_t why_size)
{
    (void)fd;
    int w = 0, h = 0;
    unsigned char *rgb = limen__image_decode(job->data, job->len, &w, &h);
    if (!rgb) {
        image_failure(job->data, job->len, why, why_size);
        return 1;
    }
    int32_t wh[2] = { w, h };
    limen__block_put(out, wh, sizeof wh);
    limen__block_put(out, rgb, (size_t)w * (size_t)h * 3);
    free(rgb);
    return 0;
}

/* Decodes buf in a child under what the script has left; a crash or a limit is a message. */
static unsigned char *decode_in_child(limen_scene *s, const unsigned char *buf, size_t len,
                                      const char *name, int *w, int *h, limen_status *st)
{
    limen__load *ld = s->load;
    limen__block job = { (unsigned char *)buf, len, len, 0, false };   /* read, never freed */
    limen__contain_limits lim = { ld->max_bytes, ld->cpu_left, 0 };
    limen__block b;
    char why[512];
    double cpu;
    int rc = limen__contain_job(decode_job, &job, -1, &lim, &b, why, sizeof why, &cpu);
    ld->cpu_spent += cpu;
    ld->cpu_left = ld->cpu_left > 0 ? (ld->cpu_left > cpu ? ld->cpu_left - cpu : 1e-9) : 0;
    int32_t wh[2];
    const unsigned char *rgb = NULL;
    if (rc == LIMEN__CONTAIN_OK && limen__block_get(&b, wh, sizeof wh) && wh[0] > 0 &&
        wh[1] > 0 && wh[0] <= MAX_SIDE && wh[1] <= MAX_SIDE)
        rgb = limen__block_take(&b, (size_t)wh[0] * (size_t)wh[1] * 3);
    if (!rgb) {
        limen__block_free(&b);
        *st = rc == LIMEN__CONTAIN_FAILED
                  ? limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as an image: %s", name, why)
              : rc == LIMEN__CONTAIN_TIME
                  ? limen__fail(s, LIMEN_ERR_IO, "%s: decoding it ran out of the time left", name)
              : rc == LIMEN__CONTAIN_SYSTEM
                  ? limen__fail(s, LIMEN_ERR_IO, "%s: %s", name, why)
                  : limen__fail(s, LIMEN_ERR_NOMEM, "the image decoder crashed or ran out of "
                                "memory reading %s", name);
        return NULL;
    }
    unsigned char *copy = malloc((size_t)wh[0] * (size_t)wh[1] * 3);
    if (copy)
        memcpy(copy, rgb, (size_t)wh[0] * (size_t)wh[1] * 3);
    limen__block_free(&b);
    if (!copy) {
        *st = limen__fail(s, LIMEN_ERR_NOMEM, "%s: out of memory", name);
        return NULL;
    }
    *w = wh[0];
    *h = wh[1];
    return copy;
}

limen_status limen__texture_decode(limen_scene *s, const unsigned char *buf, size_t len,
                                   const char *name, limen__texture **out)
{
    *out = NULL;
    int w = 0, h = 0;
    bool png = len >= 4 && memcmp(buf, "\x89PNG", 4) == 0;
    bool jpeg = len >= 2 && buf[0] == 0xFF && buf[1] == 0xD8;
    char why[300];
    if (!png && !jpeg) {
        image_failure(buf, len, why, sizeof why);
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as an image: %s", name, why);
    }
    /* the size from the header, before anything is decoded */
    if (limen__image_info(buf, len, &w, &h)) {
        if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE)
            return limen__fail(s, LIMEN_ERR_ARG, "%s: too large: %dx%d pixels (1 to %d a side)",
                               name, w, h, MAX_SIDE);
        size_t max = s->load ? s->load->max_bytes : SIZE_MAX;
        if ((uint64_t)w * (uint64_t)h * 3 > max)
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: too large: %dx%d pixels need %.1f MiB, "
                               "more than the %.1f MiB allowed", name, w, h,
                               (double)w * h * 3 / 1048576.0, max / 1048576.0);
    }
    unsigned char *rgb;
    if (limen__load_contained(s)) {
        limen_status st = LIMEN_OK;
        if (!(rgb = decode_in_child(s, buf, len, name, &w, &h, &st)))
            return st;
    } else if (!(rgb = limen__image_decode(buf, len, &w, &h))) {
        image_failure(buf, len, why, sizeof why);
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot read it as an image: %s", name, why);
    }
    if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE) {
        free(rgb);
        return limen__fail(s, LIMEN_ERR_ARG, "%s: too large: %dx%d pixels (1 to %d a side)",
                           name, w, h, MAX_SIDE);
    }
    return texture_new(s, rgb, w, h, name, out);
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

limen__texture *limen__texture_own(unsigned char *rgb, int w, int h, const char *name)
{
    return texture_of(rgb, w, h, name, NULL);
}

void limen__texture_free(limen__texture *t)
{
    texture_free(t);
}

static limen_status keep(limen_scene *s, limen__texture *t)
{
    if (limen__assets_add(&s->textures, &s->ntextures, &s->texture_cap, t))
        return LIMEN_OK;
    texture_free(t);
    return limen__fail(s, LIMEN_ERR_NOMEM, "texture: out of memory");
}

#define HEAD_BYTES (64u << 10)

/* An image's size from the first 64 KiB of its file, where they say it (every format read
 * here does, but a JPEG with more metadata than that before its frame): so that an image too
 * large is refused having read its header, not the file. */
static bool head_size(limen_scene *s, const char *path, int *w, int *h)
{
    char why[160];
    struct stat st;
    int fd = limen__confine_open(s->load ? s->load->box : NULL, path, &st, why, sizeof why);
    if (fd < 0)
        return false;
    size_t n = (uint64_t)st.st_size < HEAD_BYTES ? (size_t)st.st_size : HEAD_BYTES;
    unsigned char *head = malloc(n ? n : 1);
    bool known = head && limen__read_at(fd, head, n, 0) && limen__image_info(head, n, w, h);
    free(head);
    close(fd);
    return known;
}

static limen_status too_large(limen_scene *s, const char *path, int w, int h, size_t max_bytes)
{
    s->mem_wanted = (uint64_t)w * (uint64_t)h * 3;
    return limen__fail(s, LIMEN_ERR_NOMEM, "%s: too large: %dx%d pixels need %.1f MiB, more "
                       "than the %.1f MiB allowed", path, w, h, (double)w * h * 3 / 1048576.0,
                       max_bytes / 1048576.0);
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
    int w, h;
    if (head_size(s, path, &w, &h) && (uint64_t)w * (uint64_t)h * 3 > max_bytes)
        return too_large(s, path, w, h, max_bytes);
    unsigned char *buf;
    size_t got;
    if ((rc = limen__file_read(s, path, &buf, &got, &st))) {
        if (rc == LIMEN_ERR_NOMEM)
            s->mem_wanted = (uint64_t)st.st_size;   /* what --memory would allow */
        return rc;
    }
    if (limen__image_info(buf, got, &w, &h) && (uint64_t)w * (uint64_t)h * 3 > max_bytes) {
        free(buf);
        if (s->load)
            s->load->read_bytes -= got;
        return too_large(s, path, w, h, max_bytes);
    }
    size_t keep_max = s->load ? s->load->max_bytes : SIZE_MAX;
    if (s->load)
        s->load->max_bytes = max_bytes;     /* what decoding may take */
    limen__texture *t;
    rc = limen__texture_decode(s, buf, got, path, &t);
    free(buf);
    if (s->load) {
        s->load->max_bytes = keep_max;
        s->load->read_bytes -= got;     /* the file's bytes are given back */
    }
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
    limen__node *node;
    limen_status found = limen__node_lookup(s, n, 0, NULL, "texture", &node);
    if (found)
        return found;
    if (limen_kind_get(node->kind)->uv == LIMEN_UV_NONE)
        return limen__fail(s, LIMEN_ERR_HANDLE, "texture: '%s' is a %s, which takes no texture",
                           limen__node_title(node), limen__kind_name(node->kind));
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
        const limen__mesh *m = k < s->nmeshes ? s->meshes[k] : NULL;
        const char *key = m ? m->key : ((const limen__texture *)s->textures[k - s->nmeshes])->key;
        size_t len;
        if (!key_path(key, &len))
            continue;
        /* the file itself, then the others its import read (an OBJ's .mtl, glTF buffers) */
        const char *f = key;
        for (size_t at = 0;;) {
            size_t flen = f == key ? len : strlen(f);
            if ((f == key || flen != len || strncmp(f, key, len) != 0) && n++ == i) {
                if (flen >= size)
                    return LIMEN_ERR_ARG;
                memcpy(path, f, flen);
                path[flen] = '\0';
                return LIMEN_OK;
            }
            if (f != key)
                at += flen + 1;
            if (!m || !m->files || at >= m->files_len)
                break;
            f = m->files + at;
        }
    }
    return LIMEN_ERR_ARG;
}
