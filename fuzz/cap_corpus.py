#!/usr/bin/env python3
"""Picks a small corpus from a libFuzzer merge control file (fuzz/run.sh --merge).

    python3 fuzz/cap_corpus.py CONTROL_FILE OUT_DIR [MAX_FILES [MAX_BYTES]]

libFuzzer's -merge=1 keeps every input that adds a feature, which can be
many hundred files. Its control file lists, per input (smallest first), the
features (FT) and edges (COV) that input added to those before it. This
keeps at most MAX_FILES (200) files and MAX_BYTES (2 MiB): first the inputs
that add edges, most edges first, then those adding the most features, the
smaller input on a tie. The edge and feature counts printed are lower
bounds of what the kept files cover. Files are copied to OUT_DIR under
their SHA-1.
"""
import hashlib
import os
import shutil
import sys


def read_control(path):
    with open(path) as f:
        lines = f.read().split("\n")
    n = int(lines[0])
    files = lines[2:2 + n]
    ft, cov, size = {}, {}, {}
    for line in lines[2 + n:]:
        parts = line.split()
        if len(parts) < 2:
            continue
        kind, idx = parts[0], int(parts[1])
        if kind == "STARTED":
            size[idx] = int(parts[2])
        elif kind == "FT":
            ft[idx] = set(parts[2:])
        elif kind == "COV":
            cov[idx] = set(parts[2:])
    done = [i for i in range(n) if i in ft]
    return files, done, ft, cov, size


def greedy(cands, sets, chosen, covered, size, max_files, budget):
    while len(chosen) < max_files:
        best, gain = None, 0
        for i in cands:
            if i in chosen or size[i] > budget[0]:
                continue
            g = len(sets.get(i, set()) - covered)
            if g > gain or (g == gain and g and size[i] < size[best]):
                best, gain = i, g
        if best is None:
            return
        chosen.append(best)
        covered |= sets.get(best, set())
        budget[0] -= size[best]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    control, out = sys.argv[1], sys.argv[2]
    max_files = int(sys.argv[3]) if len(sys.argv) > 3 else 200
    max_bytes = int(sys.argv[4]) if len(sys.argv) > 4 else 2 << 20
    files, done, ft, cov, size = read_control(control)
    for i in done:
        size.setdefault(i, os.path.getsize(files[i]))
    chosen, budget = [], [max_bytes]
    greedy(done, cov, chosen, set(), size, max_files, budget)
    features = set()
    for i in chosen:
        features |= ft[i]
    greedy(done, ft, chosen, features, size, max_files, budget)
    os.makedirs(out, exist_ok=True)
    for i in chosen:
        with open(files[i], "rb") as f:
            data = f.read()
        with open(os.path.join(out, hashlib.sha1(data).hexdigest()), "wb") as f:
            f.write(data)
    all_cov = set().union(*(cov.get(i, set()) for i in done)) if done else set()
    all_ft = set().union(*(ft[i] for i in done)) if done else set()
    kept_cov = set().union(*(cov.get(i, set()) for i in chosen)) if chosen else set()
    kept_ft = set().union(*(ft[i] for i in chosen)) if chosen else set()
    print(f"kept {len(chosen)} of {len(done)} inputs, {max_bytes - budget[0]} bytes; "
          f"edges {len(kept_cov)}/{len(all_cov)}, features {len(kept_ft)}/{len(all_ft)}")


if __name__ == "__main__":
    main()
