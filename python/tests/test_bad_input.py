"""Bad input: missing and damaged files, wrong types. Always an exception
with the library's code, never a crash."""

import os
import shutil

import numpy as np
import pytest

import hpfc
from conftest import expected_invalid


def test_missing_file(tmp_path):
    with pytest.raises(hpfc.Error) as e:
        hpfc.open(tmp_path / "nope.hpfc")
    assert e.value.code == 3 and e.value.name == "HPFC_E_IO"
    assert "nope.hpfc" in str(e.value) and e.value.message == hpfc.strerror(3)


def test_directory_and_empty_file(tmp_path):
    with pytest.raises(hpfc.Error):
        hpfc.open(tmp_path)
    empty = tmp_path / "empty.hpfc"
    empty.write_bytes(b"")
    with pytest.raises(hpfc.Error):
        hpfc.open(empty)


def exercise(f):
    """Every query of the package on a file that opened: Errors are fine."""
    try:
        f.verify_checksums()
    except hpfc.Error:
        pass
    info = f.info
    for call in (lambda: f.levels, lambda: f.sections, lambda: f.face_count,
                 lambda: f.features(), lambda: list(f.leaves()), lambda: list(f.pixels()),
                 lambda: list(f.darts())):
        try:
            call()
        except hpfc.Error:
            pass
    rng = np.random.default_rng(0)
    xs = rng.integers(info["x0"], info["x0"] + max(info["width"], 1), 200)
    ys = rng.integers(info["y0"], info["y0"] + max(info["height"], 1), 200)
    try:
        f.locate_lattice(xs, ys)
    except hpfc.Error:
        pass
    for x, y in zip(xs[:20], ys[:20]):
        try:
            f.locate_lattice(int(x), int(y))
        except hpfc.Error:
            pass


@pytest.mark.parametrize("path,name", expected_invalid(), ids=lambda v: getattr(v, "name", v))
def test_damaged_fixtures(path, name):
    """The first failing status of open, then checksums, then a walk: as
    tests/data/invalid/EXPECTED says."""
    try:
        f = hpfc.open(path)
    except hpfc.Error as e:
        assert e.name == name
        return
    with f:
        try:
            f.verify_checksums()
        except hpfc.Error as e:
            assert e.name == name
            assert e.context.startswith(("section ", "the header's")), e.context
            return
        with pytest.raises(hpfc.Error) as e:
            list(f.pixels())
            f.face_count
        assert e.value.name == name
        exercise(f)


def test_corrupted_copies(tmp_path, delaunay, counties):
    """Truncations and byte flips of real files: opened with and without the
    header checksum, every query answers or raises hpfc.Error."""
    rng = np.random.default_rng(42)
    for src in (delaunay, counties):
        data = bytearray(open(src, "rb").read())
        for k in range(25):
            bad = bytearray(data)
            if k < 5:
                bad = bad[: int(rng.integers(0, len(bad)))]
            else:
                for _ in range(int(rng.integers(1, 8))):
                    bad[int(rng.integers(0, len(bad)))] ^= 1 << int(rng.integers(0, 8))
            path = tmp_path / f"bad{k}.hpfc"
            path.write_bytes(bytes(bad))
            for skip in (False, True):
                try:
                    f = hpfc.open(path, skip_checksum=skip)
                except hpfc.Error as e:
                    assert e.code > 0
                    continue
                with f:
                    exercise(f)


def test_wrong_types(delaunay):
    with pytest.raises(TypeError):
        hpfc.open(42)
    with pytest.raises(TypeError):
        hpfc.open(None)
    with pytest.raises(ValueError):
        hpfc.open("a\0b")
    with hpfc.open(delaunay) as f:
        with pytest.raises(TypeError):
            f.locate("1", 2)
        with pytest.raises(TypeError):
            f.locate(None, 2)
        with pytest.raises(TypeError):
            f.locate(np.array(["a", "b"]), np.array([1.0, 2.0]))
        with pytest.raises(TypeError):
            f.locate_lattice(1.5, 2)
        with pytest.raises(TypeError):
            f.locate_lattice(np.array([1.5]), np.array([2.0]))
        with pytest.raises(ValueError):
            f.locate(np.zeros(3), np.zeros(4))  # shapes that do not broadcast
        with pytest.raises(OverflowError):
            f.locate_lattice(2**70, 0)
        with pytest.raises(IndexError):
            f._level(99)
        with pytest.raises(TypeError):
            f.root("a", 0)
        # the raw batch call checks its buffers
        n = 4
        x = np.zeros(n, np.int64)
        outs = [np.empty(n, np.int64), np.empty(n, np.uint32), np.empty(n, np.int64),
                np.empty(n, np.uint32), np.empty(n, np.uint8), np.empty(n, np.uint8)]
        with pytest.raises(TypeError):
            f._locate_into(x.astype(np.float64), x, None, *outs)
        with pytest.raises(ValueError):
            f._locate_into(x, x[:3], None, *outs)
        with pytest.raises(TypeError):
            f._locate_into(x, x, None, outs[0], outs[0], *outs[2:])  # uint32 expected
        ro = np.empty(n, np.int64)
        ro.flags.writeable = False
        with pytest.raises((TypeError, BufferError, ValueError)):
            f._locate_into(x, x, None, ro, *outs[1:])
        with pytest.raises((TypeError, BufferError, ValueError)):
            f._locate_into(x[::2], x[::2], None, *[o[:2] for o in outs])  # not contiguous
        # the public calls take any strides and dtypes of numbers
        xs = np.linspace(-1e6, 1e6, 40)
        assert np.array_equal(f.locate(xs[::2], xs[1::2]).face,
                              f.locate(xs[::2].copy(), xs[1::2].copy()).face)
        assert np.array_equal(f.locate(xs.astype(np.float32), xs).face,
                              f.locate(xs.astype(np.float32).astype(np.float64), xs).face)
