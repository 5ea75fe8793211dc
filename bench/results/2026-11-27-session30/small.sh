#!/bin/bash
# Session 30, device call 5: the small SW clusters four to a workgroup (Q: 32 invocations a cluster,
# clusters of at most 85 vertices) or eight (Q8: 16 invocations, at most 42 vertices); N = main at 2c3598a.
# Call 6: QB = Q with room for 170 vertices a cluster (s_mem 2,040 words).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small.txt
setup $o N
warm N
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 frames=$2 scenes=$3 rep=$4
  local d=$OUT/$name-f$frames$rep
  local sd=""
  [ "$name" != N ] && sd="--shader-dir .gpu/sd/$name"
  timeout 200 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 100,200 --frames $frames --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name f$frames big rc=$? t=$((SECONDS - T0))" >> $o
  if [ $scenes = 1 ]; then
    timeout 200 /tmp/vgeo-N bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
    echo "== $name scenes rc=$? t=$((SECONDS - T0))" >> $o
  fi
  pack
}
run N 4 1 a; run QB 4 1 a; run Q 4 1 a; run N 4 1 b; run QB 4 1 b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
