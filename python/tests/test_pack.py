"""hpfc.pack and python3 -m hpfc pack: a map packed in parts on a Dask
LocalCluster of two worker processes gives hpfc-pack's very bytes (the
oracle): .pfc fixtures and a generated street network under several
partitions and options, GIS layers (noded ones too, with their features
and attributes) and Draco meshes through hpfc-pack --parts-dir; a worker
killed in the middle of the build is replaced by Dask and the file is
still the same; a failure leaves no output and no parts behind. The
--parts-dir protocol driven by hand: damaged, swapped and foreign part
files, a failed part and a closed standard input are refused with a
message and no output. Skipped where dask.distributed is missing
(Debian: python3-distributed, which tools/install-deps.sh installs)."""

import json
import math
import os
import random
import shutil
import signal
import subprocess
import sys
import threading
import time

import pytest

from conftest import TESTS_DATA

GIS = sorted((TESTS_DATA / "gis" / "ok").glob("*.geojson")) + sorted((TESTS_DATA / "gis").glob("*.geojson"))

distributed = pytest.importorskip("distributed")
import hpfc  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=":0")
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def streets(path, side, seed):
    """A small street network: junctions on a jittered grid, curved streets."""
    rng = random.Random(seed)
    at = {}
    lines = ["pfc 1"]
    for j in range(side):
        for i in range(side):
            at[i, j] = len(at)
            lines.append("v %d %d" % (i * 1000 + rng.randint(-200, 200), j * 1000 + rng.randint(-200, 200)))
    xy = [tuple(int(v) for v in line.split()[1:]) for line in lines[1:]]
    for j in range(side):
        for i in range(side):
            for k, l in ((i + 1, j), (i, j + 1)):
                if (k, l) not in at:
                    continue
                (ax, ay), (bx, by) = xy[at[i, j]], xy[at[k, l]]
                n, amp = rng.randint(3, 9), rng.uniform(-60, 60)
                length = math.hypot(bx - ax, by - ay)
                pts = []
                for s in range(1, n + 1):
                    t = s / (n + 1)
                    off = amp * math.sin(math.pi * t)
                    pts.append("%d %d" % (round(ax + (bx - ax) * t - (by - ay) / length * off),
                                          round(ay + (by - ay) * t + (bx - ax) / length * off)))
                lines.append("e %d %d %s" % (at[i, j], at[k, l], " ".join(pts)))
    path.write_text("\n".join(lines) + "\n")
    return path


