#!/bin/bash
# Session 30, device call 1: a finer HZB test (shader-only probe, `--shader-dir .gpu/sd/<V>`):
# hzb_rect_occluded picks the level where the box spans at most 3x3 texels (H3) or 5x5 (H5)
# instead of 2x2 (M = main, no shader dir). Per configuration: stress N=100 and 200 (4 frames),
# stress N=20, foliage, outdoor, indoor, drawcalls (vgeo at 1 px, timed).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/hzb.txt
setup $o M
warm M
T0=$SECONDS
run() {
  local name=$1; shift
  local d=$OUT/$name
  local sd=""
  [ "$name" != M ] && sd="--shader-dir .gpu/sd/$name"
  timeout 200 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 100,200 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-M bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
  echo "== $name scenes rc=$? t=$((SECONDS - T0))" >> $o
  (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz)
}
for c in ${CONFIGS:-M H5 S5 S9 E}; do run $c; done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && find $OUT -mindepth 1 -delete && mv /tmp/h.tgz $OUT/
