#!/bin/bash
# Session 23, device: Y (X with the small clusters' vertices in the halves of the other path's
# shared arrays, clusters of at most 127 vertices: X's own arrays cost every raster_sw workgroup
# shared memory) against W (979ba24), and Y1 (Y with no cluster sent to the small list, through
# --shader-dir: the split's fixed cost). Foliage, outdoor (8 frames), stress N = 20 / 100 / 200
# (4 frames), vgeo at 1 px; the close blade; two interleaved rounds; then whether Y's images
# equal W's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small2.txt
setup $o W Y
T0=$SECONDS
warm W
warm Y
for r in 1 2; do
  for v in W Y Y1; do
    b=${v:0:1}; sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 120 /tmp/vgeo-$b bench $sd --suite full --scenes outdoor,foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-$b render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "== images W/Y" >> $o
for x in s t; do
  for f in /tmp/su-W-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-Y-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
cmp -s /tmp/close-W.png /tmp/close-Y.png && echo "  same close" >> $o || echo "  differ close" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
