/*
 * read_driver: the OGR driver HPFC (gdal/) on a mutant file, through GDAL's
 * own entry points, as a host program (ogrinfo, QGIS, fiona) calls them.
 *
 * The input is an .hpfc file followed by command bytes (input.h). The file
 * goes to a GDAL in-memory file (/vsimem/) and is opened with GDALOpenEx,
 * the driver alone allowed, with the open option VERIFY_CHECKSUMS=NO so
 * that mutated sections reach the readers (the checksummed open is tried
 * first: it must refuse or accept without harm). Then every layer: its
 * count, extent and definition, every feature in order (at most 256), and
 * one feature past the last by fid. Command bytes choose fids for
 * GetFeature and rectangles for SetSpatialFilter (a quarter of the extent
 * when there are none), each followed by a read of what the filter lets
 * through; a polygon filter (a triangle) runs once. Then the reads a
 * host asks for less: with the geometry ignored, with an attribute filter
 * on the first field and on the geometry's area (tested before or after
 * the geometry is assembled), and from an index (SetNextByIndex).
 *
 * Oracle: no crash, leak or sanitizer report; every failure is a CPLError
 * (counted by a handler) and never a wrong shape: every geometry returned
 * is of its layer's type (or unknown), its rings closed; a filtered read
 * returns only features whose envelope meets the filter's; GetFeature(fid)
 * gives back that fid; an ignored geometry is never returned; an
 * attribute filter passes no more features than the read without it.
 */
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

extern "C" {
#include "input.h"
}
#include "ogr_hpfc.h"

