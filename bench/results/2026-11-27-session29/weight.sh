#!/bin/bash
# Session 29, device call 1: a lower weight on the table rows' error for small instances
# (shader-only probe, `--shader-dir .gpu/sd/<V>`: emit_tiny_cut multiplies a row's error by
# clamp(radius_px / R, WMIN, 1)): W8 = R 8 px, WMIN 0.25; W16 = R 16, 0.25; W8H = R 8, 0.5.
# Per configuration: stress N=20 at 384x216 and 192x108 (instances of N=100's and N=200's size at
# 1080p) against the 4x4-spp reference; stress N=20 and foliage at 1080p against theirs; stress
# N=100 and 200 timed (vgeo, 4 frames). Baseline M = main (01b5e9c), no shader dir.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/weight.txt
setup $o M
warm M
T0=$SECONDS
run() {
  local name=$1; shift
  local d=$OUT/$name
  local sd=""
  [ "$name" != M ] && sd="--shader-dir .gpu/sd/$name"
  for res in "384 216" "192 108"; do
    set -- $res
    timeout 200 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet $sd --out $d-tiny$2 > $d-tiny$2.log 2>&1
    echo "== $name tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
  done
  timeout 200 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 20 --frames 1 --modes brute,vgeo --sweep 1 --quiet $sd --out $d-s20 > $d-s20.log 2>&1
  echo "== $name s20 rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-M bench --suite full --scenes foliage --frames 2 --modes brute,vgeo --sweep 1 --quiet $sd --out $d-fol > $d-fol.log 2>&1
  echo "== $name foliage rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 100,200 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name big rc=$? t=$((SECONDS - T0))" >> $o
}
for c in ${CONFIGS:-M W8 W16 W8H}; do run $c; done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/w.tgz --exclude='*.png' --exclude='*.svg' --exclude=images . && rm -rf $OUT/* && mv /tmp/w.tgz $OUT/
