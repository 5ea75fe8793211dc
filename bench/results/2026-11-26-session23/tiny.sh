#!/bin/bash
# Session 23, device: what image error tiny instances cost at coarser cuts (issue 14 acceptance 1).
# Stress N = 20 at 384x216 has instances of the size N = 100 has at 1920x1080 (about 5 px), and
# at 768x432 those of N = 50; its 4x4-spp reference can be rendered. The blade built with the
# normal weight 1 (default), 0.25 and 0 (position and coverage only), .gpu/po/; vgeo swept over
# 0.5-8 px against brute at 1 spp. Main at 8b14cf5 (.gpu/vgeo-N.gz).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tiny.txt
setup $o N
T0=$SECONDS
for res in 384x216 768x432; do
  for w in 1 0.25 0; do
    d=$OUT/tiny-$res-w$w
    timeout 240 /tmp/vgeo-N bench --suite full --scenes-dir .gpu/po/w$w --scenes stress --stress-n 20 --width ${res%x*} --height ${res#*x} --frames 2 --modes brute,vgeo --sweep 0.5,1,2,4,8 --quiet --out $d > $d.log 2>&1
    echo "== $res w$w rc=$? t=$((SECONDS - T0))" >> $o
    rm -rf $d/*.png $d/*.svg
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
