#!/bin/bash
# Session 17, device (1920x1080, 1 px): the max-delta triangle code (N, .gpu/vgeo-N.gz) against
# main before it (H, .gpu/vgeo-H.gz, 233b13b). Two interleaved rounds per binary: vgeo bench on
# stress N=20, 100 (4 frames) and outdoor, indoor, foliage, drawcalls (8 frames); the close blade
# and the empty frame timed as the bench times (render --time 64). Then each scene's lit image and
# the close blade's, H against N (pixels that differ), and the GPU bytes per stored triangle.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/frames.txt
setup $o H N
T0=$SECONDS
warm H
for r in 1 2; do
  for b in H N; do
    d=/tmp/s-$b-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    echo "== $b r$r t=$((SECONDS - T0))" >> $o
    for x in t s; do
      summary $d-$x/bench.json sw hw emit tris bytes >> $o 2>&1
    done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --stats --time 64 --out /tmp/$s-$b.png 2>&1 | grep -E "GPU time|timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images (lit, 1920x1080, 1 px): pixels of N that differ from H" >> $o
compare_images $o bench/results/2026-11-25-session15/pngdiff.py
echo "== total $((SECONDS - T0)) s" >> $o
