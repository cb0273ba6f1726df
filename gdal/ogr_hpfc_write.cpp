#include "ogr_hpfc.h"

void hpfc_gdal_register_create(GDALDriver *driver)
{
    (void)driver;
}
