"""Geometry back from the file: numpy rings, shapely objects, GeoDataFrames.

Every coordinate comes from the library (hpfc_shapes_*, hpfc_geometry_*,
hpfc_user_point, the inverse of the projection the CRS records): this
module only copies the library's exact rings into numpy arrays and builds
shapely objects from them. Nothing here computes geometry.

Coordinates (`coords=`):
  "user"    lattice x 10^unit_exp10, correctly rounded (the default of the
            *_geometry and *_arrays calls): the plane the file's lattice
            lives in (metres of hpfc-pack's projection for a lon/lat source);
  "lattice" the exact integers (int64 arrays; floats in shapely objects,
            exact below 2^53);
  "lonlat"  degrees, through the inverse of the projection the CRS section
            records (GeographicLib, as hpfc-inspect --export);
  "source"  what hpfc-inspect --export writes (the default of the tables):
            "lonlat" when hpfc-pack projected a geographic source, else
            "user" (the source's own coordinates).
"""

from . import _hpfc

COORDS = ("user", "lattice", "lonlat", "source")


class _LazyNumpy:
    def __getattr__(self, name):
        import numpy

        globals()["np"] = numpy
        return getattr(numpy, name)


np = _LazyNumpy()

_FACE, _FEATURE, _FEATURE_LINES, _EDGE, _DART = range(5)


def _ids(value, name):
    """A uint64 array of ids from an int, a sequence or an array of integers."""
    arr = np.asarray(value)
    if arr.dtype.kind not in "iu" and not (arr.size == 0 and arr.dtype.kind == "f"):
        raise TypeError(f"{name}: integer ids expected, got dtype {arr.dtype}")
    arr = arr.reshape(-1)
    if arr.size and arr.dtype.kind == "i" and arr.min() < 0:
        raise IndexError(f"{name}: negative id {int(arr.min())}")
    return np.ascontiguousarray(arr, dtype=np.uint64)


def _one_id(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}: an integer expected, got {type(value).__name__}")
    if value < 0 or value >= 2**64:
        raise IndexError(f"{name} {value} out of range")
    return int(value)


def _int64(raw):
    return np.frombuffer(raw, dtype=np.int64)


class RingArrays:
    """Geometry as numpy arrays, in the ragged layout of GeoArrow.

    ids: the items asked for (uint64). xy: (n, 2) int64 absolute lattice
    points, exact. ring_offsets: ring (or line) r is
    xy[ring_offsets[r]:ring_offsets[r + 1]]; a ring is closed (its last
    point repeats its first). kind "polygons": polygon_offsets (polygon p
    is rings [polygon_offsets[p], polygon_offsets[p + 1]): its outer ring,
    counter-clockwise, then its holes, clockwise), hole_only (bool per
    polygon: a hole that no outer ring of its item contains, alone: the
    unbounded face's holes), part_offsets (item i is polygons
    [part_offsets[i], part_offsets[i + 1])). kind "lines": polygon_offsets
    and hole_only are None, part_offsets index lines.
    """

    def __init__(self, index, kind, ids, part, polygon, ring, xy, hole_only):
        self._index = index
        self.kind = kind
        self.ids = ids
        self.part_offsets = _int64(part)
        self.polygon_offsets = None if polygon is None else _int64(polygon)
        self.ring_offsets = _int64(ring)
        self.xy = _int64(xy).reshape(-1, 2)
        self.hole_only = None if hole_only is None else _int64(hole_only).astype(bool)

    def __len__(self):
        return len(self.part_offsets) - 1

    def __repr__(self):
        rings = len(self.ring_offsets) - 1
        return (f"<hpfc.RingArrays {self.kind}: {len(self)} items, {rings} "
                f"{'rings' if self.kind == 'polygons' else 'lines'}, {len(self.xy)} points>")

    def coords(self, coords="user"):
        """The points: int64 lattice for "lattice", else float64 (n, 2) user
        coordinates or (lon, lat) degrees (see the module's doc for "source")."""
        mode = self._index._mode(coords)
        if mode == "lattice":
            return self.xy
        out = np.empty(self.xy.shape, dtype=np.float64)
        self._index._to_user(self.xy, out, mode == "lonlat")
        return out

    def to_shapely(self, coords="user"):
        """One shapely geometry (or None) per item; see File.face_geometry,
        feature_geometry and edge_geometry for what each kind gives."""
        pts = self.coords(coords)
        import shapely.geometry as sg

        ro = self.ring_offsets
        out = []
        for i in range(len(self)):
            a, b = int(self.part_offsets[i]), int(self.part_offsets[i + 1])
            if self.kind == "lines":
                lines = [sg.LineString(pts[ro[r]:ro[r + 1]]) for r in range(a, b)]
                out.append(None if not lines else lines[0] if len(lines) == 1
                           else sg.MultiLineString(lines))
                continue
            po = self.polygon_offsets
            outer = [p for p in range(a, b) if not self.hole_only[p]]
            if outer:
                polys = [sg.Polygon(pts[ro[po[p]]:ro[po[p] + 1]],
                                    [pts[ro[r]:ro[r + 1]] for r in range(po[p] + 1, po[p + 1])])
                         for p in outer]
                out.append(polys[0] if len(polys) == 1 else sg.MultiPolygon(polys))
            elif b > a:
                # only holes (the unbounded face): the regions they enclose
                out.append(sg.MultiPolygon([sg.Polygon(pts[ro[po[p]]:ro[po[p] + 1]])
                                            for p in range(a, b)]))
            else:
                out.append(None)
        return out


