/*
 * gis_attrs.h: the attributes of a GIS pack's features, for the file's
 * ATTR section (spec/hpfc-format.md §6.3): typed columns (integer, real,
 * string), one row per recorded feature (gis_features.h), in its order.
 *
 * Column 0 is always "source_fid", the feature's FID in its source (the
 * file's fid is the feature's position in its layer, which does not depend
 * on the input format). The others are the fields asked for with --fields,
 * by name across all layers: a layer without one of them leaves it null;
 * when layers disagree on a column's type, integer and real make real, any
 * other mix makes string.
 */
#ifndef HPFC_PACK_GIS_ATTRS_H
#define HPFC_PACK_GIS_ATTRS_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"

typedef struct gis_attrs gis_attrs;

gis_attrs *gis_attrs_create(void);
void gis_attrs_free(gis_attrs *a);

/* The column named `name` with values of `type` (HPFC_ATTR_*), added if
 * new, its type widened if it differs; -1 when memory runs out. */
long gis_attrs_column(gis_attrs *a, const char *name, int type);

/* Starts the next row (feature); then gis_attrs_set_* fill its columns
 * (unset ones stay null). 0 or -1. */
int gis_attrs_row(gis_attrs *a);
int gis_attrs_set_integer(gis_attrs *a, uint32_t column, int64_t v);
int gis_attrs_set_real(gis_attrs *a, uint32_t column, double v);
int gis_attrs_set_string(gis_attrs *a, uint32_t column, const char *s);

uint32_t gis_attrs_rows(const gis_attrs *a);

/* The table over all rows, every value of its column's type; valid until
 * the next call or gis_attrs_free. 0 or -1. */
int gis_attrs_table(gis_attrs *a, hpfc_attr_table *out);

#endif
