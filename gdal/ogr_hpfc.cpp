/*
 * ogr_hpfc.cpp: the OGR vector driver "HPFC" (interfaces §7), a GDAL plugin
 * over the public hpfc.h. A file opens as one layer per source layer, then
 * "faces" and "edges" (the topology itself); geometry and fields come from
 * common/ogr_shapes.h, the code behind hpfc-inspect --export, so the
 * driver and the export give the same features.
 *
 * Every byte of the file is hostile: the library bounds-checks each read
 * and answers a status, which the driver turns into a CPLError, never an
 * abort. Spatial filters descend the tree (hpfc_shapes_window) to the
 * window's leaves; OGR's own FilterGeometry then refines the candidates
 * exactly against the filter geometry.
 */
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include "hpfc.h"
#include "ogr_hpfc.h"
#include "ogr_shapes.h"

namespace
{

const unsigned char kMagic[8] = {0x89, 'H', 'P', 'F', 'C', '\r', '\n', 0x1a};

class HPFCDataset;

enum class LayerKind { Source, Faces, Edges };

class HPFCLayer final : public OGRLayer
{
  public:
    HPFCLayer(HPFCDataset *ds, LayerKind kind, const std::string &name,
              OGRwkbGeometryType type);
    ~HPFCLayer() override;

    void ResetReading() override;
    OGRFeature *GetNextFeature() override;
    OGRFeature *GetFeature(GIntBig fid) override;
    GIntBig GetFeatureCount(int force) override;
    OGRErr GetExtent(OGREnvelope *env, int force) override;
    OGRErr GetExtent(int geom_field, OGREnvelope *env, int force) override
    {
        return geom_field == 0 ? GetExtent(env, force) : OGRERR_FAILURE;
    }
    void SetSpatialFilter(OGRGeometry *geom) override;
    OGRErr SetAttributeFilter(const char *where) override;
    OGRErr SetNextByIndex(GIntBig index) override;
    void SetSpatialFilter(int geom_field, OGRGeometry *geom) override
    {
        if (geom_field == 0)
            SetSpatialFilter(geom);
        else
            CPLError(CE_Failure, CPLE_AppDefined, "HPFC: no geometry field %d", geom_field);
    }
    OGRFeatureDefn *GetLayerDefn() override { return defn_; }
    int TestCapability(const char *cap) override;
    const char *GetFIDColumn() override { return fid_column_.c_str(); }

    bool Init(); /* fields; false after a CPLError */
    /* a source layer's feature count, and whether it holds every feature
     * of the file (one source layer): known at open, before its members */
    void SetCount(uint64_t count, bool all) { count_ = count, all_ = all; }
    void AddMember(hpfc_id feature, int64_t fid) { members_.push_back({feature, fid}); }
    void IndexMembers();
    void ForgetMembers() { members_.clear(), by_fid_.clear(); }

  private:
    OGRFeature *Build(uint64_t id, bool with_geometry);
    bool AttachGeometry(OGRFeature *f, uint64_t id);
    bool BuildWindow();
    uint64_t Count() const;

    HPFCDataset *ds_;
    LayerKind kind_;
    OGRFeatureDefn *defn_;
    std::string fid_column_;
    ogr_shapes_field *fields_ = nullptr;
    size_t field_count_ = 0;
    int count_field_ = -1, fids_field_ = -1, keys_field_ = -1; /* faces */
    int left_face_ = -1, right_face_ = -1, left_fids_ = -1, right_fids_ = -1,
        line_fids_ = -1; /* edges */
    struct Member {
        hpfc_id feature;
        int64_t fid;
    };
    /* source: its features in file order, listed on first need
     * (HPFCDataset::ListMembers); with all_ a feature's member index is
     * its id, and only GetFeature needs the list (for the fids) */
    std::vector<Member> members_;
    uint64_t count_ = 0;
    bool all_ = false;
    /* source: members_ indices by ascending fid, where the fids are not
     * already ascending in file order (they are for a 1.2 writer's single
     * layer: positions in the source layer) */
    std::vector<size_t> by_fid_;
    uint64_t cursor_ = 0;
    bool windowed_ = false;                         /* iterate over hits_ */
    bool attr_reads_geometry_ = false;              /* the attribute filter names OGR_GEOM* */
    bool window_built_ = false;                     /* hits_ answer the current filter */
    std::vector<uint64_t> hits_;                    /* members_ indices or face/edge ids */
    const Member *FindFid(int64_t fid) const;
};

class HPFCDataset final : public GDALDataset
{
  public:
    ~HPFCDataset() override;
    static GDALDataset *Open(GDALOpenInfo *info);

