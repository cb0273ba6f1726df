"""hpfc.File: an open .hpfc file, its queries and its traversal.

The C half (_hpfc._File) holds the mapping and calls libhpfcfile; this half
shapes its answers into Python values: dicts, lists, numpy arrays, pandas
frames.

A file with exact geometry (GEOM and LABL sections, format 1.2) answers
every point exactly (hpfc_locate_point): its one face, or the faces around
it when it lies on an edge or a vertex (on_boundary). Other files give the
candidate faces of the point's leaf (exact False).
"""

from . import _hpfc
from ._errors import Error
from ._geometry import GeometryMixin
from ._topology import TopologyMixin

WEST, NORTH, EAST, SOUTH = 0, 1, 2, 3


class _LazyNumpy:
    """numpy, imported on first use: `import hpfc; hpfc.open(path)` then
    costs the library's open, not numpy's import (about 0.1 s)."""

    def __getattr__(self, name):
        import numpy

        globals()["np"] = numpy
        return getattr(numpy, name)


np = _LazyNumpy()


def _as_scalar(value, name):
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name}: a number expected, got {type(value).__name__}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: a number expected, got {type(value).__name__}") from None


def _as_float_array(value, name):
    arr = np.asarray(value)
    if arr.dtype.kind not in "biuf":
        raise TypeError(f"{name}: an array of numbers expected, got dtype {arr.dtype}")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _as_lattice_array(value, name):
    arr = np.asarray(value)
    if arr.dtype.kind not in "biu":
        raise TypeError(f"{name}: an array of integers expected, got dtype {arr.dtype}")
    return np.ascontiguousarray(arr, dtype=np.int64)


class Location:
    """The answer for one point.

    inside: whether the point lies in the file's domain; x, y: its lattice
    point; pixel: the leaf holding it (None outside); private: the leaf has
    no crossing, so its one face is the point's; exact: the file's geometry
    decided the answer; faces: with exact, the point's face, or the faces
    around it when on_boundary (it lies on edge `edge` or on vertex
    `vertex`, input graph ids), else the faces meeting the leaf (the
    candidates for the point's face), ascending; face: the one face when
    there is one, else None; features: the features of those faces,
    ascending; feature: the point's feature when every face links exactly
    that one feature, else None; key: that feature's key value (None
    without one).
    """

    __slots__ = ("inside", "x", "y", "pixel", "private", "faces", "face", "features",
                 "feature", "key", "exact", "on_boundary", "vertex", "edge")

    def __init__(self, **kw):
        for name in self.__slots__:
            setattr(self, name, kw.get(name))

    def __repr__(self):
        return (f"Location(inside={self.inside}, face={self.face}, faces={self.faces}, "
                f"on_boundary={self.on_boundary}, feature={self.feature}, key={self.key!r}, "
                f"pixel={self.pixel})")


