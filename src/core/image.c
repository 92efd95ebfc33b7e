/* image.c - PNG output through stb_image_write. */
#include <errno.h>
#include <limits.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO_UNUSED
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "core/internal.h"

limen_status limen_write_png(const char *path, int width, int height, const unsigned char *rgb)
{
    if (!path || !rgb || width <= 0 || height <= 0 || width > INT_MAX / 3 / height)
        return LIMEN_ERR_ARG;
    errno = 0;
    if (!stbi_write_png(path, width, height, 3, rgb, width * 3))
        return LIMEN_ERR_IO;
    return LIMEN_OK;
}