def hpfc_pack(pack_tool, src, out, *options):
    r = subprocess.run([pack_tool, "-q", "--force", *options, str(src), "-o", str(out)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    return out.read_bytes()


OPTIONS = [
    ({}, []),
    ({"root": (5, 3), "refine": 3, "layout": "paper"}, ["--root", "5x3", "--refine", "3", "--layout", "paper"]),
    ({"leaf_points": 1, "root": 9}, ["--leaf-points", "1", "--root", "9"]),
    # without GEOM (the merge numbers LABL's faces a root pixel at a time
    # here as with the graph file; read_on_workers=False numbers them whole)
    ({"geometry": False, "root": 7, "layout": "paper"}, ["--no-geometry", "--root", "7", "--layout", "paper"]),
]


def inputs(tmp_path):
    return sorted((TESTS_DATA / "valid").glob("*.pfc")) + [streets(tmp_path / "streets.pfc", 24, 7)]


@pytest.mark.parametrize("kwargs,flags", OPTIONS)
def test_same_bytes_as_hpfc_pack(tmp_path, client, pack_tool, kwargs, flags):
    for src in inputs(tmp_path):
        want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc", *flags)
        for parts in (1, 3, 7):
            # the .pfc read by the workers in 1 to 9 chunks (and by the
            # client once), cut wherever the text's length falls
            out = tmp_path / ("got-%d.hpfc" % parts)
            hpfc.pack(src, out, client=client, partitions=parts, chunks=2 * parts - 1, **kwargs)
            assert out.read_bytes() == want, (src.name, kwargs, parts)
        hpfc.pack(src, out, client=client, partitions=2, read_on_workers=False, **kwargs)
        assert out.read_bytes() == want, (src.name, kwargs, "read here")
    assert not list(tmp_path.glob(".hpfc-parts.*")), "the parts' directory was left behind"


def test_command_line(tmp_path, pack_tool):
    src = streets(tmp_path / "s.pfc", 12, 3)
    want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc")
    env = dict(os.environ)
    r = subprocess.run([sys.executable, "-m", "hpfc", "pack", str(src), "-o", str(tmp_path / "got.hpfc"),
                        "--workers", "2", "--partitions", "5"], capture_output=True, text=True,
                       check=False, env=env)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "got.hpfc").read_bytes() == want
    r = subprocess.run([sys.executable, "-m", "hpfc", "pack", str(src), "-o", str(tmp_path / "here.hpfc"),
                        "--workers", "1", "--partitions", "3", "--read-here"], capture_output=True,
                       text=True, check=False, env=env)
    assert r.returncode == 0 and (tmp_path / "here.hpfc").read_bytes() == want, r.stderr
    bad = tmp_path / "bad.pfc"
    bad.write_text("pfc 1\nv 0 0\nv 1 1\ne 0 7\n")
    r = subprocess.run([sys.executable, "-m", "hpfc", "pack", str(bad), "-o", str(tmp_path / "no.hpfc"),
                        "--workers", "1"], capture_output=True, text=True, check=False, env=env)
    assert r.returncode == 1
    assert len(r.stderr.strip().splitlines()) == 1 and "HPFC_E_VERTEX_INDEX" in r.stderr, r.stderr
    assert not (tmp_path / "no.hpfc").exists()
    assert not list(tmp_path.glob(".hpfc-parts.*"))


def test_failures_leave_nothing(tmp_path, client):
    bad = tmp_path / "crossing.pfc"
    bad.write_text("pfc 1\nv 0 0\nv 10 10\nv 0 10\nv 10 0\ne 0 1\ne 2 3\n")
    with pytest.raises(hpfc.Error) as e:
        hpfc.pack(bad, tmp_path / "out.hpfc", client=client, partitions=4)
    assert e.value.name == "HPFC_E_NONPLANAR"
    with pytest.raises(ValueError):
        hpfc.pack(bad, tmp_path / "out.hpfc", client=client, refine=1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["crossing.pfc"]


FLAWED = {
    # an edge naming a vertex that a later chunk defines
    "forward.pfc": "pfc 1\n" + "".join("v %d %d\n" % (i, i * i) for i in range(40)) + "e 0 40\n"
                   + "v 100 0\n" + "".join("e %d %d\n" % (i, i + 1) for i in range(40)),
    "digits.pfc": "pfc 1\nv 0 0\nv 1 1e-31\ne 0 1\n",
    "noedge.pfc": "pfc 1\nv 0 0\nv 1 1\n",
    "isolated.pfc": "pfc 1\nv 0 0\nv 3 3\nv 7 7\ne 0 1\n",
    "duplicate.pfc": "pfc 1\nv 0 0\nv 3 3\nv 0 0\nv 9 0\ne 0 1\ne 2 3\n",
    "zero.pfc": "pfc 1\nv 0 0\nv 3 3\ne 0 1 0 0 1 1\n",
    "syntax.pfc": "pfc 1\n" + "".join("v %d 0\n" % i for i in range(30)) + "v 1,5 0\n",
}


@pytest.mark.parametrize("name", sorted(FLAWED))
def test_chunk_flaws_in_hpfc_packs_words(tmp_path, client, pack_tool, name):
    """A flaw the workers' chunks find, or one only the whole text shows,
    is the one hpfc-pack reports, with its line; nothing is left."""
    src = tmp_path / name
    src.write_text(FLAWED[name])
    r = subprocess.run([pack_tool, "-q", str(src), "-o", str(tmp_path / "want.hpfc")],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 1 and not (tmp_path / "want.hpfc").exists()
    for chunks in (1, 4):
        with pytest.raises(hpfc.Error) as e:
            hpfc.pack(src, tmp_path / "out.hpfc", client=client, partitions=3, chunks=chunks)
        assert r.stderr == "hpfc-pack: %s\n" % e.value.context, (r.stderr, e.value.context)
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_killed_worker(tmp_path, client, pack_tool):
    """A worker killed while the parts are being built: Dask's nanny starts
    another, the lost part is built again, and the file is the same."""
    src = streets(tmp_path / "big.pfc", 90, 11)
    want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc")
    shared = tmp_path / "shared"
    shared.mkdir()
    pids = client.run(os.getpid)
    errors = []

    def run():
        try:
            hpfc.pack(src, tmp_path / "got.hpfc", client=client, partitions=256, shared_dir=shared)
        except Exception as exc:  # noqa: BLE001 - reported below
            errors.append(exc)

    t = threading.Thread(target=run)
    t.start()
    killed = None
    deadline = time.monotonic() + 120
    while killed is None and t.is_alive() and time.monotonic() < deadline:
        if list(shared.glob("*/part-*.part")):  # parts under way: kill one worker
            killed = sorted(pids.values())[0]
            os.kill(killed, signal.SIGKILL)
        time.sleep(0.01)
    t.join(300)
    assert killed is not None, "the build ended before a worker could be killed"
    assert not errors, errors
    assert (tmp_path / "got.hpfc").read_bytes() == want
    assert killed not in client.run(os.getpid).values()


@pytest.mark.parametrize("kwargs,options,parts", [
    ({}, ["--fields", "all"], (2, 7)),
    ({"root": (5, 4), "layout": "paper", "ranges": 5}, ["--fields", "all", "--vertices", "all"], (5,)),
    ({"ranges": 1}, ["--fields", "all", "--invalid", "node"], (3,)),
    ({"read_on_workers": False}, [], (3,)),
])
def test_gis_same_bytes_as_hpfc_pack(tmp_path, client, pack_tool, kwargs, options, parts, capfd):
    """GIS layers go through hpfc-pack --parts-dir: their features read by
    the workers in ranges (or by hpfc-pack), noded and projected once,
    built on the workers, joined with their features."""
    flags = list(options)
    if "root" in kwargs:
        flags += ["--root", "%dx%d" % kwargs["root"], "--layout", kwargs["layout"]]
    nodings = set()
    for src in GIS:
        want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc", *flags)
        r = subprocess.run([pack_tool, "--json", *flags, str(src), "-o", "-"], capture_output=True,
                           check=False)
        nodings.add(json.loads(r.stderr.decode().splitlines()[-1])["noding"])
        for k in parts:
            out = tmp_path / "got.hpfc"
            capfd.readouterr()
            hpfc.pack(src, out, client=client, partitions=k, options=options, hpfc_pack=pack_tool,
                      **kwargs)
            assert out.read_bytes() == want, (src.name, options, k)
            out.unlink()
            # the workers read the features: hpfc-pack did not fall back
            assert "read by hpfc-pack alone" not in capfd.readouterr().err, src.name
    assert nodings & {"partial", "all"}, nodings  # the noded path is in the test
    assert not list(tmp_path.glob(".hpfc-parts.*")), "the parts' directory was left behind"


def two_layers(tmp_path):
    """A GeoPackage of two layers (lines crossing, borders shared twice)."""
    ogr2ogr = shutil.which("ogr2ogr")
    if not ogr2ogr:
        pytest.skip("ogr2ogr (gdal-bin) not installed")
    gpkg = tmp_path / "two.gpkg"
    ok = TESTS_DATA / "gis" / "ok"
    subprocess.run([ogr2ogr, "-f", "GPKG", "-nln", "borders", str(gpkg), str(ok / "duplicate_borders.geojson")],
                   check=True, capture_output=True)
    subprocess.run([ogr2ogr, "-update", "-nln", "roads", str(gpkg), str(ok / "lines_crossing.geojson")],
                   check=True, capture_output=True)
    return gpkg


def test_gis_layers_read_in_ranges(tmp_path, client, pack_tool, capfd):
    """Two layers cut into ranges, by GeoPackage's random access, in the
    dataset's order and in the order --layer names them: hpfc-pack's bytes."""
    src = two_layers(tmp_path)
    for options in ([], ["-l", "roads", "-l", "borders", "--fields", "all"]):
        want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc", *options)
        for ranges in (2, 4, 40):
            out = tmp_path / "got.hpfc"
            capfd.readouterr()
            hpfc.pack(src, out, client=client, partitions=3, options=options, hpfc_pack=pack_tool,
                      ranges=ranges)
            assert out.read_bytes() == want, (options, ranges)
            assert "read by hpfc-pack alone" not in capfd.readouterr().err
            out.unlink()


def test_gis_ranges_declined_when_gdal_skips_elsewhere(tmp_path, client, pack_tool, capfd):
    """A shapefile whose .dbf marks records deleted: GDAL's GetNextFeature
    passes over them, its SetNextByIndex does not, so ranges after them
    would start early. The ranges' FIDs do not chain: hpfc-pack reads the
    features itself, says so, and writes its own bytes."""
    ogr2ogr = shutil.which("ogr2ogr")
    if not ogr2ogr:
        pytest.skip("ogr2ogr (gdal-bin) not installed")
    shp = tmp_path / "w.shp"
    subprocess.run([ogr2ogr, "-f", "ESRI Shapefile", str(shp), str(TESTS_DATA / "gis" / "countries_world.geojson")],
                   check=True, capture_output=True)
    dbf = bytearray(shp.with_suffix(".dbf").read_bytes())
    records, head, size = int.from_bytes(dbf[4:8], "little"), int.from_bytes(dbf[8:10], "little"), \
        int.from_bytes(dbf[10:12], "little")
    assert records > 20
    for r in (3, 4, records // 2):
        dbf[head + r * size] = ord("*")
    shp.with_suffix(".dbf").write_bytes(bytes(dbf))
    want = hpfc_pack(pack_tool, shp, tmp_path / "want.hpfc", "--fields", "all")
    capfd.readouterr()
    hpfc.pack(shp, tmp_path / "got.hpfc", client=client, partitions=3, options=["--fields", "all"],
              hpfc_pack=pack_tool, ranges=4)
    assert (tmp_path / "got.hpfc").read_bytes() == want
    err = capfd.readouterr().err
    assert "the ranges read elsewhere were not taken" in err and "SetNextByIndex" in err, err


def drive_ranges(pack_tool, src, out, shared, ranges, options=(), tamper=None, answer=b"read\n",
                 tag=None, json_report=True):
    """hpfc-pack --read-ranges by hand: the ranges read by hpfc-pack
    --read-range (with `tag`, else the reading's), `tamper(shared)`
    applied, `answer` sent; then, if it goes on, every part built here.
    `json_report`: the report as --json prints it, else as text. (exit
    status, stdout after the plan, stderr)."""
    report_flags = ["--json"] if json_report else []
    proc = subprocess.Popen([pack_tool, *report_flags, "--partitions", "3", "--parts-dir", str(shared),
                             "--read-ranges", str(ranges), *options, str(src), "-o", str(out)],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    first = json.loads(proc.stdout.readline())
    assert 1 <= len(first["ranges"]) <= ranges + 1 and len(first["tag"]) == 16, first
    for k, (layer, begin, end) in enumerate(first["ranges"]):
        r = subprocess.run([pack_tool, "-q", "--read-range", "%d:%d:%s" % (layer, begin, "end" if end < 0 else end),
                            "--range-tag", tag or first["tag"], *options, "-o", str(shared / ("range-%d" % k)),
                            str(src)], capture_output=True, text=True, check=False)
        assert r.returncode == 0, r.stderr
    if tamper:
        tamper(shared)
    if answer:
        proc.stdin.write(answer)
        proc.stdin.flush()
    else:
        proc.stdin.close()  # then the parts' line cannot come either
        proc.stdin = None
    line = proc.stdout.readline()
    if line:
        plan = json.loads(line)
        for k in range(plan["parts"]):
            hpfc._hpfc._pack_part(str(shared), plan, k)
        if answer:
            proc.stdin.write(b"built\n")
    rest, err = proc.communicate(timeout=120)
    return proc.returncode, rest.decode(), err.decode()


def report(text):
    """A --json report without what a run's clock or directory changes."""
    def timeless(d):
        return {k: timeless(v) if isinstance(v, dict) else v for k, v in d.items()
                if not k.endswith("seconds")}
    return {k: v for k, v in timeless(json.loads(text)).items() if k not in ("parts", "output")}


def test_read_ranges_protocol(tmp_path, pack_tool):
    """--read-ranges driven by hand: the same bytes and report as hpfc-pack
    alone (features, empty ones, antimeridian cuts, invalid polygons and
    their names); a range file flipped, of another reading, swapped, cut
    short or missing refused with one line naming it and no output; after
    'failed' the features read by hpfc-pack itself."""
    out = tmp_path / "out.hpfc"
    n = noded = 0
    for src, options in [(TESTS_DATA / "gis" / "ok" / "antimeridian_mixed.geojson", ["--fields", "all"]),
                         (TESTS_DATA / "gis" / "ok" / "empty_geometries.geojson", []),
                         (TESTS_DATA / "gis" / "bad" / "self_intersecting_ring.geojson", []),
                         (TESTS_DATA / "gis" / "countries_world.geojson", ["--key", "name"])]:
        alone = subprocess.run([pack_tool, "--json", "--force", *options, str(src), "-o", str(tmp_path / "a.hpfc")],
                               capture_output=True, text=True, check=True)
        text = subprocess.run([pack_tool, "--force", *options, str(src), "-o", str(tmp_path / "b.hpfc")],
                              capture_output=True, text=True, check=True)
        repaired = [ln for ln in text.stdout.splitlines() if ln.startswith("repaired")]
        for ranges in (2, 3):
            n += 1
            shared = tmp_path / ("s%d" % n)
            shared.mkdir()
            rc, rest, err = drive_ranges(pack_tool, src, out, shared, ranges, options)
            assert (rc, err) == (0, ""), err
            assert out.read_bytes() == (tmp_path / "a.hpfc").read_bytes(), src.name
            assert report(rest) == report(alone.stdout), src.name
            out.unlink()
        # the text report's names of the polygons noded, word for word
        shared = tmp_path / ("t%d" % n)
        shared.mkdir()
        rc, rest, err = drive_ranges(pack_tool, src, out, shared, 3, options, json_report=False)
        assert rc == 0, err
        out.unlink()
        assert [ln for ln in rest.splitlines() if ln.startswith("repaired")] == repaired, src.name
        noded += bool(repaired)
    assert noded >= 1  # a layer with invalid polygons noded is in the test

    src = TESTS_DATA / "gis" / "countries_world.geojson"
    want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc")

    def flip(shared):
        p = shared / "range-1"
        data = bytearray(p.read_bytes())
        data[len(data) // 2] ^= 0x04
        p.write_bytes(bytes(data))

    def swap(shared):
        a, b = shared / "range-0", shared / "range-1"
        tmp = a.read_bytes()
        a.write_bytes(b.read_bytes())
        b.write_bytes(tmp)

    def cut(shared):
        p = shared / "range-2"
        p.write_bytes(p.read_bytes()[:-9])

    def missing(shared):
        (shared / "range-0").unlink()

    for k, (tamper, tag, words) in enumerate([
            (flip, None, "range-1: damaged range file"),
            (swap, None, "range-0: a range file of another reading"),
            (cut, None, "range-2: damaged range file"),
            (missing, None, "range-0: cannot read"),
            (None, "0123456789abcdef", "range-0: a range file of another reading")]):
        shared = tmp_path / ("bad-%d" % k)
        shared.mkdir()
        rc, rest, err = drive_ranges(pack_tool, src, out, shared, 3, tamper=tamper, tag=tag)
        assert rc == 1 and err.startswith("hpfc-pack: ") and words in err, (k, err)
        assert len(err.strip().splitlines()) == 1, err
        assert not out.exists(), k
    for k, answer in enumerate((b"failed\n", b"done\n")):  # read by hpfc-pack itself
        shared = tmp_path / ("here-%d" % k)
        shared.mkdir()
        rc, rest, err = drive_ranges(pack_tool, src, out, shared, 3, tamper=missing, answer=answer)
        assert (rc, err) == (0, ""), err
        assert out.read_bytes() == want
        out.unlink()
    shared = tmp_path / "closed"
    shared.mkdir()
    rc, rest, err = drive_ranges(pack_tool, src, out, shared, 3, answer=b"")
    assert rc == 1 and "standard input ended" in err and not out.exists(), err


def test_gis_notes_passed_on(tmp_path, client, pack_tool, capfd):
    """hpfc-pack's notes on the input (a guessed SRS, rings noded, ...)
    reach the caller's standard error, word for word."""
    # a layer without an SRS, in the longitude/latitude range: hpfc-pack notes WGS 84
    ogr2ogr = shutil.which("ogr2ogr")
    if not ogr2ogr:
        pytest.skip("ogr2ogr (gdal-bin) not installed")
    bare = tmp_path / "bare.shp"
    subprocess.run([ogr2ogr, "-f", "ESRI Shapefile", "-nlt", "PROMOTE_TO_MULTI", "-where",
                    "OGR_GEOMETRY='Polygon' OR OGR_GEOMETRY='MultiPolygon'", str(bare),
                    str(TESTS_DATA / "gis" / "ok" / "world.geojson")], check=True, capture_output=True)
    bare.with_suffix(".prj").unlink()
    noted = 0
    for src in GIS + [bare]:
        r = subprocess.run([pack_tool, str(src), "-o", str(tmp_path / "x.hpfc")],
                           capture_output=True, text=True, check=False)
        (tmp_path / "x.hpfc").unlink()
        capfd.readouterr()
        hpfc.pack(src, tmp_path / "got.hpfc", client=client, partitions=3, hpfc_pack=pack_tool)
        (tmp_path / "got.hpfc").unlink()
        notes = [ln for ln in capfd.readouterr().err.splitlines() if ln.startswith("hpfc-pack: ")]
        assert notes == r.stderr.splitlines(), src.name
        noted += bool(notes)
    assert noted >= 1  # a fixture with a note is in the test


def test_mesh_same_bytes_as_hpfc_pack(tmp_path, client, pack_tool):
    src = TESTS_DATA / "mesh" / "ok" / "delaunay_q11.drc"
    want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc")
    hpfc.pack(src, tmp_path / "got.hpfc", client=client, partitions=6, hpfc_pack=pack_tool)
    assert (tmp_path / "got.hpfc").read_bytes() == want


def test_gis_failure_is_hpfc_packs(tmp_path, client, pack_tool):
    """A layer hpfc-pack refuses: the same words, no output, no parts."""
    refused = 0
    for src in sorted((TESTS_DATA / "gis" / "bad").glob("*")):
        r = subprocess.run([pack_tool, "-q", str(src), "-o", str(tmp_path / "x.hpfc")],
                           capture_output=True, text=True, check=False)
        if r.returncode == 0:  # refused only with --invalid reject
            (tmp_path / "x.hpfc").unlink()
            continue
        refused += 1
        with pytest.raises(hpfc.Error) as e:
            hpfc.pack(src, tmp_path / "out.hpfc", client=client, partitions=3, hpfc_pack=pack_tool)
        assert e.value.code == r.returncode, src.name
        assert "hpfc-pack: " + e.value.message == r.stderr.strip().splitlines()[-1], src.name
    assert refused >= 5, refused
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def drive(pack_tool, src, out, shared, parts, tamper=None, answer=b"built\n"):
    """hpfc-pack --parts-dir by hand: the plan read, every part built here,
    `tamper(shared, plan)` applied, `answer` sent. (exit status, stderr)."""
    proc = subprocess.Popen([pack_tool, "-q", "--partitions", str(parts), "--parts-dir", str(shared),
                             str(src), "-o", str(out)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    plan = json.loads(proc.stdout.readline())
    for k in range(plan["parts"]):
        try:
            hpfc._hpfc._pack_part(str(shared), plan, k)
        except hpfc.Error:
            pass  # the graph's flaw, which hpfc-pack words after "failed"
    if tamper:
        tamper(shared, plan)
    _, err = proc.communicate(answer, timeout=120)
    return proc.returncode, err.decode()


def flip_byte(shared, plan):
    p = shared / "part-1.part"
    data = bytearray(p.read_bytes())
    data[len(data) // 2] ^= 0x10
    p.write_bytes(bytes(data))


def swap_parts(shared, plan):
    a, b = shared / "part-0.part", shared / "part-1.part"
    tmp = a.read_bytes()
    a.write_bytes(b.read_bytes())
    b.write_bytes(tmp)


def test_parts_dir_protocol(tmp_path, pack_tool):
    src = streets(tmp_path / "s.pfc", 14, 5)
    want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc")
    other = streets(tmp_path / "o.pfc", 14, 6)  # another map, the same plan's shape
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    drive(pack_tool, other, tmp_path / "o.hpfc", foreign, 4)
    (tmp_path / "o.hpfc").unlink()

    def foreign_part(shared, plan):
        (shared / "part-2.part").write_bytes((foreign / "part-2.part").read_bytes())

    def missing_part(shared, plan):
        (shared / "part-3.part").unlink()

    out = tmp_path / "out.hpfc"
    for n, (tamper, answer, words) in enumerate([
            (flip_byte, b"built\n", "part-1.part: "),
            (foreign_part, b"built\n", ""),
            (missing_part, b"built\n", "part-3.part: "),
            (None, b"failed\n", "a part's build failed"),
            (None, b"", "standard input ended before the parts were built"),
            (None, b"done\n", "'built' or 'failed' expected")]):
        shared = tmp_path / ("shared-%d" % n)
        shared.mkdir()
        rc, err = drive(pack_tool, src, out, shared, 4, tamper, answer)
        assert rc == 1 and err.startswith("hpfc-pack: ") and words in err, (n, err)
        assert len(err.strip().splitlines()) == 1, err
        assert not out.exists(), n
    for n, tamper in enumerate((None, swap_parts)):  # a part file knows its root pixels
        shared = tmp_path / ("shared-ok-%d" % n)
        shared.mkdir()
        assert drive(pack_tool, src, out, shared, 4, tamper) == (0, "")
        assert out.read_bytes() == want
        out.unlink()


def test_part_refuses_a_bad_plan(tmp_path, pack_tool):
    """A worker's plan comes from a JSON line: one that does not hold
    together is an error, never a crash or a huge allocation."""
    src = streets(tmp_path / "s.pfc", 8, 2)
    plan = hpfc._hpfc._pack_cut(str(src), str(tmp_path), 4, 4, 2, 2, 16, 3)
    assert hpfc._hpfc._pack_part(str(tmp_path), plan, 2).endswith("part-2.part")
    for change in ({"root": [2**32 - 1, 2**32 - 1], "parts": 1}, {"parts": 0}, {"parts": 99},
                   {"domain": [0, 0, 0, 0, 3]}, {"edges": 0}, {"unit_exp10": 99}):
        bad = dict(plan, **change)
        with pytest.raises(hpfc.Error):
            hpfc._hpfc._pack_part(str(tmp_path), bad, 0)
    for bad in ({}, {"parts": "x"}, dict(plan, domain=[1, 2])):
        with pytest.raises((TypeError, ValueError, OverflowError)):
            hpfc._hpfc._pack_part(str(tmp_path), bad, 0)


def test_parts_dir_words_a_flaw_as_hpfc_pack(tmp_path, pack_tool):
    """A crossing only the parts see: after 'failed', hpfc-pack validates
    the whole graph and says what hpfc-pack alone says."""
    bad = tmp_path / "crossing.pfc"
    bad.write_text("pfc 1\nv 0 0\nv 100 100\nv 0 100\nv 100 0\nv 300 300\nv 400 300\ne 0 1\ne 2 3\ne 4 5\n")
    alone = subprocess.run([pack_tool, "-q", str(bad), "-o", str(tmp_path / "x.hpfc")],
                           capture_output=True, text=True, check=False)
    shared = tmp_path / "shared"
    shared.mkdir()
    rc, err = drive(pack_tool, bad, tmp_path / "out.hpfc", shared, 4, answer=b"failed\n")
    assert (rc, err) == (alone.returncode, alone.stderr)
    assert "cross" in err, err


def test_routed_parts_refuse_foreign_files(tmp_path):
    """The workers' read driven by hand (chunks scanned and filled into the
    graph file, routed, a part built from them): a route file cut short,
    two swapped, one of another plan, one missing and a graph file of
    another map are each refused with a message, never built from."""
    from hpfc import _hpfc
    src = streets(tmp_path / "s.pfc", 14, 5)

    def read(directory, path):
        directory.mkdir()
        bounds = _hpfc._pfc_chunks(str(path), 3)
        scans = [_hpfc._pfc_scan(str(path), b, e) for b, e in bounds]
        totals = tuple(sum(s[k] for s in scans) for k in range(3))
        graph = str(directory / "graph")
        _hpfc._graph_create(graph, *totals, 0)
        firsts, ranges, boxes = [0, 0, 0], [], []
        for (b, e), s in zip(bounds, scans):
            boxes.append(_hpfc._pfc_fill(str(path), b, e, s, graph, totals, 0, tuple(firsts)))
            ranges.append((firsts[1], firsts[1] + s[1]))
            firsts = [firsts[k] + s[k] for k in range(3)]
        box = (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes),
               max(b[3] for b in boxes))
        return graph, ranges, box

    d = tmp_path / "d"
    graph, ranges, box = read(d, src)
    assert len(ranges) == 3
    plan = _hpfc._pack_plan(graph, 8, 8, 2, 2, 16, 4, box)
    for k, (e0, e1) in enumerate(ranges):
        _hpfc._pfc_route(str(d), plan, k, e0, e1)
    good = {k: (d / ("route-%d" % k)).read_bytes() for k in range(3)}
    assert _hpfc._pack_part_routed(str(d), plan, 1, 3).endswith("part-1.part")

    def refused(what):
        with pytest.raises(hpfc.Error) as e:
            _hpfc._pack_part_routed(str(d), plan, 1, 3)
        assert e.value.name in ("HPFC_E_CORRUPT", "HPFC_E_IO"), what
        for k in range(3):
            (d / ("route-%d" % k)).write_bytes(good[k])

    (d / "route-1").write_bytes(good[1][:-4])
    refused("cut short")
    (d / "route-0").write_bytes(good[1])
    (d / "route-1").write_bytes(good[0])
    refused("swapped")
    other = dict(plan, parts=5)
    _hpfc._pfc_route(str(d), other, 2, *ranges[2])
    refused("another plan's")
    (d / "route-2").unlink()
    refused("missing")
    # a graph file of another map under the same routes
    e = tmp_path / "e"
    read(e, streets(tmp_path / "t.pfc", 9, 6))
    shutil.copy(e / "graph", d / "graph")
    refused("another map's graph")