class Locations:
    """The answers for an array of points, as numpy arrays of its shape.

    face (int64): the point's face (with exact geometry; without it, when
    its leaf meets one face), else -1 (outside, on a boundary between faces
    too); face_count (uint32): exact: 1, or the faces around a boundary
    point; else faces meeting the leaf (0 outside); on_boundary, exact
    (bool): the point lies on an edge or a vertex, the file's geometry
    decided the answer;
    feature (int64): the point's feature when every candidate face links
    exactly that one, else -1; feature_count (uint32): distinct features of
    the candidates; inside, private, single (bool): in the domain, in a private
    leaf, one candidate face; depth (uint8): the leaf's level; x, y (int64):
    lattice points. key: the features' key values (an object array, None
    where feature is -1), made on first use.
    """

    def __init__(self, file, shape, x, y, face, face_count, feature, feature_count, flags,
                 depth):
        self._file = file
        self.x = x.reshape(shape)
        self.y = y.reshape(shape)
        self.face = face.reshape(shape)
        self.face_count = face_count.reshape(shape)
        self.feature = feature.reshape(shape)
        self.feature_count = feature_count.reshape(shape)
        self.flags = flags.reshape(shape)
        self.depth = depth.reshape(shape)
        self._key = None

    def __len__(self):
        return len(self.face)

    @property
    def inside(self):
        return (self.flags & _hpfc.LOC_INSIDE) != 0

    @property
    def private(self):
        return (self.flags & _hpfc.LOC_PRIVATE) != 0

    @property
    def single(self):
        return (self.flags & _hpfc.LOC_SINGLE) != 0

    @property
    def on_boundary(self):
        return (self.flags & _hpfc.LOC_BOUNDARY) != 0

    @property
    def exact(self):
        return (self.flags & _hpfc.LOC_EXACT) != 0

    @property
    def key(self):
        if self._key is None:
            keys = np.empty(0, dtype=object)
            if self._file.has_features:
                keys = np.array(self._file.feature_keys() + [None], dtype=object)
            else:
                keys = np.array([None], dtype=object)
            self._key = keys[self.feature]  # -1 picks the trailing None
        return self._key

    def to_frame(self):
        """A pandas DataFrame, one row a point (needs pandas)."""
        import pandas as pd

        cols = {
            "x": self.x.ravel(), "y": self.y.ravel(), "face": self.face.ravel(),
            "face_count": self.face_count.ravel(), "feature": self.feature.ravel(),
            "feature_count": self.feature_count.ravel(), "inside": self.inside.ravel(),
            "private": self.private.ravel(), "depth": self.depth.ravel(),
            "on_boundary": self.on_boundary.ravel(), "exact": self.exact.ravel(),
        }
        if self._file.has_features and self._file.features_info["key_field"] is not None:
            cols["key"] = self.key.ravel()
        return pd.DataFrame(cols)


