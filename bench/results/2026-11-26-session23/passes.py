#!/usr/bin/env python3
"""Per scene of a `vgeo bench` report: GPU ms, triangles, clusters, then every pass's mean ms.
Usage: passes.py BENCH_JSON"""
import json, sys

r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = s.get("passes_mean", [])
    print(f"  {s['scene']:12} {s.get('mode','')} {s.get('error_px','')}px {s['gpu_ms_mean']:8.3f} ms  tris {s['triangles_mean']:.0f}")
    print("    " + "  ".join(f"{k} {v:.3f}" for k, v in p))
