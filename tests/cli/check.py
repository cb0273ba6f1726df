"""Checks used by the CLI contract tests (tests/cli/*.sh).

    check.py oneline STDERR PREFIX     exactly one line, starting with PREFIX
    check.py json FILE                 FILE is one valid JSON value
    check.py report REPORT PFC         hpfc-pack --json report: shape, totals, and
                                       vertex / edge counts of the .pfc input
    check.py agree REPORT INSPECT      hpfc-inspect --json agrees with the report
    check.py unchanged FILE TEXT       FILE holds exactly TEXT

Exit status 0 when the check holds, 1 with a one-line reason otherwise.
"""
import json
import sys

LEVEL_KEYS = ("images", "word_pixels", "refined_pixels", "word_bits",
              "address_bits", "pool_bits")


def fail(msg):
    print("check.py: " + msg, file=sys.stderr)
    sys.exit(1)


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: not valid JSON: {e}")


def pfc_counts(path):
    """Vertices and edges of a .pfc file: records 'v' and 'e' after comments."""
    nv = ne = 0
    with open(path, "rb") as f:
        for line in f:
            fields = line.split(b"#", 1)[0].split()
            if fields and fields[0] == b"v":
                nv += 1
            elif fields and fields[0] == b"e":
                ne += 1
    return nv, ne


def oneline(path, prefix):
    data = open(path, "rb").read()
    lines = data.split(b"\n")
    if len(lines) != 2 or lines[1] != b"":
        fail(f"stderr is not exactly one line: {data!r}")
    if not lines[0].startswith(prefix.encode()):
        fail(f"stderr does not start with {prefix!r}: {data!r}")


def report(path, pfc):
    r = load(path)
    need = ("vertices", "edges", "faces", "components", "root_cols", "root_rows",
            "refine_cols", "refine_rows", "depth", "level_count", "levels",
            "word_pixels", "refined_pixels", "private_pixels", "total_pixels",
            "file_bytes", "bits_per_edge", "build_seconds")
    missing = [k for k in need if k not in r]
    if missing:
        fail(f"{path}: report lacks {missing}")
    nv, ne = pfc_counts(pfc)
    if (r["vertices"], r["edges"]) != (nv, ne):
        fail(f"{path}: {r['vertices']} vertices, {r['edges']} edges; {pfc} has {nv}, {ne}")
    if r["faces"] != r["edges"] - r["vertices"] + 1 + r["components"]:
        fail(f"{path}: faces break Euler's formula")
    levels = r["levels"]
    if len(levels) != r["level_count"] or r["depth"] != r["level_count"] - 1:
        fail(f"{path}: depth / level_count / levels disagree")
    for key in ("word_pixels", "refined_pixels", "private_pixels"):
        if sum(lv[key] for lv in levels) != r[key]:
            fail(f"{path}: levels' {key} do not add up to the total")
    if r["total_pixels"] != r["word_pixels"] + r["refined_pixels"]:
        fail(f"{path}: total_pixels is not word + refined")
    if levels[-1]["refined_pixels"] != 0 or levels[0]["images"] != 1:
        fail(f"{path}: the last level refines or the root is not one image")
    for a, b in zip(levels, levels[1:]):
        if b["images"] != a["refined_pixels"]:
            fail(f"{path}: images of a level differ from refined pixels above")
    if any(lv["private_pixels"] > lv["word_pixels"] for lv in levels):
        fail(f"{path}: more private than word pixels")
    if r["bits_per_edge"] <= 0 or r["file_bytes"] <= 0:
        fail(f"{path}: no file size")


def agree(report_path, inspect_path):
    r, i = load(report_path), load(inspect_path)
    for key in ("root_cols", "root_rows", "refine_cols", "refine_rows", "depth",
                "level_count", "word_pixels", "refined_pixels", "total_pixels"):
        if r[key] != i[key]:
            fail(f"{key}: hpfc-pack says {r[key]}, hpfc-inspect says {i[key]}")
    if r["file_bytes"] != i["file_bytes"]:
        fail(f"file_bytes: hpfc-pack says {r['file_bytes']}, hpfc-inspect {i['file_bytes']}")
    for lr, li in zip(r["levels"], i["levels"]):
        for key in LEVEL_KEYS:
            if lr[key] != li[key]:
                fail(f"level {lr['level']} {key}: {lr[key]} vs {li[key]}")
    for key in ("format_version", "compat_flags", "incompat_flags", "domain",
                "unit_exp10", "crs", "sections"):
        if key not in i:
            fail(f"{inspect_path}: lacks {key}")
    for s in i["sections"]:
        if set(s) < {"tag", "offset", "length", "crc32c"}:
            fail(f"{inspect_path}: section lacks fields: {s}")
    for lv in i["levels"]:
        if set(lv) < set(LEVEL_KEYS) | {"pool_offset", "cell_w", "cell_h"}:
            fail(f"{inspect_path}: level lacks fields: {lv}")


def unchanged(path, text):
    if open(path, "rb").read() != text.encode():
        fail(f"{path} was modified")


def main(argv):
    cmds = {"oneline": (oneline, 2), "json": (load, 1), "report": (report, 2),
            "agree": (agree, 2), "unchanged": (unchanged, 2)}
    if len(argv) < 2 or argv[1] not in cmds or len(argv) - 2 != cmds[argv[1]][1]:
        fail("usage: check.py oneline|json|report|agree|unchanged ARGS")
    cmds[argv[1]][0](*argv[2:])


if __name__ == "__main__":
    main(sys.argv)
