/* model.h - model files as scenes (core/model.c). Not part of the public API. */
#ifndef LIMEN_CORE_MODEL_H
#define LIMEN_CORE_MODEL_H

#include <stddef.h>

#include "limen.h"

/* limen_model_load refusing meshes that would hold more than max_bytes; *charged: the
 * bytes its meshes hold. */
limen_status limen__model_load(limen_scene *s, limen_node group, const char *path,
                               const limen_model_desc *desc, size_t max_bytes, size_t *charged);

#endif
