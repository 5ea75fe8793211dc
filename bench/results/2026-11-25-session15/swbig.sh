#!/bin/bash
# Session 15 (H100, 1920x1080, 1 px): raster_sw's large triangles rasterized by the whole
# workgroup (pieces of rows) instead of one invocation each. One binary (.gpu/vgeo-M.gz) and
# shader folders for every variant (so every variant is compiled the same way, by --shader-dir):
#   base  = .gpu/hwpos (main's shaders: raster_hw's hw_position, the old raster_sw)
#   e64 = .gpu/sw-e64 (plus the new raster_sw, RASTER_SW_BIG_BOX_PIXELS = 64)
# (Call 7 ran a first form that rasterized one large triangle at a time, bN; call 8 dealt pieces
# round-robin over all of a cluster's large triangles, rN, behind a barrier of their own; this is
# call 9 drew them at the start of the workgroup's next cluster, without a barrier of their own,
# dN (slower: double buffers); this is call 10: call 8's form, skipped (with its barrier) for a
# cluster whose projected bounding sphere is too small to hold a large triangle.)
# Per variant: vgeo bench on outdoor, indoor, foliage, drawcalls (8 frames) and stress N=20, 100
# (4 frames), and the close turbine blade (render --stats, 8 frames); two rounds. Then images
# (view triangles) of base and e64 compared with pngdiff.py: the same pixels are expected.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo; chmod +x /tmp/vgeo; V=/tmp/vgeo
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > $OUT/swbig.txt 2>&1
T0=$SECONDS
dir() { case $1 in base) echo $PWD/.gpu/hwpos;; *) echo $PWD/.gpu/sw-$1;; esac; }
timeout 60 $V bench --suite full --scenes outdoor --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
for r in 1 2; do
  vs="base e64"
  for v in $vs; do
    export VGEO_SHADER_DIR=$(dir $v)
    d=/tmp/sw-$v-r$r
    timeout 90 $V bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 90 $V bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== $v r$r t=$((SECONDS - T0))" >> $OUT/swbig.txt
    for x in s t; do
      python3 - $d-$x/bench.json >> $OUT/swbig.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  raster_sw {sw:6.3f}  tris {s['triangles_mean']:.0f}  hw {s.get('hw_clusters_mean')}")
PY
    done
    timeout 60 $V render .gpu/close.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/close-$v.png 2>&1 | grep -E "GPU time|raster_sw|main:" | sed 's/^/  close /' >> $OUT/swbig.txt
  done
done
for v in base e64; do
  export VGEO_SHADER_DIR=$(dir $v)
  for s in foliage; do timeout 60 $V render assets/scenes/$s.toml --width 1920 --height 1080 --view triangles --out /tmp/img-$s-$v.png > /dev/null 2>&1; done
  timeout 60 $V render .gpu/close.toml --width 1920 --height 1080 --view triangles --out /tmp/img-close-$v.png > /dev/null 2>&1
done
for s in foliage close; do python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/img-$s-base.png /tmp/img-$s-e64.png >> $OUT/swbig.txt 2>&1; done
echo "== total $((SECONDS - T0)) s" >> $OUT/swbig.txt