    int GetLayerCount() override { return static_cast<int>(layers_.size()); }
    OGRLayer *GetLayer(int i) override
    {
        return i >= 0 && i < GetLayerCount() ? layers_[static_cast<size_t>(i)].get() : nullptr;
    }
    int TestCapability(const char *) override { return FALSE; }

    hpfc_file *file_ = nullptr;
    hpfc_shapes *shapes_ = nullptr;
    ogr_shapes g_{};
    bool g_ready_ = false;
    OGRSpatialReference *srs_ = nullptr;
    bool have_features_ = false;
    hpfc_features_info features_{};
    hpfc_geometry_info geometry_{};
    bool extent_done_ = false, extent_ok_ = false;
    OGREnvelope extent_;

    bool Extent(OGREnvelope *env);
    bool ExtentFromBounds(OGREnvelope *env);
    bool ListMembers();
    bool Window(const OGREnvelope &env, int64_t *x0, int64_t *y0, int64_t *x1, int64_t *y1);

  private:
    bool members_listed_ = false; /* every source layer's members_ filled */
    GByte *buffer_ = nullptr; /* a /vsi file read whole; else the library maps it */
    std::vector<std::unique_ptr<HPFCLayer>> layers_;
    bool Load(GDALOpenInfo *info);
};

/* ---- errors ------------------------------------------------------------------------ */

void status_error(const char *what, int st)
{
    CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s: %s", what, hpfc_strerror(st));
}

/* ---- dataset ----------------------------------------------------------------------- */

HPFCDataset::~HPFCDataset()
{
    layers_.clear();
    if (g_ready_)
        ogr_shapes_release(&g_);
    if (srs_)
        srs_->Release();
    hpfc_shapes_free(shapes_);
    hpfc_close(file_);
    CPLFree(buffer_);
}

int identify(GDALOpenInfo *info)
{
    return info->nHeaderBytes >= 8 && memcmp(info->pabyHeader, kMagic, 8) == 0;
}

GDALDataset *HPFCDataset::Open(GDALOpenInfo *info)
{
    if (!identify(info) || !(info->nOpenFlags & GDAL_OF_VECTOR))
        return nullptr;
    if (info->eAccess == GA_Update) {
        CPLError(CE_Failure, CPLE_NotSupported,
                 "HPFC: a file is written whole (ogr2ogr -f HPFC), never updated in place");
        return nullptr;
    }
    auto ds = std::make_unique<HPFCDataset>();
    if (!ds->Load(info))
        return nullptr;
    return ds.release();
}

bool HPFCDataset::Load(GDALOpenInfo *info)
{
    const char *path = info->pszFilename;
    bool verify = CPLTestBool(CSLFetchNameValueDef(info->papszOpenOptions, "VERIFY_CHECKSUMS",
                                                   "YES"));
    unsigned flags = verify ? 0u : HPFC_OPEN_SKIP_CHECKSUM;
    int st;
    if (!STARTS_WITH(path, "/vsi")) {
        st = hpfc_open(path, flags, &file_);
    } else {
        /* no mapping of a virtual file: its bytes, read once */
        vsi_l_offset size = 0;
        if (!VSIIngestFile(nullptr, path, &buffer_, &size, -1)) {
            CPLError(CE_Failure, CPLE_FileIO, "HPFC: %s: cannot read", path);
            return false;
        }
        st = hpfc_open_memory(buffer_, static_cast<size_t>(size), flags, &file_);
    }
    if (st) {
        CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: %s", path, hpfc_strerror(st));
        return false;
    }
    /* a damaged file must not give a plausible but wrong map */
    hpfc_diag diag;
    if (verify && (st = hpfc_file_check_checksums(file_, &diag))) {
        CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: %s", path,
                 diag.message[0] ? diag.message : hpfc_strerror(st));
        return false;
    }
    if ((st = hpfc_shapes_create(file_, &shapes_))) {
        if (st == HPFC_E_NO_SECTION)
            CPLError(CE_Failure, CPLE_OpenFailed,
                     "HPFC: %s: no exact geometry (GEOM and LABL sections); pack it again "
                     "with hpfc-pack 1.2",
                     path);
        else
            CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: geometry: %s", path,
                     hpfc_strerror(st));
        return false;
    }
    if ((st = hpfc_file_get_geometry(file_, &geometry_))) {
        status_error("geometry", st);
        return false;
    }
    if (ogr_shapes_init(&g_, file_, shapes_)) {
        CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: %s", path, g_.why);
        ogr_shapes_release(&g_);
        return false;
    }
    g_ready_ = true;
    if (g_.srs) { /* shared, not copied: a copy costs PROJ a second object */
        srs_ = OGRSpatialReference::FromHandle(g_.srs);
        srs_->Reference();
    }
    SetDescription(path);

    st = hpfc_file_get_features(file_, &features_);
    if (st && st != HPFC_E_NO_SECTION) {
        status_error("features", st);
        return false;
    }
    have_features_ = st == HPFC_OK;
    std::vector<std::string> names;
    if (have_features_) {
        /* each layer's geometry type and count from its features' row
         * lengths and layers; no feature is read until a layer's members
         * are needed */
        std::vector<OGRwkbGeometryType> types(features_.layers);
        std::vector<uint64_t> counts(features_.layers);
        if (ogr_shapes_layer_types(&g_, types.data(), counts.data(), features_.layers)) {
            CPLError(CE_Failure, CPLE_OpenFailed, "HPFC: %s: %s", path, g_.why);
            return false;
        }
        for (uint32_t l = 0; l < features_.layers; l++) {
            const char *name;
            size_t len;
            if ((st = hpfc_layer_name(file_, l, &name, &len))) {
                status_error("layer name", st);
                return false;
            }
            names.emplace_back(len ? std::string(name, len) : std::string("features"));
        }
        for (uint32_t l = 0; l < features_.layers; l++)
            layers_.emplace_back(new HPFCLayer(this, LayerKind::Source, names[l], wkbUnknown));
        for (uint32_t l = 0; l < features_.layers; l++) {
            layers_[l]->GetLayerDefn()->SetGeomType(types[l]);
            layers_[l]->SetCount(counts[l], features_.layers == 1);
        }
    }
    /* the topology's layers keep their names unless a source layer has taken them */
    auto free_name = [&](const char *base) {
        std::string n = base;
        while (std::find(names.begin(), names.end(), n) != names.end())
            n = "hpfc_" + n;
        names.push_back(n);
        return n;
    };
    layers_.emplace_back(new HPFCLayer(this, LayerKind::Faces, free_name("faces"), wkbPolygon));
    layers_.emplace_back(
        new HPFCLayer(this, LayerKind::Edges, free_name("edges"), wkbLineString));
    for (auto &l : layers_)
        if (!l->Init())
            return false;
    return true;
}

