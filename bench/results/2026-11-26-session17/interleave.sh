#!/bin/bash
# Session 17, device (1920x1080, 1 px): does raster_sw's canonical-order cost come from a warp's
# triangles being neighbours? H (233b13b) and N (the max-delta code) each with their built-in
# shaders and with --shader-dir /tmp/interleave, written by interleave.py from the built-in raster_sw
# (lane i of warp w takes triangle 4 i + w).
# Two interleaved rounds of vgeo bench on stress N=20, 100 (4 frames) and foliage.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/interleave.txt
setup $o H N
IL=/tmp/interleave; mkdir -p $IL
python3 $D/interleave.py shaders_glsl/raster_sw.comp.glsl $IL/raster_sw.comp.glsl
T0=$SECONDS
warm H
for r in 1 2; do
  for v in H H-il N N-il; do
    b=${v%-il}; sd=""; [ $v != $b ] && sd="--shader-dir $IL"
    d=/tmp/s-$v-r$r
    timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress,foliage --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d > $d.log 2>&1
    echo "== $v r$r t=$((SECONDS - T0))" >> $o
    summary $d/bench.json sw >> $o 2>&1
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
