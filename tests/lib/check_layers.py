#!/usr/bin/env python3
"""The library's files form layers: no two call each other, directly or
round a longer cycle, and the groups (libhpfcfile/meson.build: one folder
each) come in order: a file calls only files of its own group and of the
groups before it, so that the reader (common to verify) never reaches the
builder or the writer.

Usage: check_layers.py LIBRARY.a

Reads the archive's symbol tables with nm: a file "calls" another when it
uses a symbol the other defines; a file's group is its folder, which meson
puts before the first '_' of the object's name (read/file.c: read_file.c.o).
Prints each cycle of files and each call against the order, and exits 1 if
there is one; exits 77 (skipped) when nm is missing.
"""
import re
import shutil
import subprocess
import sys
from collections import defaultdict


def file_calls(archive):
    """{object: set of objects whose symbols it uses}."""
    out = subprocess.run(["nm", "-A", archive], capture_output=True, text=True, check=True).stdout
    defined, used = {}, defaultdict(set)
    for line in out.splitlines():
        # "archive:member.o: [address] TYPE symbol"
        m = re.match(r"[^:]*:([^:]+\.o):\s*(?:[0-9a-f]+\s+)?([A-Za-z])\s+(\S+)$", line)
        if not m:
            continue
        obj, kind, sym = m.group(1).rsplit("/", 1)[-1], m.group(2), m.group(3)
        if kind == "U":
            used[obj].add(sym)
        elif kind in "TDBR":
            defined[sym] = obj
    calls = defaultdict(set)
    for obj, syms in used.items():
        calls[obj] |= {defined[s] for s in syms if s in defined and defined[s] != obj}
    return calls, set(defined.values()) | set(used)


GROUPS = ["common", "graph", "read", "traverse", "query", "verify", "build", "write"]


def group_of(obj):
    """The group of an object file, None when it has none."""
    g = obj.split("_", 1)[0]
    return g if g in GROUPS else None


def against_order(calls, nodes):
    """(caller, callee) pairs where the callee's group comes after the
    caller's; files outside every group are reported with caller None."""
    bad = [(None, v) for v in sorted(nodes) if group_of(v) is None]
    for v in sorted(calls):
        for w in sorted(calls[v]):
            gv, gw = group_of(v), group_of(w)
            if gv and gw and GROUPS.index(gw) > GROUPS.index(gv):
                bad.append((v, w))
    return bad


def cycles(calls, nodes):
    """The strongly connected components of more than one file (Tarjan)."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(calls.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return found


def main():
    if not shutil.which("nm"):
        print("nm not found: skipped")
        return 77
    calls, nodes = file_calls(sys.argv[1])
    if len(nodes) < 10:
        print(f"only {len(nodes)} object files read from {sys.argv[1]}: not the library?")
        return 1
    found = cycles(calls, nodes)
    for comp in found:
        print("files that call each other:", " ".join(comp))
    bad = against_order(calls, nodes)
    for v, w in bad:
        if v is None:
            print(f"{w}: in no group (a folder of {', '.join(GROUPS)})")
        else:
            print(f"{v} ({group_of(v)}) calls {w} ({group_of(w)}), a later group")
    print(f"{len(nodes)} files, {sum(len(c) for c in calls.values())} file-to-file calls, "
          f"{len(found)} cycles, {len(bad)} calls against the group order")
    return 1 if found or bad else 0


if __name__ == "__main__":
    sys.exit(main())
