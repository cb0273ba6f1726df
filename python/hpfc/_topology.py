"""Topology questions: windows, neighbours, adjacency, nearest edges,
dissolve and mesh, each one call of the library (hpfc_shapes_window,
_feature_neighbours, _adjacency, _nearest_edge, _edges_within,
_features_polygons, _mesh) on the stored map.

Points and windows come in user coordinates (lattice x 10^unit_exp10,
floored onto the lattice exactly as locate() does), or with lonlat=True in
degrees through the file's projection. Lengths and distances come back in
user units (the plane of the file: metres of hpfc-pack's projection for a
lon/lat source). Features are named by index (0 .. features - 1) or by
their key (a string).
"""

from ._geometry import _ids

_TOUCH_EDGE, _TOUCH_VERTEX = 1, 2
_MESH_INTERIOR, _MESH_EXTERIOR = 1, 2
_GROUP_NONE = 2**32 - 1


class _LazyNumpy:
    def __getattr__(self, name):
        import numpy

        globals()["np"] = numpy
        return getattr(numpy, name)


np = _LazyNumpy()


def _f64(raw):
    return np.frombuffer(raw, dtype=np.float64)


def _u64(raw):
    return np.frombuffer(raw, dtype=np.uint64)


def _i64(raw):
    return np.frombuffer(raw, dtype=np.int64)


def _finite(value, name):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: a number expected, got {type(value).__name__}") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise ValueError(f"{name}: a finite number expected, got {v}")
    return v


