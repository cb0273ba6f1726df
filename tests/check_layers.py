#!/usr/bin/env python3
"""The library's files form layers: no two call each other, directly or
round a longer cycle (issue 19's "no two library files call each other").

Usage: check_layers.py LIBRARY.a

Reads the archive's symbol tables with nm: a file "calls" another when it
uses a symbol the other defines. Prints each cycle of files and exits 1 if
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
    print(f"{len(nodes)} files, {sum(len(c) for c in calls.values())} file-to-file calls, "
          f"{len(found)} cycles")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
