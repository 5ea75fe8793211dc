#!/bin/bash
# Session 16, calls 6, 8 and 9 (device, 1920x1080, 1 px): the cull's statistics. N = .gpu/vgeo-N.gz
# (before: an atomic per test), S = .gpu/vgeo-S.gz. Call 6: S summed them per invocation and added
# them once at its end (it hung on the device; not kept). Call 8: S keeps them only in frames
# whose counters are read back (VIEW_FLAG_CULL_STATS), not in timed paths. Call 9: the same on
# an H100 (kind nvidia-h100-x1) with SCENES=outdoor,indoor,foliage,drawcalls. Per binary and round:
# vgeo bench on stress N=20, 100 (4 frames) and foliage, outdoor (8 frames); the close blade and
# the empty frame (render --stats, 8 frames). Then the --stats lines of both (the same counts are
# expected) and their images (view triangles; the same pixels are expected).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in N S; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/stats.txt 2>&1
T0=$SECONDS
timeout 60 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
for r in 1 2; do
  for b in N S; do
    d=/tmp/s-$b-r$r
    timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    timeout 60 /tmp/vgeo-$b bench --suite full --scenes ${SCENES:-foliage,outdoor} --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    echo "== $b r$r t=$((SECONDS - T0))" >> $OUT/stats.txt
    for x in t s; do
      python3 - $d-$x/bench.json >> $OUT/stats.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    cull = sum(v for k, v in p.items() if "cull" in k)
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  cull {cull:6.3f}  raster_sw {sw:6.3f}  tris {s['triangles_mean']:.0f}  visible inst {s['instances_visible_mean']:.0f}")
PY
    done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s-$b.png 2>&1 | grep -E "GPU time|timed" | sed "s/^/  $s /" >> $OUT/stats.txt
    done
  done
done
for b in N S; do
  timeout 60 /tmp/vgeo-$b render assets/scenes/foliage.toml --width 1920 --height 1080 --stats --view triangles --out /tmp/img-foliage-$b.png 2>&1 | grep -E "^  (main|post):" > /tmp/st-$b.txt
done
echo "== --stats lines (foliage), N then S; diff:" >> $OUT/stats.txt
cat /tmp/st-N.txt >> $OUT/stats.txt
diff /tmp/st-N.txt /tmp/st-S.txt >> $OUT/stats.txt && echo "  (identical)" >> $OUT/stats.txt
python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/img-foliage-N.png /tmp/img-foliage-S.png >> $OUT/stats.txt 2>&1
echo "== total $((SECONDS - T0)) s" >> $OUT/stats.txt
