"""The figures of bench_read and bench_traverse, and cachegrind's counts,
as the A/B scripts read them (run-ab.sh: layouts; run-ab-builds.sh: builds).

Each script prefixes the programs' lines with its own words (a build's
side, a layout); `prefixed` says how many, and the functions hand them back
with each figure.
"""
import re

# bench_read's rows "(b) LAYOUT fetch + decode ...: N ns each" and "(c) ..."
READ_FIGURES = {"b": "fetch + decode", "c": "locate, depth >= 16"}

# bench_traverse's rows: seed, edges, words per edge (3 columns), rPFC (3),
# then ns per operation in columns 9-17: the dart walk (none, cold, warm),
# the key walk (cold, warm, alone) and the bitmap walk (cold, warm, if);
# see its header.
WALKS = ["dart walk, no cache", "dart walk, cold cache", "dart walk, warm cache",
         "key walk, cold", "key walk, warm", "key operators alone",
         "bitmap walk, cold", "bitmap walk, warm", "bitmap walk, if"]

# `bench_read fetch LAYOUT R` fetches 4,096 random leaves R times over: the
# runs with R = 10 and R = 0 differ by this many fetches.
FETCHES_PER_10_ROUNDS = 40960


def read_figures(path, prefixed=0):
    """(prefix words, figure name, layout, ns) for each bench_read figure."""
    pattern = re.compile(r"\s*".join([r"(\S+)"] * prefixed + [r"\((b|c)\) (\w+) .*: ([\d.]+) ns each"]))
    for line in open(path):
        m = pattern.match(line)
        if m:
            g = m.groups()
            yield g[:prefixed], READ_FIGURES[g[prefixed]], g[prefixed + 1], float(g[prefixed + 2])


def traverse_figures(path, prefixed=0):
    """(prefix words, walk name, ns) for each bench_traverse timing."""
    for line in open(path):
        tok = line.replace("|", " ").split()
        row = tok[prefixed:]
        if len(row) > 17 and row[0].isdigit() and row[1].isdigit():
            for k, name in enumerate(WALKS):
                yield tuple(tok[:prefixed]), name, float(row[8 + k])


def cachegrind_count(path, key="I"):
    """A total from cachegrind's summary on stderr: "I" (instructions
    executed) or a miss count such as "D1  misses"."""
    pattern = key + r"\s+refs:\s+([\d,]+)" if key == "I" else key + r":\s+([\d,]+)"
    return int(re.search(pattern, open(path).read()).group(1).replace(",", ""))
