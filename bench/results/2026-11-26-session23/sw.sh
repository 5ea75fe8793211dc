#!/bin/bash
# Session 23, device: per-pass times of stress N=20/100 and foliage at 1 px (main, 8b14cf5), and
# raster_sw variants through --shader-dir (.gpu/sd/): S1 decodes each thread's triangle before the
# vertex barrier; S2 also runs 64-thread workgroups (two triangles a thread). Two interleaved rounds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/sw.txt
setup $o N
T0=$SECONDS
warm N
for r in 1 2; do
  for v in base S1 S2; do
    sd=""; [ $v != base ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/sw-$v-r$r
    timeout 120 /tmp/vgeo-N bench $sd --suite full --scenes stress,foliage --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== r$r $v rc=$? t=$((SECONDS - T0))" >> $o
    python3 bench/results/2026-11-26-session23/passes.py $d/bench.json >> $o 2>&1 || tail -3 $d.log >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
