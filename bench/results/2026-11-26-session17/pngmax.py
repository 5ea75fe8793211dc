#!/usr/bin/env python3
"""Pixels that differ between two PNGs (8-bit RGB/RGBA, stdlib only), the largest channel
difference, and how many pixels differ by more than 2 of 255. Usage: pngmax.py A.png B.png"""
import importlib.util, os, sys

here = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    "pngdiff", os.path.join(here, "..", "2026-11-25-session15", "pngdiff.py"))
pngdiff = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pngdiff)
(wa, ha, bpa, a), (wb, hb, bpb, b) = pngdiff.read_png(sys.argv[1]), pngdiff.read_png(sys.argv[2])
assert (wa, ha, bpa) == (wb, hb, bpb), "sizes differ"
n = big = worst = 0
for ra, rb in zip(a, b):
    if ra == rb:
        continue
    for i in range(0, len(ra), bpa):
        d = max(abs(ra[i + k] - rb[i + k]) for k in range(3))
        if d:
            n += 1
            big += d > 2
            worst = max(worst, d)
print(f"{n} of {wa * ha} pixels differ, largest channel difference {worst}, {big} by more than 2")
