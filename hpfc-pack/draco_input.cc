// Draco meshes as hpfc graphs (draco_input.h), over Draco's C++ API. It
// decodes with Draco, copies the x, y of the positions (as doubles, exact for
// every float) and the triangles into plain arrays, and leaves the rest to
// mesh_graph_build(). Every entry point catches all exceptions.
#include "draco_input.h"

#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#include "draco/compression/decode.h"

namespace {

int fail(hpfc_diag *diag, int status, const char *fmt, ...)
{
    if (diag) {
        std::memset(diag, 0, sizeof *diag);
        diag->status = status;
        diag->edge[0] = diag->edge[1] = -1;
        va_list ap;
        va_start(ap, fmt);
        std::vsnprintf(diag->message, sizeof diag->message, fmt, ap);
        va_end(ap);
    }
    return status;
}

// Draco's reason, or a fallback when it gave none.
const char *reason(const draco::Status &status, const char *fallback)
{
    return status.error_msg_string().empty() ? fallback : status.error_msg();
}

// Doubles hold every value of the position types up to 32 bits exactly;
// 64-bit integers only up to 2^53, beyond which nothing fits the lattice
// exactly anyway (HPFC_COORD_MAX is 2^40).
bool position_type_ok(draco::DataType t)
{
    switch (t) {
    case draco::DT_INT8: case draco::DT_UINT8: case draco::DT_INT16: case draco::DT_UINT16:
    case draco::DT_INT32: case draco::DT_UINT32: case draco::DT_INT64: case draco::DT_UINT64:
    case draco::DT_FLOAT32: case draco::DT_FLOAT64:
        return true;
    default:
        return false;
    }
}

int decode(const void *data, size_t size, const draco_options *opts, hpfc_graph **out,
           hpfc_diag *diag)
{
    if (!draco_has_magic(data, size))
        return fail(diag, DRACO_E_DECODE, "not a Draco file (it does not start with \"DRACO\")");
    draco::DecoderBuffer buffer;
    buffer.Init(static_cast<const char *>(data), size);
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok())
        return fail(diag, DRACO_E_DECODE, "not a valid Draco file: %s",
                    reason(type.status(), "unreadable header"));
    if (type.value() == draco::POINT_CLOUD)
        return fail(diag, DRACO_E_NOT_MESH, "a Draco point cloud, not a mesh: hpfc-pack needs "
                                            "triangles");
    if (type.value() != draco::TRIANGULAR_MESH)
        return fail(diag, DRACO_E_NOT_MESH, "not a Draco triangle mesh (geometry type %d)",
                    static_cast<int>(type.value()));
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok())
        return fail(diag, DRACO_E_DECODE, "corrupt or unsupported Draco mesh: %s",
                    reason(decoded.status(), "the decoder gave no reason"));
    std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (!mesh)
        return fail(diag, DRACO_E_DECODE, "corrupt Draco mesh: the decoder returned nothing");
    const draco::PointAttribute *att = mesh->GetNamedAttribute(draco::GeometryAttribute::POSITION);
    if (!att)
        return fail(diag, DRACO_E_NOT_MESH, "the Draco mesh has no positions");
    if (att->num_components() < 2 || !position_type_ok(att->data_type()))
        return fail(diag, DRACO_E_NOT_MESH, "the Draco mesh's positions are not 2-D or 3-D "
                                            "numbers (%d components of type %d)",
                    static_cast<int>(att->num_components()), static_cast<int>(att->data_type()));
    const size_t npoints = mesh->num_points(), ntri = mesh->num_faces();
    if (ntri == 0)
        return fail(diag, HPFC_E_EMPTY, "the Draco mesh has no triangle (%zu points)", npoints);

    std::vector<double> xy(2 * npoints);
    const bool int64 = att->data_type() == draco::DT_INT64 || att->data_type() == draco::DT_UINT64;
    for (size_t p = 0; p < npoints; p++) {
        const draco::AttributeValueIndex avi =
            att->mapped_index(draco::PointIndex(static_cast<uint32_t>(p)));
        if (avi.value() >= att->size() || !att->ConvertValue<double>(avi, 2, &xy[2 * p]))
            return fail(diag, DRACO_E_DECODE, "corrupt Draco mesh: no position for point %zu", p);
        if (int64 && (std::fabs(xy[2 * p]) > 9007199254740992.0 ||
                      std::fabs(xy[2 * p + 1]) > 9007199254740992.0))
            return fail(diag, HPFC_E_EXTENT, "mesh point %zu: a 64-bit integer coordinate "
                                             "beyond 2^53", p);
    }
    std::vector<uint32_t> tri(3 * ntri);
    for (size_t f = 0; f < ntri; f++) {
        const draco::Mesh::Face &face = mesh->face(draco::FaceIndex(static_cast<uint32_t>(f)));
        for (int k = 0; k < 3; k++)
            tri[3 * f + k] = face[k].value();
    }
    mesh.reset(); // the decoded mesh is no longer needed: free it before building
    return mesh_graph_build(xy.data(), 2, npoints, tri.data(), ntri, opts ? &opts->mesh : nullptr,
                            out, opts ? opts->stats : nullptr, diag);
}

} // namespace

extern "C" int draco_input_available(void)
{
    return 1;
}

extern "C" int draco_graph_from_memory(const void *data, size_t size, const draco_options *opts,
                                       hpfc_graph **out, hpfc_diag *diag)
{
    if (!out || (!data && size))
        return fail(diag, HPFC_E_ARG, "no input or no output graph");
    *out = nullptr;
    try {
        return decode(data, size, opts, out, diag);
    } catch (const std::bad_alloc &) {
        return fail(diag, HPFC_E_NOMEM, "out of memory decoding the Draco mesh");
    } catch (const std::exception &e) {
        return fail(diag, DRACO_E_DECODE, "the Draco decoder failed: %s", e.what());
    } catch (...) {
        return fail(diag, DRACO_E_DECODE, "the Draco decoder failed");
    }
}

extern "C" int draco_read_graph(const char *path, const draco_options *opts, hpfc_graph **out,
                                hpfc_diag *diag)
{
    if (!out || !path)
        return fail(diag, HPFC_E_ARG, "no path or no output graph");
    *out = nullptr;
    try {
        std::unique_ptr<std::FILE, int (*)(std::FILE *)> f(std::fopen(path, "rb"), std::fclose);
        if (!f)
            return fail(diag, HPFC_E_IO, "%s", std::strerror(errno));
        std::vector<char> bytes;
        char chunk[1 << 16];
        size_t n;
        while ((n = std::fread(chunk, 1, sizeof chunk, f.get())) > 0)
            bytes.insert(bytes.end(), chunk, chunk + n);
        if (std::ferror(f.get()))
            return fail(diag, HPFC_E_IO, "read error");
        f.reset();
        return decode(bytes.data(), bytes.size(), opts, out, diag);
    } catch (const std::bad_alloc &) {
        return fail(diag, HPFC_E_NOMEM, "out of memory decoding the Draco mesh");
    } catch (const std::exception &e) {
        return fail(diag, DRACO_E_DECODE, "the Draco decoder failed: %s", e.what());
    } catch (...) {
        return fail(diag, DRACO_E_DECODE, "the Draco decoder failed");
    }
}
