/* image.c - PNG in and out (stb_image, stb_image_write) and image comparison. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#if defined(__GNUC__)
/* stb declares static functions it does not define in every configuration; the check runs
 * at the end of the file, so this one stays off for the whole file */
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#endif
#include <stb_image.h>
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "core/internal.h"
#include "core/texture.h"

limen_status limen_write_png(const char *path, int width, int height, const unsigned char *rgb)
{
    if (!path || !rgb || width <= 0 || height <= 0 || width > INT_MAX / 3 / height)
        return LIMEN_ERR_ARG;
    if (!stbi_write_png(path, width, height, 3, rgb, width * 3))
        return LIMEN_ERR_IO;
    return LIMEN_OK;
}

limen_status limen_read_png(const char *path, int *width, int *height, unsigned char **rgb)
{
    if (!path || !width || !height || !rgb)
        return LIMEN_ERR_ARG;
    *rgb = NULL;
    int n = 0;
    unsigned char *data = stbi_load(path, width, height, &n, 3);
    if (!data)
        return LIMEN_ERR_IO;
    *rgb = data;
    return LIMEN_OK;
}

unsigned char *limen__image_decode(const unsigned char *buf, size_t len, int *w, int *h)
{
    int n = 0;
    if (len > INT_MAX)
        return NULL;
    return stbi_load_from_memory(buf, (int)len, w, h, &n, 3);
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
