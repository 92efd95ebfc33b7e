/* trace.c - the reference ray tracer (being written). */
#include "core/internal.h"