/* The extent from GEOM's box of every lattice point (hpfc_geometry_bounds,
 * a few of its blocks read) where the output coordinates are a
 * non-decreasing function of each lattice coordinate: user coordinates,
 * or longitude and latitude back from the equirectangular projection as
 * long as no point wraps across the antimeridian (the box's corners are
 * then every point's bounds). False where that does not hold. */
bool HPFCDataset::ExtentFromBounds(OGREnvelope *env)
{
    if (g_.plan && mapproj_plan_kind(g_.plan) != MAPPROJ_EQC)
        return false;
    int64_t box[4];
    if (hpfc_geometry_bounds(file_, box) != HPFC_OK)
        return false;
    const int64_t corners[4] = {box[0], box[1], box[2], box[3]};
    double user[4], out[4];
    hpfc_user_points(file_, corners, 2, user);
    if (g_.plan) {
        /* the raw longitudes of the box's sides: inside [-180, 180] up to
         * the rounding step the put-back rule allows, no point wraps */
        double lon[2], lat[2];
        if (mapproj_inverse(g_.plan, user[0], user[1], &lon[0], &lat[0]) != 0 ||
            mapproj_inverse(g_.plan, user[2], user[3], &lon[1], &lat[1]) != 0 ||
            lon[0] < -180.0 - 1e-6 || lon[1] > 180.0 + 1e-6)
            return false;
    }
    if (ogr_shapes_points(&g_, corners, 2, out))
        return false;
    env->MinX = out[0], env->MinY = out[1], env->MaxX = out[2], env->MaxY = out[3];
    return env->MinX <= env->MaxX && env->MinY <= env->MaxY;
}

/* The map's extent in output coordinates (each layer's features lie
 * within it): from GEOM's box where that gives it exactly, else from every
 * point of GEOM, O(points); computed once, on first asking, and kept. */
