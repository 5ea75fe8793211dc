#!/usr/bin/env python3
"""Counts the pixels that differ between PNG images (8-bit RGB/RGBA, non-interlaced), stdlib only.
Usage: pngdiff.py REF.png OTHER.png [...]: one line per OTHER: differing pixels, total, and the
bounding box of the differences."""
import struct, sys, zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and ctype in (2, 6) and interlace == 0, (path, depth, ctype)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


ref = read_png(sys.argv[1])
for other in sys.argv[2:]:
    o = read_png(other)
    if o[:2] != ref[:2]:
        print(f"{other}: size {o[:2]} != {ref[:2]}")
        continue
    w, h, bpp = ref[0], ref[1], ref[2]
    diff, box = 0, [w, h, -1, -1]
    for y in range(h):
        ra, rb = ref[3][y], o[3][y]
        if ra == rb:
            continue
        for x in range(w):
            if ra[x * bpp:x * bpp + 3] != rb[x * o[2]:x * o[2] + 3]:
                diff += 1
                box = [min(box[0], x), min(box[1], y), max(box[2], x), max(box[3], y)]
    print(f"{other}: {diff} of {w * h} pixels differ" + (f", within x {box[0]}-{box[2]}, y {box[1]}-{box[3]}" if diff else ""))
