"""hpfc.pack and python3 -m hpfc pack: a .pfc packed in parts on a Dask
LocalCluster of two worker processes gives hpfc-pack's very bytes (the
oracle), for the fixtures and a generated street network, under several
partitions and options; a worker killed in the middle of the build is
replaced by Dask and the file is still the same; a failure leaves no
output and no parts behind. Skipped where dask.distributed is missing
(Debian: python3-distributed, which tools/install-deps.sh installs)."""

import math
import os
import random
import signal
import subprocess
import sys
import threading
import time

import pytest

from conftest import TESTS_DATA

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
]


def inputs(tmp_path):
    return sorted((TESTS_DATA / "valid").glob("*.pfc")) + [streets(tmp_path / "streets.pfc", 24, 7)]


@pytest.mark.parametrize("kwargs,flags", OPTIONS)
def test_same_bytes_as_hpfc_pack(tmp_path, client, pack_tool, kwargs, flags):
    for src in inputs(tmp_path):
        want = hpfc_pack(pack_tool, src, tmp_path / "want.hpfc", *flags)
        for parts in (1, 3, 7):
            out = tmp_path / ("got-%d.hpfc" % parts)
            hpfc.pack(src, out, client=client, partitions=parts, **kwargs)
            assert out.read_bytes() == want, (src.name, kwargs, parts)
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
