#!/bin/bash
# Session 23, device: small instances cut from their mesh's table (T, this session's build) against
# main before it (N = 8b14cf5), and T with the 64-thread raster_sw (.gpu/sd/S2, --shader-dir).
# Stress N = 20 / 100 / 200 and foliage at 1 px, 4 frames, per-pass times; three interleaved rounds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tiny_cut.txt
setup $o N T
T0=$SECONDS
warm N
warm T
for r in 1 2 3; do
  for v in N T TS2; do
    b=${v:0:1}; sd=""; [ $v = TS2 ] && sd="--shader-dir .gpu/sd/S2"
    d=/tmp/tc-$v-r$r
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes stress,foliage --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== r$r $v rc=$? t=$((SECONDS - T0))" >> $o
    python3 bench/results/2026-11-26-session23/passes.py $d/bench.json >> $o 2>&1 || tail -3 $d.log >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
