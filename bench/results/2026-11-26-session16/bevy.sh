#!/bin/bash
# Session 16, calls 2 and 10 (device machine, 1920x1080): issue 14 item 7, vgeo against Bevy 0.19.1's
# virtual geometry (meshlets) on the stress scene, in one call. First `vgeo bench --scenes stress`
# (VGEO_GZ, default .gpu/vgeo-M.gz: main at 6b555f9 in call 2 on an H200; call 10 on an H100 with
# VGEO_GZ=.gpu/vgeo-S.gz, main at 59f10e4) at N = 8, 20, 50, 100, 16 frames of the path, 1 px; then the
# Bevy harness (.gpu/vgeo-peer-bevy.gz, bench/peers/bevy/run.sh) over the same N, mesh and path.
# Results: $OUT/vgeo-stress.txt, $OUT/bevy.tgz (summary.md, per-N json/log/png).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c ${VGEO_GZ:-.gpu/vgeo-M.gz} > /tmp/vgeo; chmod +x /tmp/vgeo
T0=$SECONDS
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/vgeo-stress.txt 2>&1
timeout 60 /tmp/vgeo bench --suite full --scenes stress --stress-n 8 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
timeout 150 /tmp/vgeo bench --suite full --scenes stress --stress-n 8,20,50,100 --frames 16 --modes vgeo --sweep 1 --quiet --out /tmp/vs > /tmp/vs.log 2>&1
echo "vgeo bench rc=$? t=$((SECONDS - T0)) s" >> $OUT/vgeo-stress.txt
python3 - /tmp/vs/bench.json >> $OUT/vgeo-stress.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print("device:", r.get("device"))
for s in r["summary"]:
    print(f"| vgeo | {s['scene']} | {s['gpu_ms_mean']:.3f} ms | tris {s['triangles_mean']:.0f} |")
PY
tail -5 /tmp/vs.log >> $OUT/vgeo-stress.txt
cp /tmp/vs/bench.json $OUT/vgeo-stress.json 2>/dev/null
BEVY_TIMEOUTS="45 60 90 240" bash bench/peers/bevy/run.sh .gpu/vgeo-peer-bevy.gz "" /tmp/bevy
tar czf $OUT/bevy.tgz -C /tmp bevy
echo "total $((SECONDS - T0)) s" >> $OUT/vgeo-stress.txt
