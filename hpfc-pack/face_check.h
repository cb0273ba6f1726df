/*
 * face_check.h: the features around a witness point (face_witness.h),
 * exactly: the features whose rings, as they lie in the map
 * (gis_features.h), hold the point an odd number of times (even-odd rule,
 * spec/hpfc-format.md §6.2). This is the independent answer that every
 * face's walked answer is checked against (face_link.h).
 *
 * Rings are found by a packed R-tree over their boxes (sort-tile-recursive)
 * and tested by the crossings of a ray (face_witness_ray_crosses: exact
 * integer tests on the symbolically moved point). A ring asked about more
 * than once and long enough gets an index of its segments by their y
 * extent (a packed interval tree), so that a ring of 10^6 points around
 * 10^5 faces costs the segments that meet each ray, not the whole ring each
 * time. All in time near-linear in the map for real layers.
 */
#ifndef HPFC_PACK_FACE_CHECK_H
#define HPFC_PACK_FACE_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "face_witness.h"
#include "gis_features.h"

typedef struct face_check face_check;

/* A growable list of feature indices. */
typedef struct feature_list {
    uint32_t *v;
    size_t n, cap;
} feature_list;

/* An index over the rings of fs (which must outlive it). HPFC_OK or
 * HPFC_E_NOMEM. */
int face_check_create(const gis_features *fs, face_check **out);
void face_check_free(face_check *fc);

/* A thread's working arrays for face_check_features: zeroed before the
 * first call, freed with face_check_scratch_free. */
typedef struct face_check_scratch {
    int64_t *pts;    /* a ring's points, decoded */
    size_t cap_pts;
    uint32_t *hits;  /* the parts whose box holds the witness */
    size_t n_hits, cap_hits;
} face_check_scratch;
void face_check_scratch_free(face_check_scratch *s);

/* Sets *out to the features whose rings hold w an odd number of times,
 * ascending. HPFC_OK, HPFC_E_NOMEM, or HPFC_E_CORRUPT when w lies on a
 * ring (a witness never lies on a segment of the map). Several threads
 * may ask one fc at once, each with its own scratch. */
int face_check_features(face_check *fc, face_check_scratch *s, const face_witness *w,
                        feature_list *out);

#endif
