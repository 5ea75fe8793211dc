#!/usr/bin/env python3
"""Mean GPU ms per pass of each binary's runs for one scene (and how many frames of the path):
Usage: passes.py CALL_DIR SCENE KIND A H  (KIND: the run folder's suffix, e.g. scenes)"""
import json, glob, sys
d, scene, kind, bins = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
per = {}
for b in bins:
    acc = {}; n = 0
    for f in sorted(glob.glob(f"{d}/{b}[a-z]-{kind}/bench.json")):
        for r in json.load(open(f))["records"]:
            if r["scene"] != scene or r["mode"] != "vgeo": continue
            n += 1
            for name, ms in r["passes"]:
                acc[name] = acc.get(name, 0.0) + ms
    per[b] = {k: v / max(n, 1) for k, v in acc.items()}
names = list(per[bins[0]].keys())
for k in names:
    vals = [per[b].get(k, 0.0) for b in bins]
    print(f"{k:24}" + "".join(f"{v:9.4f}" for v in vals) + f"  {vals[-1]-vals[0]:+.4f}")
print(f"{'total':24}" + "".join(f"{sum(per[b].values()):9.4f}" for b in bins))