bool HPFCDataset::Extent(OGREnvelope *env)
{
    if (!extent_done_ && ExtentFromBounds(&extent_)) {
        extent_done_ = extent_ok_ = true;
    }
    if (!extent_done_) {
        extent_done_ = true;
        OGREnvelope e;
        bool ok = true;
        for (uint64_t v = 0; ok && v < geometry_.vertices; v++) {
            int64_t x, y;
            double ox, oy;
            ok = hpfc_geometry_vertex(file_, v, &x, &y) == HPFC_OK &&
                 ogr_shapes_point(&g_, x, y, &ox, &oy) == 0;
            if (ok)
                e.Merge(ox, oy);
        }
        for (uint64_t edge = 0; ok && edge < geometry_.edges; edge++) {
            hpfc_id u, v;
            uint64_t n;
            ok = hpfc_geometry_edge(file_, edge, &u, &v, &n) == HPFC_OK;
            for (uint64_t k = 1; ok && k + 1 < n; k++) {
                int64_t x, y;
                double ox, oy;
                ok = hpfc_geometry_edge_point(file_, edge, k, &x, &y) == HPFC_OK &&
                     ogr_shapes_point(&g_, x, y, &ox, &oy) == 0;
                if (ok)
                    e.Merge(ox, oy);
            }
        }
        extent_ok_ = ok && e.IsInit();
        if (!ok)
            CPLError(CE_Failure, CPLE_AppDefined, "HPFC: extent: the geometry does not read");
        extent_ = e;
    }
    if (extent_ok_)
        *env = extent_;
    return extent_ok_;
}

/* A lattice window holding every lattice point whose output coordinates
 * lie in env. Without a projection back that is env scaled and rounded
 * outwards. With one, the envelope (in longitude/latitude) is traced along
 * its border and projected forwards; the projections hpfc-pack uses bend
 * a border's image by far less than the margin added, and a window too
 * wide only costs time, since OGR refines every candidate exactly. Where
 * the projection cannot be trusted (a wide or polar window) the whole
 * domain is the window. */
bool HPFCDataset::Window(const OGREnvelope &env, int64_t *x0, int64_t *y0, int64_t *x1,
                         int64_t *y1)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file_, &fi);
    double scale = std::pow(10.0, -static_cast<double>(fi.unit_exp10));
    double ux0, uy0, ux1, uy1;
    bool whole = false;
    if (!g_.plan) {
        ux0 = env.MinX, uy0 = env.MinY, ux1 = env.MaxX, uy1 = env.MaxY;
    } else {
        double lon0 = std::max(env.MinX, -180.0), lon1 = std::min(env.MaxX, 180.0);
        double lat0 = std::max(env.MinY, -90.0), lat1 = std::min(env.MaxY, 90.0);
        if (lon0 > lon1 || lat0 > lat1)
            return false; /* nothing of the map's lon/lat range */
        whole = lon1 - lon0 > 60.0 || lat0 < -80.0 || lat1 > 80.0;
        ux0 = uy0 = std::numeric_limits<double>::infinity();
        ux1 = uy1 = -ux0;
        const int steps = 64;
        for (int side = 0; !whole && side < 4; side++)
            for (int k = 0; k <= steps; k++) {
                double t = static_cast<double>(k) / steps;
                double lon = side < 2 ? lon0 + t * (lon1 - lon0) : side == 2 ? lon0 : lon1;
                double lat = side < 2 ? (side == 0 ? lat0 : lat1) : lat0 + t * (lat1 - lat0);
                double px, py;
                if (mapproj_forward(g_.plan, lon, lat, &px, &py) != 0 || !std::isfinite(px) ||
                    !std::isfinite(py)) {
                    whole = true;
                    break;
                }
                ux0 = std::min(ux0, px), ux1 = std::max(ux1, px);
                uy0 = std::min(uy0, py), uy1 = std::max(uy1, py);
            }
        if (!whole) {
            double mx = 0.01 * (ux1 - ux0) + 1.0, my = 0.01 * (uy1 - uy0) + 1.0;
            ux0 -= mx, ux1 += mx, uy0 -= my, uy1 += my;
        }
    }
    double dx0 = static_cast<double>(fi.x0), dy0 = static_cast<double>(fi.y0);
    double dx1 = dx0 + static_cast<double>(fi.width), dy1 = dy0 + static_cast<double>(fi.height);
    double lx0 = whole ? dx0 : std::floor(ux0 * scale) - 1, ly0 = whole ? dy0 : std::floor(uy0 * scale) - 1;
    double lx1 = whole ? dx1 : std::ceil(ux1 * scale) + 1, ly1 = whole ? dy1 : std::ceil(uy1 * scale) + 1;
    if (!(lx0 <= lx1 && ly0 <= ly1)) /* NaN too */
        return false;
    /* nothing lies outside the domain: clamping keeps the integers exact */
    lx0 = std::max(lx0, dx0 - 1), ly0 = std::max(ly0, dy0 - 1);
    lx1 = std::min(lx1, dx1 + 1), ly1 = std::min(ly1, dy1 + 1);
    if (lx0 > lx1 || ly0 > ly1)
        return false;
    /* a hostile header's domain may reach past what int64 holds as a double */
    const double lim = 4611686018427387904.0; /* 2^62 */
    lx0 = std::min(std::max(lx0, -lim), lim), ly0 = std::min(std::max(ly0, -lim), lim);
    lx1 = std::min(std::max(lx1, -lim), lim), ly1 = std::min(std::max(ly1, -lim), lim);
    *x0 = static_cast<int64_t>(lx0), *y0 = static_cast<int64_t>(ly0);
    *x1 = static_cast<int64_t>(lx1), *y1 = static_cast<int64_t>(ly1);
    return true;
}