class TopologyMixin:
    """The topology methods of hpfc.File (needs GEOM and LABL; FEAT for
    features)."""

    # ---- arguments -------------------------------------------------------------------

    def _user_scale(self):
        return 10.0 ** self.unit_exp10

    def _feature_index(self, feature):
        info = self.features_info
        if info is None:
            raise ValueError("the file has no features (FEAT section)")
        if isinstance(feature, str):
            keys = self.__dict__.get("_key_index")
            if keys is None:
                keys = {}
                for k, key in enumerate(self.feature_keys()):
                    if key is not None:
                        keys.setdefault(key, k)
                self.__dict__["_key_index"] = keys
            if feature not in keys:
                raise KeyError(f"no feature has the key {feature!r}")
            return keys[feature]
        if isinstance(feature, bool) or not isinstance(feature, (int, np.integer)):
            raise TypeError(f"feature: an index or a key expected, got {type(feature).__name__}")
        if not 0 <= feature < info["features"]:
            raise IndexError(f"feature {feature} out of range")
        return int(feature)

    def _points(self, x, y, lonlat):
        """Lattice points of user (or lon/lat) coordinates; ValueError for
        one beyond the lattice or that does not project."""
        u = np.atleast_1d(np.asarray(x, dtype=np.float64)).ravel()
        v = np.atleast_1d(np.asarray(y, dtype=np.float64)).ravel()
        u, v = np.broadcast_arrays(u, v)
        if not (np.isfinite(u).all() and np.isfinite(v).all()):
            raise ValueError("points: finite coordinates expected (NaN or infinity given)")
        if lonlat and ((np.abs(u) > 180).any() or (np.abs(v) > 90).any()):
            raise ValueError("points: longitudes in [-180, 180] and latitudes in [-90, 90] "
                             "expected")
        u, v = np.ascontiguousarray(u), np.ascontiguousarray(v)
        n = u.size
        lx, ly = np.empty(n, np.int64), np.empty(n, np.int64)
        ok = np.empty(n, np.uint8)
        self._lattice_points(u, v, lx, ly, ok, lonlat)
        bad = np.flatnonzero(ok == 0)
        lim = 2**41
        bad = np.union1d(bad, np.flatnonzero((np.abs(lx) > lim) | (np.abs(ly) > lim)))
        if bad.size:
            k = int(bad[0])
            raise ValueError(f"point {k} ({u[k]}, {v[k]}) lies beyond the lattice or does not "
                             "project")
        return lx, ly

    # ---- windows ---------------------------------------------------------------------

    def window(self, x0, y0, x1, y1, lonlat=False, lattice=False):
        """What meets the closed rectangle [x0, x1] x [y0, y1] (user
        coordinates; lattice=True: lattice integers; lonlat=True: W, S, E, N
        degrees, the box around the projected outline): a dict of numpy
        arrays "features", "faces", "edges" (ids, ascending) and
        "features_inside", "faces_inside", "edges_inside" (bool: it lies
        wholly in the window)."""
        if lattice:
            w = [int(v) for v in (x0, y0, x1, y1)]
        else:
            vals = [_finite(v, n) for v, n in zip((x0, y0, x1, y1), ("x0", "y0", "x1", "y1"))]
            if lonlat:
                s = np.linspace(0.0, 1.0, 33)
                lon = np.concatenate([vals[0] + s * (vals[2] - vals[0]), np.full(33, vals[2]),
                                      vals[0] + s * (vals[2] - vals[0]), np.full(33, vals[0])])
                lat = np.concatenate([np.full(33, vals[1]), vals[1] + s * (vals[3] - vals[1]),
                                      np.full(33, vals[3]), vals[1] + s * (vals[3] - vals[1])])
                lx, ly = self._points(lon, lat, True)
                w = [int(lx.min()), int(ly.min()), int(lx.max()), int(ly.max())]
            else:
                lx, ly = self._points([vals[0], vals[2]], [vals[1], vals[3]], False)
                w = [int(lx[0]), int(ly[0]), int(lx[1]), int(ly[1])]
        if w[0] > w[2] or w[1] > w[3]:
            raise ValueError("window: x0 <= x1 and y0 <= y1 expected")
        what = 1 | 2 | (4 if self.has_features else 0)
        with self._shapes()._lock:
            raw = self._shapes()._c._window(w[0], w[1], w[2], w[3], what)
        out = {}
        for k, name in enumerate(("faces", "edges", "features")):
            out[name] = _u64(raw[2 * k])
            out[name + "_inside"] = np.frombuffer(raw[2 * k + 1], dtype=np.uint8).astype(bool)
        return out

    # ---- neighbours --------------------------------------------------------------------

    def neighbours(self, feature):
        """The features that touch `feature` (an index or a key): a dict of
        numpy arrays "feature" (indices, ascending), "touch" ("edge": a
        shared border, "vertex": only a shared vertex), "length" (of the
        shared border, user units; 0 for a vertex), "edges" (per neighbour,
        the shared edges' ids). From the stored side labels: no geometry
        is tested."""
        k = self._feature_index(feature)
        with self._shapes()._lock:
            ids, touch, length, start, edges = self._shapes()._c._neighbours(k)
        touch = np.frombuffer(touch, dtype=np.uint8)
        start, edges = _i64(start), _u64(edges)
        return {"feature": _u64(ids).astype(np.int64),
                "touch": np.where(touch == _TOUCH_EDGE, "edge", "vertex"),
                "length": _f64(length) * self._user_scale(),
                "edges": [edges[start[j]:start[j + 1]] for j in range(len(ids) // 8)]}

    def adjacency(self, queen=True, weights=False):
        """The contiguity of the features as a symmetric scipy.sparse CSR
        matrix (features x features): 1 where two features share a border
        edge, and with queen=True also where they share only a vertex;
        weights=True puts the shared border's length (user units) instead
        (0-length vertex contacts stay stored, explicitly). Needs scipy."""
        from scipy import sparse

        a, b, touch, length = self._adjacency_pairs(queen)
        n = self.features_info["features"]
        data = length if weights else np.ones(len(a))
        m = sparse.coo_matrix((np.concatenate([data, data]),
                               (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(n, n))
        return m.tocsr()

    def adjacency_pairs(self, queen=True):
        """The touching pairs as a dict of numpy arrays "a" < "b" (feature
        indices, ascending by (a, b)), "touch" ("edge" / "vertex") and
        "length" (user units)."""
        a, b, touch, length = self._adjacency_pairs(queen)
        return {"a": a, "b": b, "touch": np.where(touch == _TOUCH_EDGE, "edge", "vertex"),
                "length": length}

    def _adjacency_pairs(self, queen):
        if self.features_info is None:
            raise ValueError("the file has no features (FEAT section)")
        flags = _TOUCH_EDGE | (_TOUCH_VERTEX if queen else 0)
        with self._shapes()._lock:
            a, b, touch, length = self._shapes()._c._adjacency(flags)
        return (_u64(a).astype(np.int64), _u64(b).astype(np.int64),
                np.frombuffer(touch, dtype=np.uint8), _f64(length) * self._user_scale())

    def weights(self, queen=True):
        """The contiguity as a libpysal.weights.W over feature indices (needs
        libpysal): queen (shared vertex or edge) or rook (shared edge)."""
        from libpysal.weights import W

        a, b, _, _ = self._adjacency_pairs(queen)
        n = self.features_info["features"]
        neighbours = {k: [] for k in range(n)}
        for i, j in zip(a.tolist(), b.tolist()):
            neighbours[i].append(j)
            neighbours[j].append(i)
        return W(neighbours, silence_warnings=True)

    # ---- nearest -------------------------------------------------------------------------

    def nearest(self, x, y, lonlat=False, feature=None):
        """The nearest edge of the map (or of a feature's border, `feature`
        an index or a key) to each point (scalars or arrays): a dict of
        numpy arrays "edge", "segment" (the edge's segment holding the
        closest point), "x", "y" (the closest point, user coordinates) and
        "distance" (user units). Exact integer predicates decide; the
        search expands over the leaves nearest the point."""
        lx, ly = self._points(x, y, lonlat)
        k = -1 if feature is None else self._feature_index(feature)
        xy = np.ascontiguousarray(np.stack([lx, ly], axis=1).reshape(-1))
        with self._shapes()._lock:
            edge, seg, px, py, dist = self._shapes()._c._nearest(xy, k)
        s = self._user_scale()
        return {"edge": _u64(edge).astype(np.int64), "segment": _u64(seg).astype(np.int64),
                "x": _f64(px) * s, "y": _f64(py) * s, "distance": _f64(dist) * s}

    def edges_within(self, x, y, d, lonlat=False):
        """The edges within distance d (user units) of one point: a dict of
        numpy arrays "edge" (ascending) and "distance" (user units)."""
        lx, ly = self._points(x, y, lonlat)
        if lx.size != 1:
            raise ValueError("edges_within: one point expected")
        d = _finite(d, "d")
        if d < 0:
            raise ValueError("edges_within: d >= 0 expected")
        dl = int(np.floor(d / self._user_scale()))
        if dl > 2**42:
            raise ValueError("edges_within: d beyond the lattice's range")
        with self._shapes()._lock:
            edges, dist = self._shapes()._c._within(int(lx[0]), int(ly[0]), dl)
        return {"edge": _u64(edges).astype(np.int64), "distance": _f64(dist) * self._user_scale()}

    # ---- dissolve and mesh ---------------------------------------------------------------

    def _polygons_to_shapely(self, raw, coords):
        from shapely.geometry import MultiPolygon, Polygon

        polygon_ring, ring_point, xy = _i64(raw[0]), _i64(raw[1]), _i64(raw[2])
        pts = self._coords_of(xy, coords)
        polys = []
        for p in range(len(polygon_ring) - 1):
            rings = [pts[ring_point[r]:ring_point[r + 1]]
                     for r in range(polygon_ring[p], polygon_ring[p + 1])]
            polys.append(Polygon(rings[0], rings[1:]))
        return MultiPolygon(polys)

    def _coords_of(self, xy, coords):
        mode = self._shapes()._mode(coords)
        if mode == "lattice":
            return xy.reshape(-1, 2).astype(np.float64)
        out = np.empty(xy.size)
        self._shapes()._to_user(xy, out, mode == "lonlat")
        return out.reshape(-1, 2)

    def union(self, features, coords="user"):
        """The union of features (indices or keys) as one exact shapely
        MultiPolygon: the edges with both sides in the set dropped."""
        ids = [self._feature_index(f) for f in (features if not isinstance(features, str)
                                                 else [features])]
        with self._shapes()._lock:
            raw = self._shapes()._c._union(_ids(ids, "features"))
        return self._polygons_to_shapely(raw, coords)

    def _groups(self, by):
        """Each feature's group (uint32, none for a null value) and the
        groups' values, from a column name or a sequence of values."""
        n = self.features_info["features"]
        if isinstance(by, str):
            names = [c for c, _ in self.attribute_columns]
            if by not in names:
                raise KeyError(f"no attribute {by!r} (the file has: {', '.join(names)})")
            values = [row[by] for row in self.attributes()]
        else:
            values = list(by)
            if len(values) != n:
                raise ValueError(f"by: {n} values expected (one a feature), got {len(values)}")
        keys = sorted({v for v in values if v is not None and v == v}, key=lambda v: (str(type(v)), v))
        index = {v: k for k, v in enumerate(keys)}
        group = np.array([index.get(v, _GROUP_NONE) if v is not None and v == v else _GROUP_NONE
                          for v in values], dtype=np.uint32)
        return group, keys

    def dissolve(self, by, coords="source"):
        """The features merged by `by` (an attribute name, or one value a
        feature): a geopandas GeoDataFrame indexed by the value, with the
        exact union of each group's features (shared borders dropped, no
        geometry test) and its feature count, in the CRS of `coords`. Null
        values form no group (as GeoDataFrame.dissolve's dropna)."""
        import geopandas

        if self.features_info is None:
            raise ValueError("the file has no features (FEAT section)")
        group, keys = self._groups(by)
        order = np.argsort(group, kind="stable")
        bounds = np.searchsorted(group[order], np.arange(len(keys) + 1))
        geoms, counts = [], []
        with self._shapes()._lock:
            raws = [self._shapes()._c._union(np.ascontiguousarray(
                order[bounds[k]:bounds[k + 1]], dtype=np.uint64)) for k in range(len(keys))]
        for k, raw in enumerate(raws):
            geoms.append(self._polygons_to_shapely(raw, coords))
            counts.append(int(bounds[k + 1] - bounds[k]))
        name = by if isinstance(by, str) else "group"
        import pandas as pd

        index = pd.Index(keys, name=name)
        return geopandas.GeoDataFrame({"features": counts}, geometry=geoms, index=index,
                                      crs=self.crs_for(coords))

    def mesh(self, kind="interior", coords="user"):
        """The borders as a shapely MultiLineString, joined end to end through
        vertices where two meet: kind "interior" (between features),
        "exterior" (the coverage's outline), "all", or an attribute name /
        one value a feature (between different values)."""
        from shapely.geometry import LineString, MultiLineString

        if self.features_info is None:
            raise ValueError("the file has no features (FEAT section)")
        sides = {"interior": _MESH_INTERIOR, "exterior": _MESH_EXTERIOR,
                 "all": _MESH_INTERIOR | _MESH_EXTERIOR}
        group = None
        if isinstance(kind, str) and kind in sides:
            flag = sides[kind]
        else:
            group, _ = self._groups(kind)
            flag = _MESH_INTERIOR
        with self._shapes()._lock:
            raw = self._shapes()._c._mesh(group, flag)
        ring_point, xy = _i64(raw[1]), _i64(raw[2])
        pts = self._coords_of(xy, coords)
        return MultiLineString([LineString(pts[ring_point[r]:ring_point[r + 1]])
                                for r in range(len(ring_point) - 1)])
