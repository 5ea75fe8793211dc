#!/bin/bash
# Session 23, device: issue 14 acceptance 5 on the final code F (295f2eb: the small-instance table
# and the small SW clusters): stress N = 20 to 100 (8 K to 1 M instances) and 200 (8 M), vgeo at
# 1 px, 4 frames; the scaling plots against instances and scene triangles.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o F
T0=$SECONDS
warm F
d=/tmp/scaling
timeout 300 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20,30,40,50,60,70,80,90,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o
mkdir -p $OUT/scaling
cp $d/bench.md $d/*.svg $OUT/scaling/ 2>/dev/null
summary $d/bench.json tris >> $o 2>&1
echo "== total $((SECONDS - T0)) s" >> $o
