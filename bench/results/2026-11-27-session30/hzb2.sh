#!/bin/bash
# Session 30, device call 3: H5E = the 5x5-texel HZB window with an early exit; B5 = H5E with the
# instance tested by its mesh's box (the BVH root's) instead of the cube around its sphere.
# Call 4: R5 = B5 with each row of the window read in one unrolled step (independent loads, an
# exit per row); M, B5, R5 twice each, interleaved.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/hzb2.txt
setup $o M
warm M
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 frames=$2 scenes=$3 rep=$4
  local d=$OUT/$name-f$frames$rep
  local sd=""
  [ "$name" != M ] && sd="--shader-dir .gpu/sd/$name"
  timeout 200 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 100,200 --frames $frames --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name f$frames big rc=$? t=$((SECONDS - T0))" >> $o
  if [ $scenes = 1 ]; then
    timeout 200 /tmp/vgeo-M bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
    echo "== $name scenes rc=$? t=$((SECONDS - T0))" >> $o
  fi
  pack
}
run M 4 1 a; run B5 4 1 a; run R5 4 1 a; run M 4 1 b; run R5 4 1 b; run B5 4 1 b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