def _split_crs(text):
    """hpfc-pack's CRS section: "DESCRIPTION; source LABEL", LABEL
    "AUTH:CODE (name)" or a name. (description, AUTH:CODE or None)."""
    if not text:
        return None, None
    desc, _, rest = text.partition(";")
    desc = desc.strip() or None
    code = None
    if rest.startswith(" source "):
        label = rest[len(" source "):].split(" ", 1)[0]
        if ":" in label:
            code = label
    return desc, code


def _made_by_pack(desc):
    """A projection hpfc-pack's common/projection.cc describes (tmerc, lcc,
    aea, eqc, no false origin, metres), as hpfc-inspect --export decides it."""
    return bool(desc) and desc.startswith(("+proj=tmerc ", "+proj=lcc ", "+proj=aea ",
                                           "+proj=eqc ")) \
        and " +x_0=0 +y_0=0 " in desc and desc.endswith("+units=m +no_defs")


def _is_geographic(code):
    """Whether CRS `code` is geographic, by pyproj or GDAL's osr; None when
    neither is there."""
    try:
        import pyproj

        return pyproj.CRS.from_user_input(code).is_geographic
    except ImportError:
        pass
    except Exception:  # noqa: BLE001 - an unknown code: not decidable
        return None
    try:
        from osgeo import osr

        s = osr.SpatialReference()
        if s.SetFromUserInput(code) != 0:
            return None
        return bool(s.IsGeographic())
    except ImportError:
        return None


