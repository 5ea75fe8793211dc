#!/usr/bin/env python3
"""Per scene: GPU ms of each binary (mean of its runs, and each run), triangles, bytes per stored
triangle, and the error at 1 px where an e<B>-* run has it. Usage: table.py CALL_DIR A H (the frames of the path in the key)"""
import json, os, sys, glob
d, bins = sys.argv[1], sys.argv[2:]
rows = {}
for b in bins:
    for f in sorted(glob.glob(f"{d}/{b}[a-z]-*/bench.json")):
        for s in json.load(open(f))["summary"]:
            key = s["scene"] + (f" N={s['stress_n']}" if s.get("stress_n") else "") + f" f{s['frames']}"
            r = rows.setdefault(key, {}).setdefault(b, {"ms": [], "tris": [], "bytes": None, "db": None})
            r["ms"].append(s["gpu_ms_mean"]); r["tris"].append(s["triangles_mean"])
            r["bytes"] = s.get("bytes_per_stored_triangle")
    for f in glob.glob(f"{d}/e{b}-*/bench.json"):
        j = json.load(open(f)); w = j["settings"]["width"]
        for s in j["summary"]:
            if s["mode"] != "vgeo": continue
            key = s["scene"] + (f" N={s['stress_n']}" if s.get("stress_n") else "") + f" f{s['frames']}"
            if w != 1920: key += f" @{w}"
            rows.setdefault(key, {}).setdefault(b, {"ms": [], "tris": [], "bytes": None, "db": None})["db"] = s["psnr_db"]
for key, r in rows.items():
    base = r.get(bins[0], {}).get("ms")
    m0 = sum(base) / len(base) if base else None
    out = [f"{key:18}"]
    for b in bins:
        x = r.get(b)
        if not x: continue
        if x["ms"]:
            m = sum(x["ms"]) / len(x["ms"])
            rel = f" {100 * (m / m0 - 1):+5.1f}%" if m0 and b != bins[0] else ""
            out.append(f"{b} {m:.3f}{rel} ({'/'.join(f'{v:.3f}' for v in x['ms'])}) {sum(x['tris'])/len(x['tris'])/1e3:.0f}K B {x['bytes']:.3f}" if x["bytes"] else f"{b} {m:.3f}{rel}")
        if x["db"] is not None: out.append(f"{b} {x['db']:.2f} dB")
    print("  ".join(out))