namespace
{

int errors_seen;

void CPL_STDCALL count_errors(CPLErr cls, CPLErrorNum, const char *)
{
    if (cls >= CE_Failure)
        errors_seen++;
}

void check_geometry(const OGRGeometry *g, OGRwkbGeometryType layer_type)
{
    if (!g)
        return;
    OGRwkbGeometryType t = wkbFlatten(g->getGeometryType());
    FUZZ_CHECK(layer_type == wkbUnknown || t == layer_type);
    if (t == wkbPolygon || t == wkbMultiPolygon) {
        const OGRPolygon *one = t == wkbPolygon ? g->toPolygon() : nullptr;
        const OGRMultiPolygon *many = t == wkbMultiPolygon ? g->toMultiPolygon() : nullptr;
        int n = one ? 1 : many->getNumGeometries();
        for (int k = 0; k < n; k++) {
            const OGRPolygon *p = one ? one : many->getGeometryRef(k);
            for (const OGRLinearRing *r : *p)
                FUZZ_CHECK(r->getNumPoints() >= 4 && r->get_IsClosed());
        }
    }
}

int read_all(OGRLayer *l, int limit)
{
    int n = 0;
    OGRFeature *f;
    l->ResetReading();
    while (n < limit && (f = l->GetNextFeature()) != nullptr) {
        check_geometry(f->GetGeometryRef(), wkbFlatten(l->GetGeomType()));
        OGRGeometry *filter = l->GetSpatialFilter();
        if (filter && f->GetGeometryRef()) {
            OGREnvelope a, b;
            filter->getEnvelope(&a);
            f->GetGeometryRef()->getEnvelope(&b);
            FUZZ_CHECK(a.Intersects(b));
        }
        delete f;
        n++;
    }
    return n;
}

/* The reads that skip work: the geometry ignored, attribute filters,
 * a start from an index. */
void read_less(OGRLayer *l, int all)
{
    const char *no_geometry[] = {"OGR_GEOMETRY", nullptr};
    if (l->SetIgnoredFields(no_geometry) == OGRERR_NONE) {
        OGRFeature *f;
        l->ResetReading();
        for (int n = 0; n < 64 && (f = l->GetNextFeature()) != nullptr; n++) {
            FUZZ_CHECK(f->GetGeometryRef() == nullptr);
            delete f;
        }
        l->SetIgnoredFields(nullptr);
    }
    OGRFeatureDefn *defn = l->GetLayerDefn();
    if (defn->GetFieldCount() > 0) {
        CPLString where;
        where.Printf("\"%s\" IS NOT NULL", defn->GetFieldDefn(0)->GetNameRef());
        if (l->SetAttributeFilter(where) == OGRERR_NONE)
            FUZZ_CHECK(read_all(l, 256) <= all || all == 256);
    }
    if (l->SetAttributeFilter("OGR_GEOM_AREA > 0") == OGRERR_NONE)
        FUZZ_CHECK(read_all(l, 256) <= all || all == 256);
    l->SetAttributeFilter(nullptr);
    l->ResetReading();
    if (l->SetNextByIndex(1) == OGRERR_NONE)
        delete l->GetNextFeature();
}

void explore(GDALDataset *ds, fuzz_bytes *cmds)
{
    for (int i = 0; i < ds->GetLayerCount(); i++) {
        OGRLayer *l = ds->GetLayer(i);
        FUZZ_CHECK(l != nullptr);
        l->GetLayerDefn()->GetFieldCount();
        l->GetFeatureCount(TRUE);
        OGREnvelope env;
        bool have_extent = l->GetExtent(&env, TRUE) == OGRERR_NONE;
        int before = errors_seen;
        int all = read_all(l, 256);
        /* a read cut short by an error bounds nothing: a filter may skip
         * the feature that failed */
        if (errors_seen != before)
            all = 256;
        OGRFeature *f = l->GetFeature(l->GetFeatureCount(TRUE) + 1);
        delete f;
        read_less(l, all);
        if (!have_extent)
            continue;
        double w = env.MaxX - env.MinX, h = env.MaxY - env.MinY;
        if (fuzz_empty(cmds)) {
            l->SetSpatialFilterRect(env.MinX + w / 4, env.MinY + h / 4, env.MaxX - w / 4,
                                    env.MaxY - h / 4);
            read_all(l, 256);
            OGRPolygon tri;
            OGRLinearRing ring;
            ring.addPoint(env.MinX, env.MinY);
            ring.addPoint(env.MaxX, env.MinY);
            ring.addPoint(env.MinX, env.MaxY);
            ring.closeRings();
            tri.addRing(&ring);
            l->SetSpatialFilter(&tri);
            read_all(l, 256);
            l->SetSpatialFilter(nullptr);
        }
        for (int c = 0; c < 16 && !fuzz_empty(cmds); c++) {
            uint8_t op = fuzz_u8(cmds);
            if (op & 1) {
                GIntBig fid = static_cast<int64_t>(fuzz_u64(cmds));
                if ((f = l->GetFeature(fid)) != nullptr) {
                    FUZZ_CHECK(f->GetFID() == fid);
                    check_geometry(f->GetGeometryRef(), wkbFlatten(l->GetGeomType()));
                    delete f;
                }
            } else {
                double a = fuzz_u8(cmds) / 128.0 - 0.5, b = fuzz_u8(cmds) / 128.0 - 0.5;
                double c2 = fuzz_u8(cmds) / 128.0 - 0.5, d = fuzz_u8(cmds) / 128.0 - 0.5;
                l->SetSpatialFilterRect(env.MinX + a * w, env.MinY + b * h, env.MinX + c2 * w,
                                        env.MinY + d * h);
                read_all(l, 64);
                l->SetSpatialFilter(nullptr);
            }
        }
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static bool registered = false;
    if (!registered) {
        registered = true;
        GDALRegister_HPFC();
    }
    uint8_t *file;
    size_t file_size;
    fuzz_bytes cmds;
    if (!fuzz_split_file(data, size, &file, &file_size, &cmds))
        return 0;
    const char *path = "/vsimem/read_driver.hpfc";
    VSILFILE *fp = VSIFileFromMemBuffer(path, file, file_size, FALSE);
    if (fp)
        VSIFCloseL(fp);
    CPLPushErrorHandler(count_errors);
    const char *drivers[] = {"HPFC", nullptr};
    const char *no_checksums[] = {"VERIFY_CHECKSUMS=NO", nullptr};
    for (int pass = 0; pass < 2; pass++) {
        errors_seen = 0;
        GDALDataset *ds = GDALDataset::FromHandle(GDALOpenEx(
            path, GDAL_OF_VECTOR | GDAL_OF_READONLY, drivers, pass ? no_checksums : nullptr,
            nullptr));
        /* a file the driver refuses says why */
        if (!ds && file_size >= 8 && memcmp(file, "\x89HPFC\r\n\x1a", 8) == 0)
            FUZZ_CHECK(errors_seen > 0);
        if (ds) {
            fuzz_bytes c = cmds;
            explore(ds, &c);
            GDALClose(ds);
        }
    }
    CPLPopErrorHandler();
    VSIUnlink(path);
    free(file);
    return 0;
}
