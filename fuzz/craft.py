#!/usr/bin/env python3
"""Writes hand-crafted .hpfc regression files (spec/hpfc-format.md).

The fuzzers find inputs by mutation; some findings are easier to keep as a
file built on purpose, with valid checksums so that a plain hpfc_open gets
past them to the decoder. Each function below builds one such file, named
after the finding it pins down (fuzz/README.md, "Findings").

    python3 fuzz/craft.py OUTDIR     writes every file into OUTDIR
"""
import struct
import sys


def crc32c(data, crc=0):
    crc ^= 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF


class Bits:
    """An MSB-first bit stream (spec §2.2, "Bit order")."""

    def __init__(self, nbits):
        self.nbits = nbits
        self.buf = bytearray((nbits + 7) // 8)

    def put(self, off, k, value):
        for b in range(k):
            if value >> (k - 1 - b) & 1:
                pos = off + b
                self.buf[pos >> 3] |= 0x80 >> (pos & 7)


def address_bits(s):
    return 0 if s <= 1 else (s - 1).bit_length()


def hpfc_file(root, image, levels, width, height, pools, x0=0, y0=0, crs=None):
    """levels: per level (word_pixels, refined_pixels, images, word_bits);
    pools: per level a function(Bits, k_at, s) filling the level's pool.
    Computes k_@ and s by the recurrence, lays out POOL, fills checksums."""
    n0, m0 = root
    n, m = image
    L = len(levels)
    k_at = [0] * L
    s = [0] * L
    below = 0
    for l in range(L - 1, -1, -1):
        nw, na, images, kw = levels[l]
        k_at[l] = address_bits(below) if l + 1 < L else 0
        if l == 0:
            s[l] = n0 * m0 * (1 + max(k_at[l], kw))
        else:
            s[l] = images * n * m + nw * kw + na * k_at[l]
        below = s[l]
    sections = 1 + (crs is not None)
    meta = 128 + 64 * L + 32 * sections
    pool_start = (meta + 31) // 32 * 32
    offsets, pos, body = [], pool_start, bytearray()
    for l in range(L):
        offsets.append(pos)
        bits = Bits(s[l])
        pools[l](bits, k_at[l], s[l])
        body += bits.buf
        pos += len(bits.buf)
        pad = (-pos) % 8
        body += bytes(pad)
        pos += pad
    pool_len = offsets[-1] + (s[-1] + 7) // 8 - pool_start
    body = body[:pool_len]
    file_size = pool_start + pool_len
    crs_off = None
    if crs is not None:
        crs_off = (file_size + 7) // 8 * 8
        file_size = crs_off + len(crs)
    head = bytearray(128)
    head[0:8] = b"\x89HPFC\r\n\x1a"
    struct.pack_into("<HHIII", head, 8, 1, 0, 128, 0, 0)
    struct.pack_into("<IIIIII", head, 24, n0, m0, n, m, L, sections)
    struct.pack_into("<qqqqi", head, 48, x0, y0, width, height, 0)
    struct.pack_into("<QQ", head, 88, file_size, meta)
    table = bytearray()
    for l in range(L):
        nw, na, images, kw = levels[l]
        table += struct.pack("<QQQIIQQ16x", nw, na, images, kw, k_at[l], offsets[l], s[l])
    directory = struct.pack("<4sIQQI4x", b"POOL", 1, pool_start, pool_len, crc32c(bytes(body)))
    if crs is not None:
        directory += struct.pack("<4sIQQI4x", b"CRS ", 0, crs_off, len(crs), crc32c(crs))
    out = bytearray(head + table + directory)
    out += bytes(pool_start - len(out))
    out += body
    if crs is not None:
        out += bytes(crs_off - len(out)) + crs
    struct.pack_into("<I", out, 124, crc32c(bytes(out[:meta])))
    return bytes(out)


def aliased_images(depth=30):
    """Every refined pixel of every level points at image 0 of the next
    level, whose four pixels are all refined again: a DAG whose leaf paths
    number 4^(L-1) in a file of a few kilobytes. Before the fix,
    hpfc_faces_build counted those paths one by one (a hang)."""
    L = depth
    levels = [(0, 1, 1, 0), (0, 4, 1, 0)]
    for l in range(2, L - 1):
        levels.append((12, 4, 4, 4))
    levels.append((16, 0, 4, 4))

    def root_pool(bits, k_at, s):
        bits.put(0, 1, 1)  # refined, address 0

    def mid_pool(bits, k_at, s):
        bits.put(0, 4, 0b1111)  # image 0: four refined pixels, addresses 0

    def last_pool(bits, k_at, s):
        pass  # masks 0000, words "++++" (0000)

    pools = [root_pool] + [mid_pool] * (L - 2) + [last_pool]
    side = 2 ** (L - 1)
    return hpfc_file((1, 1), (2, 2), levels, side, side, pools)


CODES = {"+": "0", "=": "1000", "[": "1001", "]": "1010", "(": "1011", "Y": "1100", ")": "1101"}


def word_code(word):
    """The bit string of a word (spec §5.2.3); "R" writes the reserved 1111."""
    return "".join(CODES.get(c, "1111") for c in word)


def put_word(bits, off, word):
    code = word_code(word)
    if code:
        bits.put(off, len(code), int(code, 2))


def faces_gap_overflow():
    """Root 2 x 1: the west pixel refined into 2 x 2 word pixels, the east
    one a word pixel Q whose west road has no crossing. The south-east
    child claims 4 crossings on its east road (Q's west road), the
    north-east child none. From the north-east child the face builder
    counts the crossings after it along Q's side (4) and used that count as
    an index into Q's crossings (Q has 2): before the fix, a read and write
    past the end of its union-find array."""
    words = ["++++", "++++", "++++", "++[][]++"]  # NW, NE, SW, SE children
    q = "+[+]++"
    kw1 = max(len(word_code(w)) for w in words)
    kw0 = len(word_code(q))

    def root_pool(bits, k_at, s):
        r = 1 + max(k_at, kw0)
        bits.put(0, 1, 1)  # record 0: refined, address 0
        put_word(bits, r + 1, q)  # record 1: type 0, then Q's word

    def level1_pool(bits, k_at, s):
        for p, w in enumerate(words):  # mask 0000, then four word slots
            put_word(bits, 4 + p * kw1, w)

    levels = [(1, 1, 1, kw0), (4, 0, 1, kw1)]
    return hpfc_file((2, 1), (2, 2), levels, 4, 2, [root_pool, level1_pool])


FILES = {
    "aliased_images.hpfc": aliased_images,
    "faces_gap_overflow.hpfc": faces_gap_overflow,
}

if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    for name, make in FILES.items():
        with open(f"{sys.argv[1]}/{name}", "wb") as f:
            f.write(make())
