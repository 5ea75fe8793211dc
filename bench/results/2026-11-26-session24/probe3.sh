#!/bin/bash
# Session 24, device: timing probe (images not vgeo's): B (raster_sw drops the triangles it would
# give the shared large-triangle pass, its code unchanged) against M (main, 526eb64) and L
# (probe.sh): is L's foliage gain the dropped work or the smaller shader? Foliage (8 frames),
# stress N = 20 (4 frames), vgeo at 1 px; two interleaved rounds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/probe3.txt
setup $o M
T0=$SECONDS
warm M
for r in 1 2; do
  for v in M B L; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-M bench $sd --suite full --scenes foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    python3 bench/results/2026-11-26-session23/passes.py $d-s/bench.json >> $o 2>&1 || tail -3 $d-s.log >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