/* ---- layers ------------------------------------------------------------------------ */

HPFCLayer::HPFCLayer(HPFCDataset *ds, LayerKind kind, const std::string &name,
                     OGRwkbGeometryType type)
    : ds_(ds), kind_(kind)
{
    defn_ = new OGRFeatureDefn(name.c_str());
    defn_->Reference();
    defn_->SetGeomType(type);
    if (ds->srs_)
        defn_->GetGeomFieldDefn(0)->SetSpatialRef(ds->srs_);
    SetDescription(defn_->GetName());
}

HPFCLayer::~HPFCLayer()
{
    ogr_shapes_fields_free(fields_, field_count_);
    defn_->Release();
}

void HPFCLayer::IndexMembers()
{
    bool ascending = true;
    for (size_t k = 1; ascending && k < members_.size(); k++)
        ascending = members_[k - 1].fid < members_[k].fid;
    if (ascending)
        return;
    by_fid_.resize(members_.size());
    for (size_t k = 0; k < members_.size(); k++)
        by_fid_[k] = k;
    /* stable: of a repeated fid, its first feature comes first */
    std::stable_sort(by_fid_.begin(), by_fid_.end(),
                     [&](size_t a, size_t b) { return members_[a].fid < members_[b].fid; });
}

/* Every source layer's members, each feature's layer and fid read once:
 * on the first read that needs them (a layer of a file of several, or a
 * GetFeature), so that opening the file reads no feature. False after a
 * CPLError, the lists left empty. */
bool HPFCDataset::ListMembers()
{
    if (members_listed_ || !have_features_)
        return true;
    for (uint32_t k = 0; k < features_.features; k++) {
        hpfc_feature ft;
        int st = hpfc_file_get_feature(file_, k, &ft);
        if (st) {
            status_error("feature", st);
            for (uint32_t l = 0; l < features_.layers; l++)
                layers_[l]->ForgetMembers();
            return false;
        }
        layers_[ft.layer]->AddMember(k, ft.fid);
    }
    for (uint32_t l = 0; l < features_.layers; l++)
        layers_[l]->IndexMembers();
    members_listed_ = true;
    return true;
}

/* The member with this fid (the first in file order of a repeated one). */
const HPFCLayer::Member *HPFCLayer::FindFid(int64_t fid) const
{
    if (by_fid_.empty()) {
        auto it = std::lower_bound(members_.begin(), members_.end(), fid,
                                   [](const Member &m, int64_t f) { return m.fid < f; });
        return it != members_.end() && it->fid == fid ? &*it : nullptr;
    }
    auto it = std::lower_bound(by_fid_.begin(), by_fid_.end(), fid,
                               [&](size_t k, int64_t f) { return members_[k].fid < f; });
    return it != by_fid_.end() && members_[*it].fid == fid ? &members_[*it] : nullptr;
}

static void add_field(OGRFeatureDefn *defn, const char *name, OGRFieldType t, int *index)
{
    OGRFieldDefn fd(name, t);
    defn->AddFieldDefn(&fd);
    *index = defn->GetFieldCount() - 1;
}

bool HPFCLayer::Init()
{
    const bool features = ds_->have_features_;
    if (kind_ == LayerKind::Source) {
        if (ogr_shapes_fields(&ds_->g_, 0, &fields_, &field_count_)) {
            CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s", ds_->g_.why);
            return false;
        }
        for (size_t c = 0; c < field_count_; c++) {
            OGRFieldDefn fd(fields_[c].name, fields_[c].type);
            defn_->AddFieldDefn(&fd);
        }
        /* the fid the tools print is the OGR FID; ogr2ogr keeps it under this name */
        uint32_t col;
        if (hpfc_attr_find(ds_->file_, "fid", 3, &col) != HPFC_OK &&
            defn_->GetFieldIndex("fid") < 0)
            fid_column_ = "fid";
    } else if (kind_ == LayerKind::Faces) {
        if (features) {
            add_field(defn_, "features", OFTInteger, &count_field_);
            add_field(defn_, "fids", OFTString, &fids_field_);
            if (ds_->features_.key_field)
                add_field(defn_, "keys", OFTString, &keys_field_);
        }
        fid_column_ = "face";
    } else {
        add_field(defn_, "left_face", OFTInteger64, &left_face_);
        add_field(defn_, "right_face", OFTInteger64, &right_face_);
        if (features) {
            add_field(defn_, "left_fids", OFTString, &left_fids_);
            add_field(defn_, "right_fids", OFTString, &right_fids_);
        }
        hpfc_edge_links_info li;
        if (hpfc_file_get_edge_links(ds_->file_, &li) == HPFC_OK)
            add_field(defn_, "line_fids", OFTString, &line_fids_);
        fid_column_ = "edge";
    }
    ResetReading();
    return true;
}

