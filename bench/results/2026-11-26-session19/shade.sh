#!/bin/bash
# Session 19, device: `shade` with several pixels per thread. B = main (8x8 threads, one pixel
# each); S32, S64 = 16x16 threads over tiles of 32, 64 pixels (4, 16 pixels a
# thread; shared::SHADE_TILE). The close blade and the empty frame (issue 14 acceptance 4),
# interleaved, three rounds; per-pass times of one frame each; then the bench scenes for B and
# S32/S64, and the lit images of S32 against B (compare_images: H = B, N = S32).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/shade.txt
setup $o B S32 S64
cp /tmp/vgeo-B /tmp/vgeo-H; cp /tmp/vgeo-S32 /tmp/vgeo-N
T0=$SECONDS
warm B
for r in 1 2 3; do
  for b in B S32 S64; do
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s.png 2>&1 | grep -E "timed" | sed "s/^/  r$r $b $s /" >> $o
    done
  done
done
for b in B S32 S64; do
  for s in close empty; do
    timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --stats --out /tmp/$s.png 2>&1 | grep -E "GPU time|shade|emit|classify" | sed "s/^/  $b $s /" >> $o
  done
done
echo "== t=$((SECONDS - T0))" >> $o
for b in B S32 S64; do
  d=/tmp/sc-$b
  timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
  timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
  echo "== $b t=$((SECONDS - T0))" >> $o
  for x in t s; do summary $d-$x/bench.json >> $o 2>&1; done
  python3 - $d-s/bench.json >> $o <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    print(f"    {s['scene']:10} shade {p.get('shade', 0):.4f} ms")
PY
done
echo "== images (lit, 1920x1080, 1 px): pixels of S32 that differ from B, t=$((SECONDS - T0))" >> $o
compare_images $o bench/results/2026-11-25-session15/pngdiff.py
echo "== total $((SECONDS - T0)) s" >> $o
