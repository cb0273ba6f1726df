#!/usr/bin/env python3
"""The reader alone links nothing but libc (libhpfcfile/meson.build,
libhpfcreader): every symbol its archive uses and does not define is one
the C library defines, none is the math library's, and it defines none of
the builder's or writer's calls.

Usage: check_reader.py LIBHPFCREADER.a

Reads the archive with nm and the C library's dynamic symbols with nm -D
(found through the C compiler: cc -print-file-name=libc.so.6). Exits 1 on
any foreign symbol, 77 (skipped) without nm or without a libc to read.
"""
import re
import shutil
import subprocess
import sys

# calls of the build and write groups: none may be in the reader
WRITER_CALLS = ("hpfc_build", "hpfc_tree_", "hpfc_file_serialize", "hpfc_pfc_parse",
                "hpfc_file_write_file", "hpfc_file_write_fd")


def symbols(args):
    out = subprocess.run(["nm"] + args, capture_output=True, text=True, check=True).stdout
    defined, used = set(), set()
    for line in out.splitlines():
        m = re.match(r"(?:[^:]*:)?(?:[0-9a-f]+\s+)?([A-Za-z])\s+(\S+)$", line.strip())
        if not m:
            continue
        kind, sym = m.group(1), m.group(2).split("@")[0]
        (used if kind in "Uw" else defined).add(sym)
    return defined, used


def main():
    if not shutil.which("nm"):
        print("nm not found: skipped")
        return 77
    libc = subprocess.run(["cc", "-print-file-name=libc.so.6"], capture_output=True,
                          text=True).stdout.strip()
    if not libc or libc == "libc.so.6":
        print("no libc.so.6 to read: skipped")
        return 77
    defined, used = symbols([sys.argv[1]])
    libc_defined, _ = symbols(["-D", libc])
    # the compiler's own helpers and sanitizer hooks, present in sanitized builds
    foreign = sorted(s for s in used - defined - libc_defined
                     if not s.startswith(("__asan", "__ubsan", "__lsan", "__tsan",
                                          "__sanitizer", "_GLOBAL_OFFSET_TABLE_",
                                          "__stack_chk", "__gmon")))
    writer = sorted(s for s in defined if s.startswith(WRITER_CALLS))
    for s in foreign:
        print(f"the reader uses {s}, which libc does not define")
    for s in writer:
        print(f"the reader defines {s}, a call of the builder or writer")
    print(f"{len(defined)} symbols defined, {len(used - defined)} taken from libc")
    return 1 if foreign or writer else 0


if __name__ == "__main__":
    sys.exit(main())
