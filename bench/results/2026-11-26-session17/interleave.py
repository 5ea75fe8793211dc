#!/usr/bin/env python3
"""Writes the call-7 experiment's raster_sw (lane i of warp w takes triangle 4 i + w, so a warp's
triangles are spread over the cluster) from the built-in shader, for --shader-dir.
Usage: interleave.py shaders_glsl/raster_sw.comp.glsl OUT_DIR/raster_sw.comp.glsl"""
import sys

src, dst = sys.argv[1:3]
s = open(src).read()
edits = [
    ("        if (tid < tcount) {\n            uvec3 t = cluster_triangle(d, c, tid);\n",
     "        // (Experiment: lane i of warp w takes triangle 4 i + w, so a warp's triangles are spread\n"
     "        // over the cluster rather than neighbours in its stored order.)\n"
     "        uint tri = (tid & 31u) * 4u + (tid >> 5u);\n"
     "        if (tri < tcount) {\n            uvec3 t = cluster_triangle(d, c, tri);\n"),
    ("raster_triangle(v, z, visible_index, tid, width, height);",
     "raster_triangle(v, z, visible_index, tri, width, height);"),
]
for old, new in edits:
    assert s.count(old) == 1, f"{src}: the experiment's edit no longer applies: {old!r}"
    s = s.replace(old, new)
open(dst, "w").write(s)
