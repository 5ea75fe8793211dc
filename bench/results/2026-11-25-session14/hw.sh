#!/bin/bash
# Session 14 (issue 14 item 4: a hardware path worth its name), H100: raster_hw's mesh-shader path
# against vertex pulling. The release binary is .gpu/vgeo (this branch, `hw`); outputs go to $OUT.
# For foliage, stress N=100 and outdoor (vgeo only, 1920x1080, 1 px, paths of 8 frames, stress 4):
#   hybrid (the default --hw-threshold 32) with --hw-path mesh and vertex,
#   every cluster to HW (--hw-threshold 0) with --hw-path mesh and vertex,
#   software only (--hw-threshold 100000: only near-plane clusters go to HW).
# Per run: bench.md (GPU ms, triangles, clusters) and bench.json (passes_mean: GPU ms per pass);
# passes.txt gathers per-pass means of every run. A run starts only if it ends by 470 s even at its
# timeout (75 s, stress 110 s), so the whole takes under 8 minutes.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
# outdoor's scanned meshes are ../shared/assets/scanned/*.ply (relative to the repository).
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
V=.gpu/vgeo
chmod +x $V 2>/dev/null
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > $OUT/log.txt 2>&1
$V info >> $OUT/log.txt 2>&1
T0=$(date +%s)
# name: --hw-threshold --hw-path
CONFIGS="thr0-mesh:0:mesh thr0-vertex:0:vertex hybrid-mesh:32:mesh hybrid-vertex:32:vertex swonly:100000:auto"
for scene in foliage stress; do
  extra="--frames 8"; limit=75
  [ $scene = stress ] && extra="--stress-n 100 --frames 4" && limit=110
  for cfg in $CONFIGS; do
    IFS=: read name thr path <<< "$cfg"
    # Start a run only if it ends within 470 s even at its timeout (the budget is 8 minutes).
    if [ $(( $(date +%s) - T0 + limit )) -gt 470 ]; then echo "== skip $scene $name (time budget)" >> $OUT/log.txt; continue; fi
    d=/tmp/hw-$scene-$name; T1=$(date +%s)
    timeout $limit $V bench --suite full --scenes $scene $extra --modes vgeo --sweep 1 \
      --hw-threshold $thr --hw-path $path --quiet --out $d > $d.log 2>&1
    echo "== $scene $name (--hw-threshold $thr --hw-path $path) rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
    tail -2 $d.log >> $OUT/log.txt
    cp $d/bench.md $OUT/$scene-$name-bench.md 2>/dev/null
    cp $d/bench.json $OUT/$scene-$name-bench.json 2>/dev/null
    grep -E "^\| vgeo" $d/bench.md >> $OUT/log.txt 2>/dev/null
  done
done
# outdoor (hybrid only) and the close mesh: both paths, and a lower SW/HW split on the close mesh.
for path in mesh vertex; do
  d=/tmp/hw-outdoor-hybrid-$path
  timeout 75 $V bench --suite full --scenes outdoor --frames 8 --modes vgeo --sweep 1 --hw-path $path --quiet --out $d > $d.log 2>&1
  echo "== outdoor hybrid-$path rc=$?" >> $OUT/log.txt; grep -E "^\| vgeo" $d/bench.md >> $OUT/log.txt 2>/dev/null
  cp $d/bench.json $OUT/outdoor-hybrid-$path-bench.json 2>/dev/null
  for thr in 32 16 8; do
    echo "=== close $path hw-threshold $thr" >> $OUT/close.txt
    timeout 60 $V render .gpu/close.toml --width 1920 --height 1080 --stats --frames 8 --hw-path $path --hw-threshold $thr --out /tmp/close-$path-$thr.png 2>&1 | grep -E "GPU time|^  [a-z_]+( \(post\))? +[0-9.]+ ms|main:" >> $OUT/close.txt
  done
done
echo "== total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
# Per-pass GPU ms (mean over the path) of every run, from bench.json.
if command -v python3 >/dev/null; then
  python3 - "$OUT" > $OUT/passes.txt 2>&1 <<'PY'
import json, glob, os, sys
out = sys.argv[1]
for f in sorted(glob.glob(os.path.join(out, "*-bench.json"))):
    r = json.load(open(f))
    for s in r.get("summary", []):
        if s.get("mode") != "vgeo":
            continue
        print(f"{os.path.basename(f)[:-11]}: hw path {r.get('hw_path')}, hw threshold "
              f"{r['settings']['hw_threshold_px']} px, {s['scene']}: {s['gpu_ms_mean']:.3f} ms, "
              f"{s['triangles_mean']:.0f} triangles, {s.get('clusters_mean') or 0:.0f} clusters")
        for name, ms in s.get("passes_mean", []):
            print(f"    {name:<24} {ms:8.3f} ms")
PY
fi
