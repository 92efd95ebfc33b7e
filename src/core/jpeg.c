/* jpeg.c - JPEG out (stb_image_write), in a file of its own: stb's JPEG writer shifts a
 * signed int past its range (stbiw__jpg_writeBits shifts its 24-bit bit buffer left by 8),
 * which the undefined-behaviour sanitizer reports in every JPEG it writes. The Makefile
 * builds this one file without that check (-fno-sanitize=shift); everything else, PNG
 * included, keeps it. */
#include <limits.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "core/internal.h"

limen_status limen__write_jpeg(const char *path, int width, int height,
                               const unsigned char *rgb, int quality)
{
    if (!stbi_write_jpg(path, width, height, 3, rgb, quality))
        return LIMEN_ERR_IO;
    return LIMEN_OK;
}
