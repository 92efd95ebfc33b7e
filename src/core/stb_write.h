/* stb_write.h - stb_image_write's implementation, static, for the one file that includes
 * it (image.c writes PNG with it, jpeg.c JPEG: see jpeg.c for why two), with the warnings
 * its code raises turned off; and the callback that writes its bytes to a stdio stream. */
#ifndef LIMEN_STB_WRITE_H
#define LIMEN_STB_WRITE_H

#include <stdio.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include "core/stb_quiet.h"
#if defined(__GNUC__)
/* stb declares static functions it does not define in every configuration; the check runs
 * at the end of the file, so this one stays off for the whole file */
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
LIMEN__STB_BEGIN
#include <stb_image_write.h>
LIMEN__STB_END

static void limen__stb_to_file(void *ctx, void *data, int size)
{
    fwrite(data, 1, (size_t)size, ctx);     /* errors stay in the stream's error flag */
}

#endif
