#!/bin/bash
# Session 19, device: raster_sw and raster_hw without the barrier between them (X) against main
# (N, be8adeb). Both only do atomicMax on the visibility buffer (and the overdraw counter), which
# commute; without the barrier the hardware pass may overlap the compute one. Three interleaved
# rounds: bench scenes and stress N=20, 100 at 1 px; the close blade and the empty frame; then
# the lit images of X against N (compare_images: H = N, N = X).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/overlap.txt
setup $o N X
T0=$SECONDS
warm N
for r in 1 2 3; do
  for b in N X; do
    if [ $((SECONDS - T0)) -gt 420 ]; then echo "== skip r$r $b (time)" >> $o; continue; fi
    x=/tmp/ov-$b-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $x-t > $x-t.log 2>&1
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $x-s > $x-s.log 2>&1
    echo "== r$r $b t=$((SECONDS - T0))" >> $o
    for y in t s; do summary $x-$y/bench.json sw hw >> $o 2>&1; done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
    done
  done
done
cp /tmp/vgeo-N /tmp/vgeo-H; cp /tmp/vgeo-X /tmp/vgeo-N
echo "== images (lit, 1920x1080, 1 px): pixels of X that differ from N, t=$((SECONDS - T0))" >> $o
compare_images $o bench/results/2026-11-25-session15/pngdiff.py
echo "== total $((SECONDS - T0)) s" >> $o
