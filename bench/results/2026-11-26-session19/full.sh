#!/bin/bash
# Session 19, device: issue 14 acceptance 2 (vgeo against lod at equal measured error, ratios and
# the speed-against-error plots) with main at be8adeb (N): the four bench scenes in all three
# modes, lod and vgeo swept over 0.25-4 px, errors against brute at 4x4 samples per pixel
# (the bench's default reference), 8 frames; then stress N=20 (2 frames) if time is left.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o N
T0=$SECONDS
d=/tmp/full
timeout 400 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --sweep 0.25,0.5,1,2,4 --quiet --out $d > $d.log 2>&1
echo "== scenes rc=$? t=$((SECONDS - T0))" >> $o
tail -3 $d.log >> $o
mkdir -p $OUT/scenes; cp $d/bench.md $d/bench.json $d/*.svg $OUT/scenes/ 2>/dev/null
left=$((540 - (SECONDS - T0)))
if [ $left -gt 100 ]; then
  s=/tmp/full-stress
  timeout $left /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --frames 2 --sweep 0.5,1,2 --quiet --out $s > $s.log 2>&1
  echo "== stress rc=$? t=$((SECONDS - T0))" >> $o
  tail -3 $s.log >> $o
  mkdir -p $OUT/stress; cp $s/bench.md $s/bench.json $s/*.svg $OUT/stress/ 2>/dev/null
fi
echo "== total $((SECONDS - T0)) s" >> $o