uint64_t HPFCLayer::Count() const
{
    if (kind_ == LayerKind::Source)
        return count_;
    if (kind_ == LayerKind::Faces) {
        uint64_t n = hpfc_shapes_face_count(ds_->shapes_);
        return n ? n - 1 : 0;
    }
    return ds_->geometry_.edges;
}

void HPFCLayer::ResetReading()
{
    cursor_ = 0;
    windowed_ = m_poFilterGeom != nullptr;
    if (!windowed_ || window_built_)
        return; /* the same filter's hits again (GDAL resets a read more than once) */
    hits_.clear();
    if (BuildWindow())
        window_built_ = true;
    else
        hits_.clear(); /* after an error: nothing, and the next reset tries again */
}

/* The candidates of the spatial filter: what the tree's window query
 * finds in the lattice window around the filter's envelope. */
bool HPFCLayer::BuildWindow()
{
    int64_t x0, y0, x1, y1;
    if (!ds_->Window(m_sFilterEnvelope, &x0, &y0, &x1, &y1))
        return true; /* the filter misses the map */
    unsigned what = kind_ == LayerKind::Source  ? HPFC_WINDOW_FEATURES
                    : kind_ == LayerKind::Faces ? HPFC_WINDOW_FACES
                                                : HPFC_WINDOW_EDGES;
    hpfc_window_hits h;
    int st = hpfc_shapes_window(ds_->shapes_, x0, y0, x1, y1, what, &h);
    if (st) {
        status_error("spatial filter", st);
        return false;
    }
    if (kind_ == LayerKind::Source && !all_ && !ds_->ListMembers())
        return false;
    if (kind_ == LayerKind::Source && all_) {
        hits_.assign(h.feature, h.feature + h.feature_count);
    } else if (kind_ == LayerKind::Source) {
        /* members_ is in ascending feature order, as the hits are: each
         * hit found from the last by binary search, O(hits log members) */
        auto m = members_.begin();
        for (size_t k = 0; k < h.feature_count; k++) {
            m = std::lower_bound(m, members_.end(), h.feature[k],
                                 [](const Member &a, hpfc_id f) { return a.feature < f; });
            if (m != members_.end() && m->feature == h.feature[k])
                hits_.push_back(static_cast<size_t>(m - members_.begin()));
        }
    } else if (kind_ == LayerKind::Faces) {
        for (size_t k = 0; k < h.face_count; k++)
            if (h.face[k] != 0)
                hits_.push_back(h.face[k]);
    } else {
        hits_.assign(h.edge, h.edge + h.edge_count);
    }
    return true;
}

void HPFCLayer::SetSpatialFilter(OGRGeometry *geom)
{
    if (InstallFilter(geom)) {
        window_built_ = false;
        ResetReading();
    }
}

/* A feature list "fid fid ..." of a face's features into `field`. */
static bool face_fids(HPFCDataset *ds, OGRFeature *f, hpfc_id face, int field)
{
    return ogr_shapes_face_features(&ds->g_, OGRFeature::ToHandle(f), face, -1, field, -1) == 0;
}

/* Feature, face or edge `id`'s geometry attached to f (a feature with
 * none gets none); false after a CPLError. */
bool HPFCLayer::AttachGeometry(OGRFeature *f, uint64_t id)
{
    ogr_shapes *g = &ds_->g_;
    OGRGeometryH geom = nullptr;
    bool ok;
    if (kind_ == LayerKind::Source)
        ok = ogr_shapes_feature_geometry(g, id, &geom) == 0;
    else
        ok = (geom = kind_ == LayerKind::Faces ? ogr_shapes_face_geometry(g, id)
                                               : ogr_shapes_edge_geometry(g, id)) != nullptr;
    if (!ok) {
        CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s", g->why);
        return false;
    }
    if (geom) {
        OGRGeometry *og = OGRGeometry::FromHandle(geom);
        og->assignSpatialReference(ds_->srs_);
        f->SetGeometryDirectly(og);
    }
    return true;
}

/* Feature, face or edge `id` with its fields (those not ignored) and, when
 * asked, its geometry; nullptr after a CPLError. */
