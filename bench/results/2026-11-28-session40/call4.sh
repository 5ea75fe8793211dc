#!/bin/bash
# Session 40, call 4 (H200): W = main + small instances under partial residency take their
# table's finest resident row (before: every instance of a streaming mesh walked its BVH, and
# call 3 measured stress N=20 streamed +34 % against all resident). First W's streamed bench as
# call 3 ran Z's (every scene, 64 MiB, settled cameras against all resident); then W against
# Z with every page resident, runs Z W W Z at the suite's 16 frames (W changes only the cull of
# meshes with absent pages, and adds code to cull.glsl), and W's errors at 1 px.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-Z vgeo-W
warm Z
T0=$SECONDS
timeout 150 /tmp/vgeo-W bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --geometry-budget 64 --stream-mib-per-frame 64 --quiet --out $OUT/Wstreamed > $OUT/Wstreamed.log 2>&1
echo "== W streamed rc=$? t=$((SECONDS - T0))" >> $o
pack
for r in Za Wa Wb Zb; do
  [ $((SECONDS - T0)) -gt 420 ] && break
  timeout 60 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $OUT/$r-big > $OUT/$r-big.log 2>&1
  echo "== $r big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 70 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --quiet --out $OUT/$r-scenes > $OUT/$r-scenes.log 2>&1
  echo "== $r scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
timeout 80 /tmp/vgeo-W bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eW-scenes > $OUT/eW-scenes.log 2>&1
echo "== eW scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
