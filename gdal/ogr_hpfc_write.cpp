/*
 * ogr_hpfc_write.cpp: the HPFC driver's writer (ogr2ogr -f HPFC OUT IN, a
 * GIS's "Save as"). An .hpfc file is one planar map built from all its
 * layers at once, so nothing can be written feature by feature: the layers
 * and features given are gathered in GDAL's Memory driver, exact and in
 * order, and on close the dataset goes through hpfc-pack's own pipeline
 * (gis_read_graph_dataset, then pack_write: projection, noding, build,
 * feature linking, atomic write), with the creation options standing for
 * hpfc-pack's flags. So the file is the one hpfc-pack writes from the same
 * features with the same options, byte for byte, and a failure leaves no
 * file behind. An existing file of that name is replaced by the final
 * rename only (delete_dataset below): until then it stays whole.
 */
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <dlfcn.h>
#include <execinfo.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

extern "C" {
#include "cores.h"
#include "pack_write.h"
}
#include "ogr_hpfc.h"

namespace
{

class HPFCWriter final : public GDALDataset
{
  public:
    HPFCWriter(const char *path, CSLConstList options, GDALDataset *mem)
        : path_(path), options_(CSLDuplicate(const_cast<char **>(options))), mem_(mem)
    {
        SetDescription(path);
    }
    ~HPFCWriter() override;

    int GetLayerCount() override { return mem_->GetLayerCount(); }
    OGRLayer *GetLayer(int i) override { return mem_->GetLayer(i); }
    int TestCapability(const char *cap) override
    {
        return EQUAL(cap, ODsCCreateLayer);
    }

  protected:
    OGRLayer *ICreateLayer(const char *name, OGRSpatialReference *srs,
                           OGRwkbGeometryType type, char **options) override
    {
        (void)options; /* FID=: the fids are kept whatever its name */
        return mem_->CreateLayer(name, srs, type, nullptr);
    }

  private:
    bool Pack();