class GeometryMixin:
    """The geometry methods of hpfc.File (needs the GEOM and LABL sections,
    format 1.2; FEAT for features, EDGF for line features)."""

    # ---- the index and coordinates -------------------------------------------------

    @property
    def geometry_info(self):
        """The GEOM section's counts (vertices, edges, points, section_bytes),
        None without one."""
        return _hpfc.geometry_info(self)

    def bounds(self, coords="user"):
        """The exact box (xmin, ymin, xmax, ymax) of every vertex and shape
        point, None without a GEOM section. Read from GEOM's block
        directories (hpfc_geometry_bounds), a few blocks, not the points.
        coords "lattice" (integers) or "user"; "source" when that is the
        user plane. Longitude and latitude are not monotone in the
        projected plane in general (a ring across the antimeridian): take
        the box of the geometries there."""
        box = _hpfc.geometry_bounds(self)
        if box is None:
            return None
        mode = self._shapes()._mode(coords)
        if mode == "lattice":
            return box
        if mode != "user":
            raise ValueError("bounds: coords 'lattice' or 'user' (the box of longitudes and "
                             "latitudes needs the points: the geometries' total bounds)")
        out = np.empty(4)
        self._shapes()._to_user(np.array(box, dtype=np.int64), out, False)
        return tuple(float(v) for v in out)

    def _shapes(self):
        index = self.__dict__.get("_shapes_index")
        if index is None:
            index = _ShapesIndex(self)
            self.__dict__["_shapes_index"] = index
        return index

    # ---- resource limits -----------------------------------------------------------

    @property
    def limits(self):
        """The caps on one geometry or topology call (hpfc_limits), a dict:
        "max_points", the shape points one feature's or face's geometry may
        gather, and "max_items", the faces + edges + features one window()
        may list; hpfc.LIMIT_NONE where lifted."""
        return dict(self.__dict__.get("_limits") or _default_limits())

    def set_limits(self, max_points=None, max_items=None):
        """Sets both caps of every later geometry and topology call on this
        file (each None: the library's default, hpfc.LIMIT_POINTS_DEFAULT
        or hpfc.LIMIT_ITEMS_DEFAULT; hpfc.LIMIT_NONE: none). A call that
        would pass a cap raises hpfc.Error HPFC_E_OVER_LIMIT before it
        allocates its answer, and the file stays usable. The defaults keep
        one call under about 300 MB, against a file (valid or hostile)
        whose one feature holds 10^8 points."""
        limits = {"max_points": _limit(max_points, "max_points", _hpfc.LIMIT_POINTS_DEFAULT),
                  "max_items": _limit(max_items, "max_items", _hpfc.LIMIT_ITEMS_DEFAULT)}
        # stored first: an index made meanwhile by another thread reads them
        self.__dict__["_limits"] = limits
        index = self.__dict__.get("_shapes_index")
        if index is not None:
            index.set_limits(limits)

    def source_is_lonlat(self):
        """Whether hpfc-pack projected a geographic (lon, lat) source: then
        coords="source" gives lon/lat, as hpfc-inspect --export writes."""
        known = self.__dict__.get("_source_lonlat")
        if known is None:
            desc, code = _split_crs(self.crs)
            if not _made_by_pack(desc):
                known = False
            elif code is None:
                known = True
            else:
                geographic = _is_geographic(code)
                # Without pyproj or GDAL: hpfc-pack projects geographic sources
                # only; a projected source keeps its own description, which is
                # not one of hpfc-pack's (false origin, other projections) in
                # practice.
                known = True if geographic is None else geographic
            self.__dict__["_source_lonlat"] = known
        return known

    def crs_for(self, coords="source"):
        """The CRS of coordinates `coords` as a string pyproj and geopandas
        read ("EPSG:4326", a PROJ string), None when unknown or "lattice"."""
        mode = self._shapes()._mode(coords)
        desc, code = _split_crs(self.crs)
        if mode == "lattice" or (desc is None and code is None):
            return None
        if mode == "lonlat":
            if code and self.source_is_lonlat():
                return code
            if desc:
                return _geodetic_of(desc)
            return None
        # user coordinates: the file's plane
        if self.source_is_lonlat():
            return desc
        return code or desc

    # ---- numpy ---------------------------------------------------------------------

    def face_arrays(self, faces=None):
        """The rings of faces (all faces, 0 the unbounded one included, when
        None) as RingArrays."""
        if faces is None:
            faces = np.arange(self._shapes().face_count, dtype=np.uint64)
        return self._shapes().collect(_FACE, _ids(faces, "faces"))

    def feature_arrays(self, features=None, lines=False):
        """Features' geometry as RingArrays: the union of their faces
        (polygons), or with lines=True the lines along their edges (EDGF)."""
        if features is None:
            info = self.features_info
            features = np.arange(info["features"] if info else 0, dtype=np.uint64)
        kind = _FEATURE_LINES if lines else _FEATURE
        return self._shapes().collect(kind, _ids(features, "features"))

    def edge_arrays(self, edges=None):
        """Edges' exact polylines from u to v (ids of the input graph; all
        when None) as RingArrays of kind "lines"."""
        if edges is None:
            edges = np.arange(self.geometry_info["edges"], dtype=np.uint64)
        return self._shapes().collect(_EDGE, _ids(edges, "edges"))

    def dart_arrays(self, darts):
        """Darts' exact polylines, origin to target (dart keys)."""
        return self._shapes().collect(_DART, _ids(darts, "darts"))

    def vertex_xy(self, vertex, coords="lattice"):
        """Vertex `vertex` (input graph id) as (x, y)."""
        x, y = self._shapes().vertex(_one_id(vertex, "vertex"))
        if self._shapes()._mode(coords) == "lattice":
            return (x, y)
        out = np.empty(2)
        self._shapes()._to_user(np.array([x, y], dtype=np.int64), out,
                                self._shapes()._mode(coords) == "lonlat")
        return (float(out[0]), float(out[1]))

    def edge_info(self, edge):
        """Edge `edge`: dict u, v (vertex ids), points (its ends included),
        left and right (the faces on either side of u -> v)."""
        u, v, n, left, right = self._shapes().edge(_one_id(edge, "edge"))
        return {"u": u, "v": v, "points": n, "left": left, "right": right}

    def dart_edge(self, dart):
        """(edge id, reversed) of a dart key: reversed when it runs v -> u."""
        return self._shapes().dart_edge(_one_id(dart, "dart"))

    def feature_face_count(self, feature):
        """Faces linked to a feature (0: a line feature or an empty one)."""
        return self._shapes().feature_face_count(_one_id(feature, "feature"))

    # ---- shapely -------------------------------------------------------------------

    def edge_geometry(self, edge, coords="user"):
        """Edge `edge` (input graph id) as a shapely LineString, u to v."""
        return self.edge_arrays([_one_id(edge, "edge")]).to_shapely(coords)[0]

    def dart_geometry(self, dart, coords="user"):
        """Dart key `dart` as a shapely LineString, origin to target."""
        return self.dart_arrays([_one_id(dart, "dart")]).to_shapely(coords)[0]

    def face_geometry(self, face, coords="user"):
        """Face `face` as a shapely Polygon (outer ring counter-clockwise,
        holes clockwise). The unbounded face 0 has no outer ring: it gives
        a MultiPolygon of the regions its holes enclose, i.e. the bounded
        part of the map, the complement of face 0 (None for a map without
        any bounded face)."""
        return self.face_arrays([_one_id(face, "face")]).to_shapely(coords)[0]

    def feature_geometry(self, feature, coords="user"):
        """Feature `feature` (index into the features): the union of its
        faces as a Polygon or MultiPolygon; a feature without faces its
        lines (EDGF) as a LineString or MultiLineString; None when it has
        neither."""
        k = _one_id(feature, "feature")
        lines = self.feature_face_count(k) == 0
        if lines and not self._has_edge_features():
            return None
        return self.feature_arrays([k], lines=lines).to_shapely(coords)[0]

    def features_geometry(self, coords="user"):
        """Every feature's geometry (as feature_geometry), in one pass per
        kind: a list indexed by feature."""
        info = self.features_info
        n = info["features"] if info else 0
        if n == 0:
            return []
        counts = np.array([self.feature_face_count(k) for k in range(n)], dtype=np.uint64)
        out = [None] * n
        polys = np.nonzero(counts > 0)[0]
        if polys.size:
            for k, g in zip(polys, self.feature_arrays(polys).to_shapely(coords)):
                out[int(k)] = g
        lines = np.nonzero(counts == 0)[0]
        if lines.size and self._has_edge_features():
            for k, g in zip(lines, self.feature_arrays(lines, lines=True).to_shapely(coords)):
                out[int(k)] = g
        return out

    def _has_edge_features(self):
        return any(s["tag"] == "EDGF" for s in self.sections)

    # ---- tables --------------------------------------------------------------------

    @property
    def attribute_columns(self):
        """The ATTR section's columns as (name, type) pairs, type "integer",
        "real" or "string"; [] without one."""
        return _hpfc.attribute_columns(self)

    def attributes(self):
        """Every feature's stored attributes, a dict a feature (None for a
        null value); [] without an ATTR section."""
        names = [name for name, _ in self.attribute_columns]
        return [dict(zip(names, row)) for row in _hpfc.attribute_rows(self)]

    def feature_records(self, coords="source", geometry=True):
        """Every feature as a dict: feature (its index), fid, layer, the key
        (under the key field's name), the stored attributes and, with
        geometry, "geometry": a shapely object (see feature_geometry) when
        shapely is there, else the feature's RingArrays."""
        info = self.features_info
        if info is None:
            return []
        names = {name for name, _ in self.attribute_columns}
        key_name = info["key_field"] if info["key_field"] and \
            info["key_field"] not in names else None
        fid_name = "fid" if "fid" not in names else "hpfc_fid"
        attrs = self.attributes()
        records = []
        for k, feat in enumerate(self.features()):
            row = {"feature": k, fid_name: feat["fid"], "layer": feat["layer"]}
            if key_name:
                row[key_name] = feat["key"]
            if attrs:
                row.update(attrs[k])
            records.append(row)
        if geometry:
            for row, g in zip(records, self._geometries(coords, features=True)):
                row["geometry"] = g
        return records

    def face_records(self, coords="source", geometry=True, unbounded=False):
        """Every bounded face (and face 0 with unbounded=True) as a dict:
        face, features (indices), fids, keys and "geometry" (see
        face_geometry)."""
        n = self._shapes().face_count
        first = 0 if unbounded else 1
        feats = self.features() if self.has_features else None
        records = []
        for face in range(first, n):
            row = {"face": face}
            if feats is not None:
                links = self.face_features(face)
                row["features"] = links
                row["fids"] = [feats[k]["fid"] for k in links]
                row["keys"] = [feats[k]["key"] for k in links]
            records.append(row)
        if geometry:
            for row, g in zip(records, self._geometries(coords, features=False,
                                                       first_face=first)):
                row["geometry"] = g
        return records

    def _geometries(self, coords, features, first_face=1):
        try:
            import shapely  # noqa: F401
        except ImportError:
            if features:
                info = self.features_info
                return [self.feature_arrays([k], lines=self.feature_face_count(k) == 0)
                        for k in range(info["features"])]
            return [self.face_arrays([k]) for k in range(first_face, self._shapes().face_count)]
        if features:
            return self.features_geometry(coords)
        faces = np.arange(first_face, self._shapes().face_count, dtype=np.uint64)
        return self.face_arrays(faces).to_shapely(coords)

    def features_geodataframe(self, coords="source"):
        """The features as a geopandas GeoDataFrame (feature_records' columns,
        indexed by feature) in the CRS of `coords` (crs_for). Without
        geopandas: a pandas DataFrame with the same columns and the CRS in
        frame.attrs["crs"]; without pandas: ImportError (feature_records
        gives plain dicts)."""
        return self._frame(self.feature_records(coords), "feature", coords)

    def faces_geodataframe(self, coords="source", unbounded=False):
        """The bounded faces (face 0 too with unbounded=True) as a
        GeoDataFrame indexed by face: features, fids, keys, geometry. The
        same fallbacks as features_geodataframe."""
        return self._frame(self.face_records(coords, unbounded=unbounded), "face", coords)

    def _frame(self, records, index, coords):
        import pandas as pd

        crs = self.crs_for(coords)
        frame = pd.DataFrame.from_records(records)
        if len(frame.columns) == 0:
            frame = pd.DataFrame({index: [], "geometry": []})
        frame = frame.set_index(index)
        try:
            import geopandas
        except ImportError:
            frame.attrs["crs"] = crs
            return frame
        return geopandas.GeoDataFrame(frame, geometry="geometry", crs=crs)


