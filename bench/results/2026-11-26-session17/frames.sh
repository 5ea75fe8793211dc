#!/bin/bash
# Session 17, device (1920x1080, 1 px): the max-delta triangle code (N, .gpu/vgeo-N.gz) against
# main before it (H, .gpu/vgeo-H.gz, 233b13b). Two interleaved rounds per binary: vgeo bench on
# stress N=20, 100 (4 frames) and outdoor, indoor, foliage, drawcalls (8 frames); the close blade
# and the empty frame timed as the bench times (render --time 64). Then each scene's lit image and
# the close blade's, H against N (pixels that differ), and the GPU bytes per stored triangle.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in H N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
o=$OUT/frames.txt
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
T0=$SECONDS
timeout 60 /tmp/vgeo-H bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
for r in 1 2; do
  for b in H N; do
    d=/tmp/s-$b-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    echo "== $b r$r t=$((SECONDS - T0))" >> $o
    for x in t s; do
      python3 - $d-$x/bench.json >> $o 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    hw = sum(v for k, v in p.items() if k.startswith("raster_hw"))
    em = sum(v for k, v in p.items() if k.startswith("emit_gbuffer"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  raster_sw {sw:6.3f}  raster_hw {hw:6.3f}  emit {em:6.3f}  tris {s['triangles_mean']:.0f}  B/stored tri {s['bytes_per_stored_triangle']:.2f}")
PY
    done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --stats --time 64 --out /tmp/$s-$b.png 2>&1 | grep -E "GPU time|timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images (lit, 1920x1080, 1 px): pixels of N that differ from H" >> $o
for s in outdoor indoor foliage drawcalls; do
  for b in H N; do
    timeout 60 /tmp/vgeo-$b render assets/scenes/$s.toml --width 1920 --height 1080 --out /tmp/img-$s-$b.png > /dev/null 2>&1
  done
  echo "  $s: $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/img-$s-H.png /tmp/img-$s-N.png 2>&1)" >> $o
done
echo "  close: $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/close-H.png /tmp/close-N.png 2>&1)" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
