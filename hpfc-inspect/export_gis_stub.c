/*
 * export_gis_stub.c: hpfc-inspect built without GDAL. --export and
 * --export-faces say so; everything else works.
 */
#include "export_gis.h"

int export_gis(const gis_export_options *o, FILE *report)
{
    (void)report;
    fprintf(stderr, "hpfc-inspect: %s: --export needs GDAL, not built in\n", o->output);
    return 1;
}