    std::string path_;
    char **options_;
    GDALDataset *mem_;
};

HPFCWriter::~HPFCWriter()
{
    Pack();
    GDALClose(mem_);
    CSLDestroy(options_);
}

/* One creation option among `allowed` ("a|b|c"); false with a CPLError. */
bool choice(char **options, const char *name, const char *allowed, const char **out)
{
    const char *v = CSLFetchNameValue(options, name);
    *out = v;
    if (!v)
        return true;
    const CPLStringList list(CSLTokenizeString2(allowed, "|", 0));
    for (int k = 0; k < list.size(); k++)
        if (EQUAL(v, list[k])) {
            *out = list[k] == std::string("auto") ? "auto" : v;
            return true;
        }
    CPLError(CE_Failure, CPLE_IllegalArg, "HPFC: %s=%s: expected one of %s", name, v, allowed);
    return false;
}

/* Threads for the steps that share their work (hpfc-pack --threads): the
 * NUM_THREADS creation option, else GDAL's GDAL_NUM_THREADS setting, as a
 * count or ALL_CPUS; unset, one a core up to 8 (hpfc-pack's default). The
 * file is the same bytes on any count. 0 after a CPLError. */
unsigned num_threads(char **options)
{
    const char *v = CSLFetchNameValue(options, "NUM_THREADS");
    const char *name = "NUM_THREADS";
    if (!v) {
        v = CPLGetConfigOption("GDAL_NUM_THREADS", nullptr);
        name = "GDAL_NUM_THREADS";
    }
    if (!v || EQUAL(v, "ALL_CPUS"))
        return default_threads();
    char *end = nullptr;
    unsigned long n = std::strtoul(v, &end, 10);
    if (!*v || *end || v[0] == '-' || n < 1 || n > 64) {
        CPLError(CE_Failure, CPLE_IllegalArg,
                 "HPFC: %s=%s: expected ALL_CPUS or a count of threads from 1 to 64", name, v);
        return 0;
    }
    return static_cast<unsigned>(n);
}

bool HPFCWriter::Pack()
{
    const char *vertices, *projection, *layout;
    if (!choice(options_, "VERTICES", "junctions|all", &vertices) ||
        !choice(options_, "PROJECTION", "auto|none|tm|lcc|aea|eqc", &projection) ||
        !choice(options_, "LAYOUT", "compact|paper", &layout))
        return false;
    const unsigned threads = num_threads(options_);
    if (!threads)
        return false;
    hpfc_build_params params;
    hpfc_build_params_default(&params);
    params.threads = threads;
    if (const char *lp = CSLFetchNameValue(options_, "LEAF_POINTS")) {
        char *end = nullptr;
        unsigned long long n = std::strtoull(lp, &end, 10);
        if (!*lp || *end || lp[0] == '-' || n > 0xffffffffull) {
            CPLError(CE_Failure, CPLE_IllegalArg,
                     "HPFC: LEAF_POINTS=%s: expected 0 (no bound) or a positive integer", lp);
            return false;
        }
        params.max_leaf_points = static_cast<uint32_t>(n);
    }
    /* hpfc-pack's defaults: topology at junctions, invalid polygons noded,
     * every attribute stored */
    gis_options opt{};
    opt.projection = projection;
    opt.vertex_model = vertices && EQUAL(vertices, "all") ? GIS_VERTICES_ALL
                                                          : GIS_VERTICES_JUNCTIONS;
    opt.invalid_mode = GIS_INVALID_NODE;
    opt.dateline = GIS_DATELINE_CUT;
    opt.key_field = CSLFetchNameValue(options_, "KEY");
    opt.fields = "all";
    opt.threads = threads;
    hpfc_graph *g = nullptr;
    gis_info info;
    char err[1024];
    if (gis_read_graph_dataset(GDALDataset::ToHandle(mem_), &opt, &g, &info, err, sizeof err)) {
        CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s: %s", path_.c_str(), err);
        return false;
    }
    hpfc_write_options wopts{};
    wopts.crs = info.crs;
    wopts.face_labels = 1;
    wopts.layout = !layout                 ? HPFC_LAYOUT_DEFAULT
                   : EQUAL(layout, "paper") ? HPFC_LAYOUT_PAPER
                                            : HPFC_LAYOUT_COMPACT;
    wopts.geometry = g;
    wopts.threads = threads;
    pack_write_stats stats;
    hpfc_diag diag;
    int st = pack_write(g, &params, nullptr, &wopts, &info, 0, path_.c_str(), 0, nullptr, nullptr,
                        &stats, &diag);
    if (st)
        CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s: %s", path_.c_str(),
                 diag.message[0] ? diag.message : hpfc_strerror(st));
    hpfc_graph_free(g);
    gis_info_free(&info);
    return st == HPFC_OK;
}

GDALDataset *create(const char *path, int, int, int bands, GDALDataType, char **options)
{
    if (bands != 0) {
        CPLError(CE_Failure, CPLE_NotSupported, "HPFC: a vector format, no raster bands");
        return nullptr;
    }
    /* the library writes a real file atomically (a temporary beside it,
     * then a rename): the folder must exist, and GDAL's virtual files are
     * not reachable that way */
    if (STARTS_WITH(path, "/vsi")) {
        CPLError(CE_Failure, CPLE_NotSupported,
                 "HPFC: %s: only files on disk are written, not GDAL virtual files", path);
        return nullptr;
    }
    VSIStatBufL st;
    std::string dir = CPLGetPath(path);
    if (VSIStatL(dir.empty() ? "." : dir.c_str(), &st) != 0 || !VSI_ISDIR(st.st_mode)) {
        CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: no such folder", path);
        return nullptr;
    }
    GDALDriver *memory = GetGDALDriverManager()->GetDriverByName("Memory");
    GDALDataset *mem = memory ? memory->Create("", 0, 0, 0, GDT_Unknown, nullptr) : nullptr;
    if (!mem) {
        CPLError(CE_Failure, CPLE_AppDefined, "HPFC: GDAL's Memory driver is missing");
        return nullptr;
    }
    return new HPFCWriter(path, options, mem);
}

/* Whether GDAL deletes the dataset because it is about to create one of
 * that name: GDALDriver::Create and CreateCopy first delete an existing
 * dataset they recognise (GDALDriver::QuietDelete), so a full disk, a kill
 * or a failed build would leave no file at all where the old one was. GDAL
 * gives a driver no way to keep it, so the callers are recognised by their
 * exported names on the stack; where that fails (no unwind information),
 * the delete goes ahead, as GDAL's own would. */
