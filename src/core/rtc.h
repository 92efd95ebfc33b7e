/* rtc.h - ray traversal through Embree 3 over the spatial index's items (core/rtc.c). */
#ifndef LIMEN_RTC_H
#define LIMEN_RTC_H

#include "core/bvh.h"

typedef struct limen__rtc limen__rtc;

/* An Embree device; NULL when Embree cannot start (the caller walks core/bvh.c instead). */
limen__rtc *limen__rtc_create(void);
void limen__rtc_free(limen__rtc *r);
/* Builds Embree's hierarchy over the items of both trees, with their current boxes; the
 * trees must stay as they are while rays are traced. False when Embree fails. */
bool limen__rtc_commit(limen__rtc *r, const limen__bvh *shapes, const limen__bvh *surfaces);
/* As limen__bvh_ray, over both trees' items (item ids as in the trees). Thread-safe. */
void limen__rtc_ray(const limen__rtc *r, const double o[3], const double d[3], double tmin,
                    double tmax, limen__bvh_hit_fn hit, void *ctx);

#endif