class File(TopologyMixin, GeometryMixin, _hpfc._File):
    """An open .hpfc file, memory-mapped (hpfc.open(path)).

    Opening checks the header, level table and section directory only
    (O(levels)); faces are numbered on the first query that needs them.
    Use it as a context manager or call close(). Safe on untrusted files:
    a damaged file raises hpfc.Error, never crashes.
    """

    def __init__(self, path, *, skip_checksum=False):
        super().__init__(path, skip_checksum)
        self.path = path

    def __enter__(self):
        return self

    def close(self):
        """Unmaps the file (and drops the geometry index built on it)."""
        super().close()
        self.__dict__.pop("_shapes_index", None)

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        state = "closed" if self.closed else f"{self.info['levels']} levels"
        return f"<hpfc.File {self.path!r} {state}>"

    # ---- header, levels, sections, CRS ------------------------------------

    @property
    def info(self):
        """The header: format_version, grid sizes, domain (lattice), unit_exp10,
        file_size, section_count, crs."""
        return self._info()

    @property
    def crs(self):
        """The CRS section's text (a PROJ-style description), or None."""
        return self._info()["crs"]

    @property
    def unit_exp10(self):
        return self._info()["unit_exp10"]

    @property
    def levels(self):
        """The level table: one dict a level (word/refined pixels, images,
        word_bits, address_bits, pool_offset, pool_bits, cell_w, cell_h)."""
        return [self._level(l) for l in range(self._info()["levels"])]

    @property
    def sections(self):
        """The section directory: one dict a section (tag, flags, offset,
        length, crc32c)."""
        return [self._section(k) for k in range(self._info()["section_count"])]

    # ---- point location ----------------------------------------------------

    def locate(self, x, y):
        """The faces and features at user coordinates (x, y) (lattice x
        10^unit_exp10), as hpfc-inspect --locate: scalars give a Location,
        arrays a Locations (one call into C, without the GIL)."""
        if np.ndim(x) == 0 and np.ndim(y) == 0:
            u, v = _as_scalar(x, "x"), _as_scalar(y, "y")
            return self._locate_scalar_user(u, v, lonlat=False)
        return self._locate_array(_as_float_array(x, "x"), _as_float_array(y, "y"), lonlat=False)

    def locate_lonlat(self, lon, lat):
        """As locate() for (lon, lat) degrees, projected with the file's CRS
        as hpfc-inspect --locate-lonlat does. In arrays, a point out of range
        or that does not project is outside (inside False); a scalar one
        raises ValueError."""
        if np.ndim(lon) == 0 and np.ndim(lat) == 0:
            u, v = _as_scalar(lon, "lon"), _as_scalar(lat, "lat")
            if not (-180 <= u <= 180 and -90 <= v <= 90):
                raise ValueError(f"({u}, {v}) is not a longitude and latitude in degrees")
            return self._locate_scalar_user(u, v, lonlat=True)
        return self._locate_array(_as_float_array(lon, "lon"), _as_float_array(lat, "lat"),
                                  lonlat=True)

    def locate_lattice(self, x, y):
        """As locate() for lattice points (integers)."""
        if np.ndim(x) == 0 and np.ndim(y) == 0:
            if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool)
                       for v in (x, y)):
                raise TypeError("locate_lattice: integer lattice coordinates expected")
            return self._locate_scalar_lattice(int(x), int(y))
        xs, ys = np.broadcast_arrays(_as_lattice_array(x, "x"), _as_lattice_array(y, "y"))
        shape = xs.shape
        return self._run_batch(shape, np.ascontiguousarray(xs.ravel()),
                               np.ascontiguousarray(ys.ravel()), None)

    def leaf_at(self, x, y):
        """The leaf (word pixel) holding lattice point (x, y), None outside."""
        return self._leaf_at(int(x), int(y))

    def lattice_point(self, x, y, lonlat=False):
        """The lattice point of user coordinates (or lon/lat), None when it
        lies beyond any lattice or does not project."""
        u = np.array([_as_scalar(x, "x")])
        v = np.array([_as_scalar(y, "y")])
        lx, ly = np.empty(1, np.int64), np.empty(1, np.int64)
        ok = np.empty(1, np.uint8)
        self._lattice_points(u, v, lx, ly, ok, lonlat)
        return (int(lx[0]), int(ly[0])) if ok[0] else None

    def _locate_scalar_user(self, u, v, lonlat):
        point = self.lattice_point(u, v, lonlat)
        if point is None:
            return Location(inside=False, faces=[], features=[])
        return self._locate_scalar_lattice(*point)

    @property
    def has_geometry(self):
        """The file has exact geometry (GEOM and LABL): locations are exact."""
        return self._has_geometry()

    def _locate_scalar_lattice(self, x, y):
        exact = self._has_geometry()
        on_boundary, vertex, edge = False, None, None
        if exact:
            answer = self._locate_point(x, y)
            px = answer[4] if answer is not None else None
        else:
            px = self._leaf_at(x, y)
        if px is None:
            return Location(inside=False, x=x, y=y, faces=[], features=[], exact=exact,
                            on_boundary=False)
        if exact:
            faces, on_boundary, vertex, edge = answer[:4]
        else:
            faces = px.faces()
        features, per_face = [], []
        if self.has_features:
            per_face = [self.face_features(face) for face in faces]
            features = sorted({f for links in per_face for f in links})
        # the point's feature whichever candidate holds it: all link [f]
        sure = per_face and all(links == per_face[0] for links in per_face)
        feature = per_face[0][0] if sure and len(per_face[0]) == 1 else None
        key = self.feature(feature)["key"] if feature is not None else None
        return Location(inside=True, x=x, y=y, pixel=px, private=px.is_private, faces=faces,
                        face=faces[0] if len(faces) == 1 else None, features=features,
                        feature=feature, key=key, exact=exact, on_boundary=on_boundary,
                        vertex=vertex, edge=edge)

    def _locate_array(self, u, v, lonlat):
        u, v = np.broadcast_arrays(u, v)
        shape = u.shape
        u = np.ascontiguousarray(u.ravel())
        v = np.ascontiguousarray(v.ravel())
        n = u.size
        x, y = np.empty(n, np.int64), np.empty(n, np.int64)
        valid = np.empty(n, np.uint8)
        self._lattice_points(u, v, x, y, valid, lonlat)
        return self._run_batch(shape, x, y, valid)

    def _run_batch(self, shape, x, y, valid):
        n = x.size
        face, feature = np.empty(n, np.int64), np.empty(n, np.int64)
        face_count, feature_count = np.empty(n, np.uint32), np.empty(n, np.uint32)
        flags, depth = np.empty(n, np.uint8), np.empty(n, np.uint8)
        self._check_feature_faces()
        self._locate_into(x, y, valid, face, face_count, feature, feature_count, flags, depth)
        return Locations(self, shape, x, y, face, face_count, feature, feature_count, flags,
                         depth)

    def _check_feature_faces(self):
        info = self.features_info
        if info is not None and info["faces"] != self.face_count:
            raise Error(48, "HPFC_E_CORRUPT", _hpfc.strerror(48),
                        f"features: the FEAT section lists {info['faces']} faces, "
                        f"the map has {self.face_count}")

    # ---- features ------------------------------------------------------------

    @property
    def features_info(self):
        """The FEAT section's counts and key field, or None without one."""
        return self._features_info()

    @property
    def has_features(self):
        return self._features_info() is not None

    def feature(self, index):
        """Feature `index` as a dict: index, fid, layer (its name), key."""
        fid, layer, key = self._feature(index)
        return {"index": index, "fid": fid, "layer": self.layer_name(layer), "key": key}

    def features(self):
        """Every feature as a dict (see feature()); [] without a FEAT section."""
        info = self.features_info
        if info is None:
            return []
        names = [self.layer_name(k) for k in range(info["layers"])]
        out = []
        for index in range(info["features"]):
            fid, layer, key = self._feature(index)
            out.append({"index": index, "fid": fid, "layer": names[layer], "key": key})
        return out

    def feature_keys(self):
        """The key value of every feature (None for a null or no key field)."""
        info = self.features_info
        if info is None:
            return []
        return [self._feature(k)[2] for k in range(info["features"])]

    def features_frame(self):
        """The features as a pandas DataFrame indexed by feature index (needs
        pandas); the key column is named after the key field."""
        import pandas as pd

        rows = self.features()
        info = self.features_info
        frame = pd.DataFrame(rows, columns=["index", "fid", "layer", "key"]).set_index("index")
        if info is not None and info["key_field"]:
            frame = frame.rename(columns={"key": info["key_field"]})
        return frame

    # ---- traversal ------------------------------------------------------------

    def leaves(self):
        """The word pixels, depth-first (each image in scanline order)."""
        px = self._leaf_first()
        while px is not None:
            yield px
            px = self._leaf_next(px)

    def pixels(self):
        """Every pixel, refined and word, depth-first from the root image."""
        info = self._info()
        stack = [self.root(i, j) for j in reversed(range(info["root_rows"]))
                 for i in reversed(range(info["root_cols"]))]
        cols, rows = info["cols"], info["rows"]
        # A damaged file can point many refined pixels at one image: stop,
        # as the library's leaf iterator does, past the level table's count.
        limit = sum(l["word_pixels"] + l["refined_pixels"] for l in self.levels)
        seen = 0
        while stack:
            px = stack.pop()
            seen += 1
            if seen > limit:
                raise Error(48, "HPFC_E_CORRUPT", _hpfc.strerror(48),
                            "pixels: more pixels than the level table declares")
            yield px
            if px.kind == "refined":
                stack.extend(px.child(i, j) for j in reversed(range(rows))
                             for i in reversed(range(cols)))

    def vertices(self):
        """Every vertex key, leaf by leaf."""
        for px in self.leaves():
            if not px.is_private:
                yield from px.vertex_keys()

    def darts(self):
        """Every dart key: the darts leaving each vertex, clockwise."""
        for v in self.vertices():
            yield from self.vertex_darts(v)

    def face_boundary(self, dart):
        """The darts of dart's boundary loop, from dart, following next()."""
        limit = self.key_index_bound()[0] + 1
        d = dart
        for _ in range(limit):
            yield d
            d = self.next(d)
            if d == dart:
                return
        raise Error(48, "HPFC_E_CORRUPT", _hpfc.strerror(48), "face_boundary: no loop")

    def dart_pixel(self, dart):
        """The leaf holding a dart's origin."""
        return self._key_pixel(dart, False)

    def vertex_pixel(self, vertex):
        """The leaf holding a vertex."""
        return self._key_pixel(vertex, True)


def open(path, *, skip_checksum=False):  # noqa: A001 - the package's entry point
    """Maps the .hpfc file at `path` (O(levels)); raises hpfc.Error."""
    return File(path, skip_checksum=skip_checksum)
