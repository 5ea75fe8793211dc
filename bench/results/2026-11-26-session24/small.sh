#!/bin/bash
# Session 24, device: N (the small SW clusters in a pass of their own, raster_sw_small, without
# raster_sw's large-triangle code) against D (153543a: the 526eb64 binary with 153543a's
# raster_sw through --shader-dir). Scenes outdoor, indoor, foliage, drawcalls (8 frames), stress
# N = 20 / 100 / 200 (4 frames), vgeo at 1 px; the close blade and the empty frame; two
# interleaved rounds; then whether N's images equal D's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small.txt
setup $o M N
T0=$SECONDS
warm M
warm N
for r in 1 2; do
  for v in D N; do
    b=M; sd="--shader-dir .gpu/sd/D"; [ $v = N ] && b=N && sd=""
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render $sd .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$v.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images D/N" >> $o
for x in s t; do
  for f in /tmp/su-D-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-N-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-D.png /tmp/$s-N.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
echo "== total $((SECONDS - T0)) s" >> $o
