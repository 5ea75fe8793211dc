#!/usr/bin/env python3
"""One line per scene of a `vgeo bench` report: GPU ms, then the columns asked for.
Usage: summary.py BENCH_JSON [sw] [hw] [emit] [tris] [bytes]"""
import json, sys

r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    pass_ms = lambda prefix: sum(v for k, v in p.items() if k.startswith(prefix))
    columns = {
        "sw": lambda: f"raster_sw {pass_ms('raster_sw'):6.3f}",
        "hw": lambda: f"raster_hw {pass_ms('raster_hw'):6.3f}",
        "emit": lambda: f"emit {pass_ms('emit_gbuffer'):6.3f}",
        "tris": lambda: f"tris {s['triangles_mean']:.0f}",
        "bytes": lambda: f"B/stored tri {s['bytes_per_stored_triangle']:.2f}",
    }
    line = [f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms"] + [columns[c]() for c in sys.argv[2:]]
    print("  ".join(line))
