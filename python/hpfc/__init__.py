"""hpfc: read .hpfc files (hierarchical planar face complexes) from Python.

A thin layer over libhpfcfile: the file is memory-mapped, every query is the
library's. See python/README.md and the README's "Python" section.

    import hpfc
    with hpfc.open("counties.hpfc") as f:
        hits = f.locate_lonlat(lon, lat)      # numpy arrays in, arrays out
        hits.feature, hits.key, hits.face

Errors from the library raise hpfc.Error (code, name, message).
"""

from ._errors import Error
from . import _hpfc
from ._hpfc import Pixel
from ._file import (EAST, NORTH, SOUTH, WEST, File, Location, Locations, open)
from ._geometry import RingArrays
from ._pack import pack

library_version = _hpfc.library_version
strerror = _hpfc.strerror
LIMIT_NONE = _hpfc.LIMIT_NONE
LIMIT_POINTS_DEFAULT = _hpfc.LIMIT_POINTS_DEFAULT
LIMIT_ITEMS_DEFAULT = _hpfc.LIMIT_ITEMS_DEFAULT

__all__ = ["Error", "File", "Location", "Locations", "Pixel", "RingArrays", "open", "strerror",
           "library_version", "WEST", "NORTH", "EAST", "SOUTH", "LIMIT_NONE",
           "LIMIT_POINTS_DEFAULT", "LIMIT_ITEMS_DEFAULT", "pack"]
