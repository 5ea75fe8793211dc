#!/bin/bash
# Session 23, device: the review's raster_sw mend R (vertex snapping and the snapped triangle as
# helpers both paths call; the same operations) against F (295f2eb's code): stress N = 20 / 100 /
# 200 (4 frames), outdoor and foliage (8 frames), vgeo at 1 px, the close blade; two interleaved
# rounds, then whether R's images equal F's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/mend.txt
setup $o F R
T0=$SECONDS
warm F
for r in 1 2; do
  for b in F R; do
    d=/tmp/m-$b-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes outdoor,foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $b t=$((SECONDS - T0))" >> $o
    for x in s t; do summary $d-$x/bench.json tris >> $o 2>&1; done
    timeout 60 /tmp/vgeo-$b render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$b.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
for x in s t; do for f in /tmp/m-F-r1-$x/images/*.png; do n=$(basename $f); cmp -s $f /tmp/m-R-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o; done; done
cmp -s /tmp/close-F.png /tmp/close-R.png && echo "  same close" >> $o || echo "  differ close" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
