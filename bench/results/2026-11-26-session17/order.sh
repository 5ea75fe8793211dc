#!/bin/bash
# Session 17, device (1920x1080, 1 px): is raster_sw's +5 % with the max-delta triangle code the
# decoding or the canonical triangle order? H = main before (233b13b), N = the code, P = the same
# binary as N's code with VGEO_ZZ_PLAIN=1 (a temporary switch: canonical order, plain packed
# indices). Two interleaved rounds of vgeo bench on stress N=20, 100 (4 frames) and foliage.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/order.txt
setup $o H N P
T0=$SECONDS
warm H
for r in 1 2; do
  for b in H N P; do
    d=/tmp/s-$b-r$r
    env=""; [ $b = P ] && env="VGEO_ZZ_PLAIN=1"
    env $env timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress,foliage --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== $b r$r t=$((SECONDS - T0))" >> $o
    summary $d/bench.json sw emit bytes >> $o 2>&1
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
