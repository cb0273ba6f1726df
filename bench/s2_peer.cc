/*
 * s2_peer.cc: see s2_peer.h.
 *
 * Rings come from GDAL as they are in the source: their orientation is
 * not trusted. On the sphere a loop's interior is on its left, so each
 * ring is turned so that an outer ring encloses less than a hemisphere and
 * a hole more (its complement is the hole). S2LaxPolygonShape asks no
 * validity of the loops, so the self-touching rings of public layers load
 * as they are.
 */
#include "s2_peer.h"

#include <algorithm>
#include <memory>
#include <vector>

#include "s2/encoded_s2shape_index.h"
#include "s2/mutable_s2shape_index.h"
#include "s2/s2contains_point_query.h"
#include "s2/s2latlng.h"
#include "s2/s2lax_polygon_shape.h"
#include "s2/s2loop_measures.h"
#include "s2/s2shapeutil_coding.h"
#include "s2/util/coding/coder.h"

struct s2_peer {
    std::vector<std::vector<S2Point>> loops; // of the polygon being added
    std::vector<int64_t> ids;                // shape id -> polygon id
    MutableS2ShapeIndex building;
    Encoder encoder;
    std::unique_ptr<Decoder> decoder;
    EncodedS2ShapeIndex index;
    std::unique_ptr<S2ContainsPointQuery<EncodedS2ShapeIndex>> query;
    bool open = false;
};

static void flush(s2_peer *p)
{
    if (p->loops.empty())
        return;
    p->building.Add(std::make_unique<S2LaxPolygonShape>(p->loops));
    p->loops.clear();
}

extern "C" s2_peer *s2_peer_create(void)
{
    return new s2_peer;
}

extern "C" void s2_peer_free(s2_peer *p)
{
    delete p;
}

extern "C" void s2_peer_begin(s2_peer *p, int64_t id)
{
    flush(p);
    p->ids.push_back(id);
}

extern "C" void s2_peer_ring(s2_peer *p, const double *lon, const double *lat, size_t n, int shell)
{
    if (n > 1 && lon[0] == lon[n - 1] && lat[0] == lat[n - 1])
        n--;
    if (n < 3)
        return;
    std::vector<S2Point> loop;
    loop.reserve(n);
    for (size_t k = 0; k < n; k++) {
        S2Point v = S2LatLng::FromDegrees(lat[k], lon[k]).ToPoint();
        if (loop.empty() || loop.back() != v)
            loop.push_back(v);
    }
    if (loop.size() < 3)
        return;
    /* outer rings small, holes large (the complement of a small region) */
    double area = S2::GetSignedArea(S2PointLoopSpan(loop));
    if ((shell != 0) != (area > 0))
        std::reverse(loop.begin(), loop.end());
    p->loops.push_back(std::move(loop));
}

extern "C" int s2_peer_build(s2_peer *p, size_t *bytes)
{
    flush(p);
    if ((size_t)p->building.num_shape_ids() != p->ids.size())
        return -1;
    p->building.ForceBuild();
    if (!s2shapeutil::CompactEncodeTaggedShapes(p->building, &p->encoder))
        return -1;
    p->building.Encode(&p->encoder);
    *bytes = p->encoder.length();
    /* one decoder: the shapes' vector first, then the index after it */
    p->decoder = std::make_unique<Decoder>(p->encoder.base(), p->encoder.length());
    auto factory = s2shapeutil::LazyDecodeShapeFactory(p->decoder.get());
    if (!p->index.Init(p->decoder.get(), factory))
        return -1;
    p->query = std::make_unique<S2ContainsPointQuery<EncodedS2ShapeIndex>>(&p->index);
    p->building.Clear(); /* the encoded buffer is the only copy queried */
    p->open = true;
    return 0;
}

extern "C" void s2_peer_point(double lon, double lat, double xyz[3])
{
    S2Point v = S2LatLng::FromDegrees(lat, lon).ToPoint();
    xyz[0] = v.x(), xyz[1] = v.y(), xyz[2] = v.z();
}

extern "C" int64_t s2_peer_locate(s2_peer *p, const double xyz[3])
{
    int64_t found = -1;
    p->query->VisitContainingShapes(S2Point(xyz[0], xyz[1], xyz[2]), [&](S2Shape *shape) {
        found = p->ids[(size_t)shape->id()];
        return false;
    });
    return found;
}