OGRFeature *HPFCLayer::Build(uint64_t id, bool with_geometry)
{
    ogr_shapes *g = &ds_->g_;
    auto f = std::make_unique<OGRFeature>(defn_);
    bool ok = true;
    if (kind_ == LayerKind::Source) {
        hpfc_feature feat;
        int st = hpfc_file_get_feature(ds_->file_, id, &feat);
        if (st) {
            status_error("feature", st);
            return nullptr;
        }
        ok = ogr_shapes_fill(g, OGRFeature::ToHandle(f.get()), 0, fields_, field_count_, id,
                             &feat) == 0;
        f->SetFID(feat.fid);
    } else if (kind_ == LayerKind::Faces) {
        ok = !ds_->have_features_ ||
             ogr_shapes_face_features(g, OGRFeature::ToHandle(f.get()), id, count_field_,
                                      fids_field_, keys_field_) == 0;
        f->SetFID(static_cast<GIntBig>(id));
    } else {
        hpfc_id left, right;
        int st = hpfc_geometry_edge_faces(ds_->file_, id, &left, &right);
        if (st) {
            status_error("edge", st);
            return nullptr;
        }
        f->SetField(left_face_, static_cast<GIntBig>(left));
        f->SetField(right_face_, static_cast<GIntBig>(right));
        if (ds_->have_features_)
            ok = face_fids(ds_, f.get(), left, left_fids_) &&
                 face_fids(ds_, f.get(), right, right_fids_);
        if (ok && line_fids_ >= 0) {
            uint32_t n = 0;
            std::string text;
            st = hpfc_edge_feature_count(ds_->file_, id, &n);
            for (uint32_t k = 0; !st && k < n; k++) {
                hpfc_id index;
                hpfc_feature feat;
                if (!(st = hpfc_edge_feature_id(ds_->file_, id, k, &index)) &&
                    !(st = hpfc_file_get_feature(ds_->file_, index, &feat)))
                    text += (text.empty() ? "" : " ") + std::to_string(feat.fid);
            }
            if (st) {
                status_error("edge features", st);
                return nullptr;
            }
            f->SetField(line_fids_, text.c_str());
        }
        f->SetFID(static_cast<GIntBig>(id));
    }
    if (!ok) {
        CPLError(CE_Failure, CPLE_AppDefined, "HPFC: %s", g->why);
        return nullptr;
    }
    for (int i = 0; i < defn_->GetFieldCount(); i++)
        if (defn_->GetFieldDefn(i)->IsIgnored())
            f->UnsetField(i);
    if (with_geometry && !AttachGeometry(f.get(), id))
        return nullptr;
    return f.release();
}

/* The attribute filter's fields: whether it reads the geometry
 * (OGR_GEOMETRY, OGR_GEOM_AREA, OGR_GEOM_WKT). Without, it is evaluated
 * before the geometry is assembled. */
OGRErr HPFCLayer::SetAttributeFilter(const char *where)
{
    OGRErr err = OGRLayer::SetAttributeFilter(where);
    attr_reads_geometry_ = false;
    if (m_poAttrQuery) {
        char **used = m_poAttrQuery->GetUsedFields();
        for (char **u = used; u && *u; u++)
            attr_reads_geometry_ = attr_reads_geometry_ || STARTS_WITH_CI(*u, "OGR_GEOM");
        CSLDestroy(used);
    }
    return err;
}

OGRFeature *HPFCLayer::GetNextFeature()
{
    /* the geometry is assembled (the bulk of a feature's cost) only for
     * candidates that pass an attribute filter that does not read it, and
     * only when it is not ignored or the spatial filter must test it */
    const bool want_geometry = !defn_->IsGeometryIgnored() || m_poFilterGeom != nullptr;
    const bool attributes_first = m_poAttrQuery && !attr_reads_geometry_;
    if (kind_ == LayerKind::Source && !all_ && !ds_->ListMembers())
        return nullptr;
    for (;;) {
        uint64_t id;
        if (windowed_) {
            if (cursor_ >= hits_.size())
                return nullptr;
            id = hits_[cursor_++];
        } else {
            if (cursor_ >= Count())
                return nullptr;
            id = cursor_++;
        }
        if (kind_ == LayerKind::Source && !all_) {
            if (id >= members_.size()) /* the counts at open agree; a guard */
                return nullptr;
            id = members_[id].feature; /* else the feature itself */
        }
        else if (kind_ == LayerKind::Faces && !windowed_)
            id++; /* the unbounded face has no polygon */
        std::unique_ptr<OGRFeature> f(Build(id, want_geometry && !attributes_first));
        if (!f)
            return nullptr;
        if (attributes_first && !m_poAttrQuery->Evaluate(f.get()))
            continue;
        if (attributes_first && want_geometry && !AttachGeometry(f.get(), id))
            return nullptr;
        if (!FilterGeometry(f->GetGeometryRef()) ||
            (m_poAttrQuery && !attributes_first && !m_poAttrQuery->Evaluate(f.get())))
            continue;
        if (defn_->IsGeometryIgnored())
            f->SetGeometryDirectly(nullptr); /* built for the spatial filter only */
        return f.release();
    }
}

