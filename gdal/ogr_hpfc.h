/*
 * ogr_hpfc.h: the HPFC driver's parts (ogr_hpfc.cpp reads, ogr_hpfc_write.cpp
 * writes) and the plugin's exported entry points.
 */
#ifndef HPFC_OGR_HPFC_H
#define HPFC_OGR_HPFC_H

#include <gdal_priv.h>

/* the plugin's entry points are its only visible symbols */
#define HPFC_GDAL_EXPORT __attribute__((visibility("default")))

/* Registers the driver (reading, and writing through the function below). */
extern "C" HPFC_GDAL_EXPORT void GDALRegister_HPFC();
/* Gives the driver its Create and its creation options. */
void hpfc_gdal_register_create(GDALDriver *driver);

#endif
