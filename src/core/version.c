/* version.c - the library's own version, as built (limen.h's LIMEN_VERSION_*). */
#include "core/internal.h"

const char *limen_version(void)
{
    return LIMEN_VERSION;
}

int limen_version_number(void)
{
    return LIMEN_VERSION_NUMBER;
}