bool deleting_to_create()
{
    void *frames[8];
    int n = backtrace(frames, 8);
    for (int k = 1; k < n; k++) {
        Dl_info info;
        if (!dladdr(frames[k], &info) || !info.dli_sname)
            continue;
        const char *name = info.dli_sname;
        if (std::strstr(name, "GDALDriver11QuietDelete") ||
            std::strstr(name, "GDALDriver6Create") || std::strstr(name, "GDALDriver10CreateCopy"))
            return true;
        if (std::strstr(name, "GDALDeleteDataset") || std::strstr(name, "DeleteDataSource"))
            return false; /* a delete asked for */
    }
    return false;
}

/* The driver's Delete: an .hpfc dataset is its one file. Kept when a create
 * of the same name follows (above): the writer replaces it by renaming the
 * new file over it, or leaves it as it was. */
CPLErr delete_dataset(const char *path)
{
    GDALOpenInfo info(path, GA_ReadOnly);
    GDALDriver *self = GetGDALDriverManager()->GetDriverByName("HPFC");
    if (!self || !self->pfnIdentify || !self->pfnIdentify(&info)) {
        CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: not an .hpfc file, not deleted", path);
        return CE_Failure;
    }
    if (deleting_to_create())
        return CE_None;
    if (VSIUnlink(path) != 0) {
        CPLError(CE_Failure, CPLE_FileIO, "HPFC: %s: cannot delete: %s", path,
                 VSIStrerror(errno));
        return CE_Failure;
    }
    return CE_None;
}

} // namespace

void hpfc_gdal_register_create(GDALDriver *driver)
{
    driver->SetMetadataItem(GDAL_DCAP_CREATE, "YES");
    driver->SetMetadataItem(GDAL_DCAP_CREATE_LAYER, "YES");
    driver->SetMetadataItem(GDAL_DMD_CREATIONFIELDDATATYPES,
                            "Integer Integer64 Real String Date DateTime Time");
    driver->SetMetadataItem(
        GDAL_DMD_CREATIONOPTIONLIST,
        "<CreationOptionList>"
        "  <Option name='VERTICES' type='string-select' default='junctions' "
        "description='Vertices where other than two edges meet (shape points kept exactly "
        "between them), or at every shape point (hpfc-pack --vertices)'>"
        "    <Value>junctions</Value><Value>all</Value></Option>"
        "  <Option name='LEAF_POINTS' type='int' default='16' "
        "description='Refine a leaf holding more shape points than this; 0: no bound "
        "(hpfc-pack --leaf-points)'/>"
        "  <Option name='KEY' type='string' "
        "description='Field(s) kept as each feature key, comma-separated (hpfc-pack --key)'/>"
        "  <Option name='PROJECTION' type='string-select' default='auto' "
        "description='Projection of longitudes/latitudes (hpfc-pack --projection)'>"
        "    <Value>auto</Value><Value>none</Value><Value>tm</Value><Value>lcc</Value>"
        "<Value>aea</Value><Value>eqc</Value></Option>"
        "  <Option name='LAYOUT' type='string-select' default='compact' "
        "description='Pool layout (hpfc-pack --layout)'>"
        "    <Value>compact</Value><Value>paper</Value></Option>"
        "  <Option name='NUM_THREADS' type='string' default='ALL_CPUS' "
        "description='Threads for validation, the build, the faces and the polygons checks: "
        "a count or ALL_CPUS (one a core, up to 8); GDAL_NUM_THREADS when not given. "
        "The same bytes on any count (hpfc-pack --threads)'/>"
        "</CreationOptionList>");
    /* declared so that ogr2ogr keeps the source's fids, as hpfc-pack does */
    driver->SetMetadataItem(GDAL_DS_LAYER_CREATIONOPTIONLIST,
                            "<LayerCreationOptionList>"
                            "  <Option name='FID' type='string' "
                            "description='Ignored: the source fids are kept'/>"
                            "</LayerCreationOptionList>");
    driver->pfnCreate = create;
    driver->pfnDelete = delete_dataset;
}