/* Without filters the cursor moves there in O(1); with them, as OGR does
 * (index counts the features the filters pass). */
OGRErr HPFCLayer::SetNextByIndex(GIntBig index)
{
    if (m_poFilterGeom || m_poAttrQuery)
        return OGRLayer::SetNextByIndex(index);
    if (index < 0 || static_cast<uint64_t>(index) >= Count())
        return OGRERR_FAILURE;
    cursor_ = static_cast<uint64_t>(index);
    return OGRERR_NONE;
}

OGRFeature *HPFCLayer::GetFeature(GIntBig fid)
{
    uint64_t id;
    if (kind_ == LayerKind::Source) {
        if (!ds_->ListMembers())
            return nullptr;
        const Member *m = FindFid(fid);
        if (!m)
            return nullptr;
        id = m->feature;
    } else if (fid < (kind_ == LayerKind::Faces ? 1 : 0) ||
               static_cast<uint64_t>(fid) >= Count() + (kind_ == LayerKind::Faces)) {
        return nullptr;
    } else {
        id = static_cast<uint64_t>(fid);
    }
    return Build(id, !defn_->IsGeometryIgnored());
}

GIntBig HPFCLayer::GetFeatureCount(int force)
{
    if (m_poFilterGeom || m_poAttrQuery)
        return OGRLayer::GetFeatureCount(force);
    return static_cast<GIntBig>(Count());
}

OGRErr HPFCLayer::GetExtent(OGREnvelope *env, int force)
{
    (void)force;
    if (Count() == 0)
        return OGRERR_FAILURE;
    return ds_->Extent(env) ? OGRERR_NONE : OGRERR_FAILURE;
}

int HPFCLayer::TestCapability(const char *cap)
{
    if (EQUAL(cap, OLCRandomRead) || EQUAL(cap, OLCFastGetExtent) ||
        EQUAL(cap, OLCFastSpatialFilter) || EQUAL(cap, OLCStringsAsUTF8) ||
        EQUAL(cap, OLCIgnoreFields))
        return TRUE;
    if (EQUAL(cap, OLCFastFeatureCount) || EQUAL(cap, OLCFastSetNextByIndex))
        return !m_poFilterGeom && !m_poAttrQuery;
    return FALSE;
}

} // namespace

/* ---- registration ------------------------------------------------------------------- */

void GDALRegister_HPFC()
{
    if (!GDAL_CHECK_VERSION("HPFC"))
        return;
    if (GDALGetDriverByName("HPFC") != nullptr)
        return;
    auto *driver = new GDALDriver();
    driver->SetDescription("HPFC");
    driver->SetMetadataItem(GDAL_DCAP_VECTOR, "YES");
    driver->SetMetadataItem(GDAL_DMD_LONGNAME, "hierarchical Planar Face Complex (hpfc)");
    driver->SetMetadataItem(GDAL_DMD_EXTENSION, "hpfc");
    driver->SetMetadataItem(GDAL_DMD_HELPTOPIC, "https://github.com/hpfc/hpfc");
    driver->SetMetadataItem(GDAL_DCAP_VIRTUALIO, "YES");
    driver->SetMetadataItem(GDAL_DMD_SUPPORTED_SQL_DIALECTS, "OGRSQL SQLITE");
    driver->SetMetadataItem(
        GDAL_DMD_OPENOPTIONLIST,
        "<OpenOptionList>"
        "  <Option name='VERIFY_CHECKSUMS' type='boolean' default='YES' "
        "description='Check every section CRC-32C on open (reads the whole file once)'/>"
        "</OpenOptionList>");
    driver->pfnIdentify = identify;
    driver->pfnOpen = HPFCDataset::Open;
    hpfc_gdal_register_create(driver);
    GetGDALDriverManager()->RegisterDriver(driver);
}

/* GDAL's plugin loader calls RegisterOGR<NAME> for ogr_<NAME>.so. */
extern "C" HPFC_GDAL_EXPORT void RegisterOGRHPFC()
{
    GDALRegister_HPFC();
}

extern "C" HPFC_GDAL_EXPORT void GDALRegisterMe()
{
    GDALRegister_HPFC();
}
