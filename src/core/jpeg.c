/* jpeg.c - JPEG out (stb_image_write), in a file of its own: stb's JPEG writer shifts a
 * signed int past its range (stbiw__jpg_writeBits shifts its 24-bit bit buffer left by 8),
 * which the undefined-behaviour sanitizer reports in every JPEG it writes. The Makefile
 * builds this one file without that check (-fno-sanitize=shift); everything else, PNG
 * included, keeps it. */
#include <limits.h>

#include "core/internal.h"
#include "core/stb_write.h"

/* Whole or not at all, as PNGs are (core/file.c). */
limen_status limen__write_jpeg(const char *path, int width, int height,
                               const unsigned char *rgb, int quality)
{
    limen__out o;
    limen_status st = limen__out_open(&o, path);
    if (st)
        return st;
    if (!stbi_write_jpg_to_func(limen__stb_to_file, o.f, width, height, 3, rgb, quality)) {
        limen__out_abort(&o);
        return LIMEN_ERR_IO;
    }
    return limen__out_close(&o);
}