def _geodetic_of(desc):
    """The geographic CRS of a projection's ellipsoid (what hpfc-inspect
    --export writes for a source without an authority code)."""
    try:
        import pyproj

        return pyproj.CRS.from_proj4(desc).geodetic_crs.to_wkt()
    except ImportError:
        return "EPSG:4326" if "+ellps=WGS84" in desc or "+datum=WGS84" in desc else None
    except Exception:  # noqa: BLE001 - a description pyproj does not read
        return None


def _default_limits():
    return {"max_points": _hpfc.LIMIT_POINTS_DEFAULT, "max_items": _hpfc.LIMIT_ITEMS_DEFAULT}


def _limit(value, name, default):
    """A cap from set_limits: None the default, else an int from 1 to
    hpfc.LIMIT_NONE (0, which the C call reads as the default, is refused:
    it reads as "nothing allowed")."""
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}: an integer, None or hpfc.LIMIT_NONE expected, "
                        f"got {type(value).__name__}")
    if value < 1 or value > _hpfc.LIMIT_NONE:
        raise ValueError(f"{name}: from 1 to hpfc.LIMIT_NONE expected, got {value}")
    return int(value)


class _ShapesIndex:
    """The library's hpfc_shapes over a file (built once, O(edges + faces +
    links)), and the conversions of lattice points."""

    def __init__(self, file):
        import threading

        self._file = file
        self._c = _hpfc._Shapes(file)
        # the library's index answers one call at a time: threads take turns
        self._lock = threading.Lock()
        limits = file.__dict__.get("_limits")
        if limits is not None:
            self.set_limits(limits)

    def set_limits(self, limits):
        with self._lock:
            self._c._set_limits(limits["max_points"], limits["max_items"])

    @property
    def face_count(self):
        with self._lock:
            return self._c._face_count()

    def _mode(self, coords):
        if coords not in COORDS:
            raise ValueError(f"coords: one of {', '.join(COORDS)} expected, got {coords!r}")
        if coords == "source":
            return "lonlat" if self._file.source_is_lonlat() else "user"
        return coords

    def _to_user(self, xy, out, lonlat):
        xy = np.ascontiguousarray(xy, dtype=np.int64).reshape(-1)
        with self._lock:
            self._c._to_user(xy, out.reshape(-1), lonlat)

    def collect(self, kind, ids):
        with self._lock:
            part, polygon, ring, xy, hole_only = self._c._collect(kind, ids)
        return RingArrays(self, "polygons" if polygon is not None else "lines", ids, part,
                          polygon, ring, xy, hole_only)

    def vertex(self, v):
        with self._lock:
            return self._c._vertex(v)

    def edge(self, e):
        with self._lock:
            return self._c._edge(e)

    def dart_edge(self, d):
        with self._lock:
            return self._c._dart_edge(d)

    def feature_face_count(self, k):
        with self._lock:
            return self._c._feature_face_count(k)
