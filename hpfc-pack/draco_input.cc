// Draco meshes as hpfc graphs (draco_input.h), over Draco's C++ API. It
// decodes with Draco, copies the x, y of the positions (as doubles, exact for
// every float) and the triangles into plain arrays, and leaves the rest to
// mesh_graph_build(). Every entry point catches all exceptions.
#include "draco_input.h"

#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdint>
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

// ---- declared sizes ----------------------------------------------------------
//
// Draco sizes its tables from the counts of the connectivity header before it
// reads anything behind them, and a metadata entry's buffer from its declared
// length: a 150-byte file declaring 155 million faces made it allocate 3 GB.
// So the counts are read first, as the Draco bitstream defines them (versions
// 1.0 to 2.2), and a mesh declaring more faces or vertices than
// kMaxCountPerByte per byte of the file is refused. Real meshes stay far
// below: a perfectly regular 1000 x 1000 grid at Draco's strongest settings
// takes 68 faces per byte (684 when its positions are quantized to 1 bit,
// which leaves a mesh hpfc-pack cannot use). Bytes this reading cannot make
// sense of are left to Draco, which then refuses them with its own reason.

constexpr uint64_t kMaxCountPerByte = 1024;
constexpr int kMaxMetadataDepth = 32;

// A bounds-checked reader over the file, little-endian, LEB128 varints.
struct Cursor {
    const unsigned char *p;
    size_t n;
    bool ok = true;

    uint64_t bytes(size_t k)
    {
        uint64_t v = 0;
        if (!ok || n < k) {
            ok = false;
            return 0;
        }
        for (size_t i = 0; i < k; i++)
            v |= static_cast<uint64_t>(p[i]) << (8 * i);
        p += k;
        n -= k;
        return v;
    }
    void skip(uint64_t k)
    {
        if (!ok || k > n) {
            ok = false;
            return;
        }
        p += k;
        n -= static_cast<size_t>(k);
    }
    uint64_t varint() // Draco's uint32 varint: at most 5 bytes
    {
        uint64_t v = 0;
        for (int i = 0; i < 5 && ok; i++) {
            uint64_t b = bytes(1);
            v |= (b & 0x7f) << (7 * i);
            if (!(b & 0x80))
                return v;
        }
        ok = false;
        return 0;
    }
    uint64_t count(bool fixed32) { return fixed32 ? bytes(4) : varint(); }
};

// Skips one metadata element (entries, then named sub-elements); false when
// it nests too deep or an entry claims more bytes than the file holds.
bool skip_metadata(Cursor &c, int depth, hpfc_diag *diag, int *status)
{
    if (depth > kMaxMetadataDepth) {
        *status = fail(diag, DRACO_E_DECODE, "corrupt Draco metadata: nested deeper than %d "
                                             "levels", kMaxMetadataDepth);
        return false;
    }
    for (uint64_t k = 0, entries = c.varint(); c.ok && k < entries; k++) {
        c.skip(c.bytes(1)); // name
        uint64_t len = c.varint();
        if (c.ok && len > c.n) {
            *status = fail(diag, DRACO_E_DECODE, "corrupt Draco metadata: an entry of %llu "
                                                 "bytes, with %zu left in the file",
                           static_cast<unsigned long long>(len), c.n);
            return false;
        }
        c.skip(len);
    }
    for (uint64_t k = 0, subs = c.varint(); c.ok && k < subs; k++) {
        c.skip(c.bytes(1)); // name
        if (!skip_metadata(c, depth + 1, diag, status))
            return false;
    }
    return true;
}

// HPFC_OK, or DRACO_E_DECODE when the declared counts or metadata sizes are
// impossible for a file of this size.
int check_declared_sizes(const void *data, size_t size, hpfc_diag *diag)
{
    Cursor c{static_cast<const unsigned char *>(data), size};
    c.skip(5); // "DRACO"
    const uint64_t major = c.bytes(1), minor = c.bytes(1);
    const uint64_t version = major << 8 | minor;
    const uint64_t type = c.bytes(1), method = c.bytes(1), flags = c.bytes(2);
    if (!c.ok || type != draco::TRIANGULAR_MESH)
        return HPFC_OK;
    int status = HPFC_OK;
    if (version >= 0x0103 && (flags & 0x8000)) { // geometry metadata
        for (uint64_t k = 0, atts = c.varint(); c.ok && k < atts; k++) {
            c.varint(); // attribute id
            if (!skip_metadata(c, 0, diag, &status))
                return status;
        }
        if (!skip_metadata(c, 0, diag, &status))
            return status;
    }
    const bool fixed32 = version < 0x0200; // counts were uint32 before 2.0
    uint64_t faces = 0, vertices = 0;
    if (method == draco::MESH_SEQUENTIAL_ENCODING) {
        // uint32 counts up to 2.1, varints from 2.2
        faces = c.count(version < 0x0202);
        vertices = c.count(version < 0x0202);
    } else if (method == draco::MESH_EDGEBREAKER_ENCODING) {
        c.skip(1); // traversal decoder type
        if (version < 0x0202)
            c.count(fixed32); // number of new vertices
        vertices = c.count(fixed32);
        faces = c.count(fixed32);
    }
    if (!c.ok)
        return HPFC_OK;
    const uint64_t limit = kMaxCountPerByte * size;
    if (faces > limit || vertices > limit)
        return fail(diag, DRACO_E_DECODE,
                    "implausible Draco mesh: it declares %llu faces and %llu vertices in %zu "
                    "bytes (hpfc-pack accepts at most %llu of each per byte)",
                    static_cast<unsigned long long>(faces),
                    static_cast<unsigned long long>(vertices), size,
                    static_cast<unsigned long long>(kMaxCountPerByte));
    return HPFC_OK;
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
    const int sizes = check_declared_sizes(data, size, diag);
    if (sizes != HPFC_OK)
        return sizes;
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
    std::vector<char> bytes;
    try {
        std::unique_ptr<std::FILE, int (*)(std::FILE *)> f(std::fopen(path, "rb"), std::fclose);
        if (!f)
            return fail(diag, HPFC_E_IO, "%s", std::strerror(errno));
        char chunk[1 << 16];
        size_t n;
        while ((n = std::fread(chunk, 1, sizeof chunk, f.get())) > 0)
            bytes.insert(bytes.end(), chunk, chunk + n);
        if (std::ferror(f.get()))
            return fail(diag, HPFC_E_IO, "read error");
    } catch (const std::bad_alloc &) {
        return fail(diag, HPFC_E_NOMEM, "out of memory reading the Draco mesh");
    }
    return draco_graph_from_memory(bytes.data(), bytes.size(), opts, out, diag);
}
