/* image.c - PNG in and out, JPEG out (stb_image, stb_image_write) and image comparison. */
#include <limits.h>
#include <pthread.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
/* every format stb_image reads (PNG, JPEG, TGA, BMP, PSD, GIF, HDR, PIC, PNM): model files
 * name textures in all of them */
#include "core/stb_quiet.h"
LIMEN__STB_BEGIN
#include <stb_image.h>
LIMEN__STB_END

#include "core/internal.h"
#include "core/texture.h"
#include "core/stb_write.h"
#include <string.h>
#include <strings.h>

#define LIMEN__JPEG_QUALITY 95

limen_status limen_write_png(const char *path, int width, int height, const unsigned char *rgb)
{
    if (!path || !rgb || width <= 0 || height <= 0 || width > INT_MAX / 3 / height)
        return LIMEN_ERR_ARG;
    limen__out o;
    limen_status st = limen__out_open(&o, path);
    if (st)
        return st;
    if (!stbi_write_png_to_func(limen__stb_to_file, o.f, width, height, 3, rgb, width * 3)) {
        limen__out_abort(&o);
        return LIMEN_ERR_IO;
    }
    return limen__out_close(&o);
}

/* PNG chunks with a zero-length IDAT left out: they hold no data, and stb_image copies
 * zero bytes to a NULL buffer for one that comes first (undefined behaviour). Anything
 * that is not a well-formed chunk sequence is passed on as it is, for stb to refuse. */
static size_t drop_empty_idat(unsigned char *buf, size_t len)
{
    static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    if (len < 8 || memcmp(buf, sig, 8) != 0)
        return len;
    size_t in = 8, out = 8;
    while (len - in >= 12) {
        size_t n = (size_t)buf[in] << 24 | (size_t)buf[in + 1] << 16 |
                   (size_t)buf[in + 2] << 8 | buf[in + 3];
        if (n > len - in - 12)
            break;
        size_t whole = n + 12;
        if (!(n == 0 && memcmp(buf + in + 4, "IDAT", 4) == 0)) {
            memmove(buf + out, buf + in, whole);
            out += whole;
        }
        in += whole;
    }
    memmove(buf + out, buf + in, len - in);
    return out + (len - in);
}

limen_status limen__png_decode(unsigned char *buf, size_t len, int *width, int *height,
                               unsigned char **rgb)
{
    *rgb = NULL;
    *width = *height = 0;
    if (len > INT_MAX)
        return LIMEN_ERR_ARG;
    len = drop_empty_idat(buf, len);
    int w = 0, h = 0, n = 0;
    if (!stbi_info_from_memory(buf, (int)len, &w, &h, &n))
        return LIMEN_ERR_IO;
    if (w <= 0 || h <= 0 || (long long)w * h > LIMEN_IMAGE_MAX_PIXELS)
        return LIMEN_ERR_ARG;   /* refused from the header, before any decoding */
    unsigned char *data = stbi_load_from_memory(buf, (int)len, &w, &h, &n, 3);
    if (!data)
        return LIMEN_ERR_IO;
    *width = w;
    *height = h;
    *rgb = data;
    return LIMEN_OK;
}

/* Case-insensitive: does path end in ext (".png")? */
static bool ends_with(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n > k && strcasecmp(path + n - k, ext) == 0;
}

limen_status limen_write_image(const char *path, int width, int height, const unsigned char *rgb)
{
    if (!path || !rgb || width <= 0 || height <= 0 || width > INT_MAX / 3 / height)
        return LIMEN_ERR_ARG;
    if (ends_with(path, ".png"))
        return limen_write_png(path, width, height, rgb);
    if (!ends_with(path, ".jpg") && !ends_with(path, ".jpeg"))
        return LIMEN_ERR_ARG;
    return limen__write_jpeg(path, width, height, rgb, LIMEN__JPEG_QUALITY);
}

limen_status limen_read_png(const char *path, int *width, int *height, unsigned char **rgb)
{
    if (!path || !width || !height || !rgb)
        return LIMEN_ERR_ARG;
    *rgb = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return LIMEN_ERR_IO;
    /* the whole file in memory (a PNG is compressed: a file as large as the largest image
     * allowed uncompressed is surely not one) */
    size_t cap = 1 << 16, len = 0;
    unsigned char *buf = malloc(cap);
    limen_status st = buf ? LIMEN_OK : LIMEN_ERR_NOMEM;
    while (!st) {
        if (len == cap) {
            if (cap >= (size_t)LIMEN_IMAGE_MAX_PIXELS * 3) {
                st = LIMEN_ERR_ARG;
                break;
            }
            unsigned char *more = realloc(buf, cap * 2);
            if (!more) {
                st = LIMEN_ERR_NOMEM;
                break;
            }
            buf = more;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            if (ferror(f))
                st = LIMEN_ERR_IO;
            break;
        }
    }
    fclose(f);
    if (!st)
        st = limen__png_decode(buf, len, width, height, rgb);
    free(buf);
    return st;
}

unsigned char *limen__image_decode(const unsigned char *buf, size_t len, int *w, int *h)
{
    int n = 0;
    if (len > INT_MAX)
        return NULL;
    return stbi_load_from_memory(buf, (int)len, w, h, &n, 3);
}

static void hdr_linear(void)
{
    stbi_hdr_to_ldr_gamma(1.0f);
    stbi_hdr_to_ldr_scale(1.0f);
}

unsigned char *limen__image_decode_rgba(const unsigned char *buf, size_t len, int *w, int *h)
{
    int n = 0;
    if (len > INT_MAX)
        return NULL;
    /* HDR: linear values clamped to [0, 1], no tone curve (colours are linear here) */
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, hdr_linear);
    return stbi_load_from_memory(buf, (int)len, w, h, &n, 4);
}

bool limen__image_info(const unsigned char *buf, size_t len, int *w, int *h)
{
    int n;
    return len <= INT_MAX && stbi_info_from_memory(buf, (int)len, w, h, &n) != 0;
}

const char *limen__image_why(void)
{
    const char *why = stbi_failure_reason();
    return why ? why : "unknown";
}

void limen_free(void *p)
{
    free(p);    /* stb_image allocates with malloc */
}

limen_status limen_image_diff(const unsigned char *a, const unsigned char *b, int width,
                              int height, int threshold, limen_diff *out,
                              unsigned char *heatmap)
{
    if (!a || !b || !out || width <= 0 || height <= 0 || threshold < 0)
        return LIMEN_ERR_ARG;
    size_t n = (size_t)width * (size_t)height;
    double sq = 0;
    long bad = 0;
    int maxd = 0;
    for (size_t i = 0; i < n; i++) {
        int m = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[3 * i + c] - (int)b[3 * i + c]);
            sq += (double)d * d;
            m = d > m ? d : m;
        }
        maxd = m > maxd ? m : maxd;
        bad += m > threshold;
        if (heatmap) {
            unsigned char *h = heatmap + 3 * i;
            if (m > threshold) {
                /* red at the threshold, towards yellow at full difference */
                h[0] = 255;
                h[1] = (unsigned char)(255 * (m - threshold) / (255 - threshold + 1));
                h[2] = 0;
            } else {
                int grey = (a[3 * i] + a[3 * i + 1] + a[3 * i + 2]) / 9;
                h[0] = h[1] = h[2] = (unsigned char)grey;
            }
        }
    }
    double mse = sq / (3.0 * (double)n);
    out->bad_pixels = bad;
    out->bad_share = (double)bad / (double)n;
    out->psnr = mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    out->max_delta = maxd;
    return LIMEN_OK;
}
