/* fuzz_png.c - libFuzzer target for PNG reading (make fuzz): arbitrary bytes through the
 * decoder behind limen_read_png (the size refusal, the empty-IDAT filter, stb_image), and
 * a decoded image compared with itself and written back out. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "limen.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* src/core/internal.h (kept out of here, with cglm) */
limen_status limen__png_decode(unsigned char *buf, size_t len, int *width, int *height,
                               unsigned char **rgb);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned char *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    int w = 0, h = 0;
    unsigned char *rgb = NULL;
    limen_status st = limen__png_decode(copy, size, &w, &h, &rgb);
    free(copy);
    if (st == LIMEN_OK) {
        if (w <= 0 || h <= 0 || (long long)w * h > LIMEN_IMAGE_MAX_PIXELS || !rgb)
            abort();
        limen_diff d;
        if (limen_image_diff(rgb, rgb, w, h, 8, &d, NULL) || d.bad_pixels)
            abort();
        if ((long long)w * h <= 4096) {
            char path[64];
            snprintf(path, sizeof path, "/tmp/limen-fuzz-%ld.png", (long)getpid());
            int w2, h2;
            unsigned char *back = NULL;
            if (limen_write_png(path, w, h, rgb) || limen_read_png(path, &w2, &h2, &back) ||
                w2 != w || h2 != h || memcmp(back, rgb, (size_t)w * h * 3))
                abort();    /* what limen writes, it reads back the same */
            limen_free(back);
            remove(path);
        }
    } else if (rgb) {
        abort();
    }
    limen_free(rgb);
    return 0;
}
