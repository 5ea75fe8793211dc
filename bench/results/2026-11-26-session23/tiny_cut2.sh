#!/bin/bash
# Session 23, device: the table's cut with each cluster still tested (frustum, HZB) as the walk
# tests it: V1 always, V2 when the instance's radius projects over 4 px, V1S2 V1 with the 64-thread
# raster_sw (all through --shader-dir on this session's build T); against main N (8b14cf5) and T.
# Stress N = 20 / 100 / 200 and foliage at 1 px, 4 frames, per-pass times; two interleaved rounds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tiny_cut2.txt
setup $o N T
T0=$SECONDS
warm N
warm T
for r in 1 2; do
  for v in N T V1 V2 V1S2; do
    b=T; [ $v = N ] && b=N
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/tc-$v-r$r
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes stress,foliage --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== r$r $v rc=$? t=$((SECONDS - T0))" >> $o
    python3 bench/results/2026-11-26-session23/passes.py $d/bench.json >> $o 2>&1 || tail -3 $d.log >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
