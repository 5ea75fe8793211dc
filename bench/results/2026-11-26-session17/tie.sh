#!/bin/bash
# Session 17, device (1920x1080, 1 px): does the order of a fan's triangles (the triangles that
# share their largest index m, whose relative order the code leaves free) change raster_sw's cost?
# H = 233b13b; T = the max-delta code with a temporary switch VGEO_ZZ_TIE (not in the repo):
# unset = stable (as committed), a / b = sorted by (m, second / third corner), ra = (m, second
# corner descending). The same bytes in every variant. Two interleaved rounds of vgeo bench on
# stress N=20, 100 (4 frames) and foliage.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tie.txt
setup $o H T
T0=$SECONDS
warm H
for r in 1 2; do
  for v in H T T-a T-b T-ra; do
    b=${v%%-*}; tie=${v#T-}; [ "$v" = T ] && tie=""; [ $b = H ] && tie=""
    d=/tmp/s-$v-r$r
    VGEO_ZZ_TIE=$tie timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress,foliage --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== $v r$r t=$((SECONDS - T0))" >> $o
    summary $d/bench.json sw bytes >> $o 2>&1
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
