#!/bin/bash
# Session 20, device (1920x1080, 1 px): the generalized-strip triangle code (N, branch b2-tricode:
# call 3 at 9537abd, call 4 at 7411add)
# against main before it (H). Three interleaved rounds per binary, the split fixed at 64 px in
# both (the A/B is the triangle decoding, not the tuner): vgeo bench on stress N=20, 100 (4 frames)
# and outdoor, indoor, foliage, drawcalls (8 frames), with the GPU bytes per stored triangle; the
# close blade and the empty frame (render --time 64). Then each scene's lit image and the close
# blade's, H against N (pixels that differ and by how much).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/b2.txt
setup $o H N
T0=$SECONDS
warm H
for r in 1 2 3; do
  for b in H N; do
    if [ $((SECONDS - T0)) -gt 480 ]; then echo "== skip $b r$r (time)" >> $o; continue; fi
    d=/tmp/s-$b-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --hw-threshold 64 --quiet --out $d-t > $d-t.log 2>&1
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --hw-threshold 64 --quiet --out $d-s > $d-s.log 2>&1
    echo "== $b r$r t=$((SECONDS - T0))" >> $o
    for x in t s; do
      summary $d-$x/bench.json sw hw emit tris bytes >> $o 2>&1
    done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --hw-threshold 64 --time 64 --out /tmp/$s-$b.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images (lit, 1920x1080, 1 px): N against H" >> $o
compare_images $o bench/results/2026-11-26-session17/pngmax.py
echo "== total $((SECONDS - T0)) s" >> $o
