#!/bin/bash
# Session 28, device, call 4: the lod baseline with the same rule for closed solids (an instance
# seen from outside its box drawn with CULL_MODE_BACK). F = session 27's release binary, L = this
# session's final tree. Two interleaved rounds of lod at 1 px (bench, no reference: times and
# triangles) on the four scenes (8 frames) and stress N=20 (4 frames); which lod images differ.
# Then final.sh with L (the full run with errors: the README tables). Outputs: cmp.txt, final.tgz.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/cmp.txt
setup $o F L
T0=$SECONDS
warm L
for r in 1 2; do
  for v in F L; do
    d=/tmp/lod-$v-r$r
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes lod --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes stress --stress-n 20 --frames 4 --modes lod --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
  done
done
echo "== lod images F/L" >> $o
for x in s t; do
  for f in /tmp/lod-F-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/lod-L-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
BIN=L bash bench/results/2026-11-27-session28/final.sh
