#!/bin/bash
# Session 19, device: what the faithful 1 px costs stress (issue 14 acceptance 1). The turbine
# blade built twice here (.gpu/posonly/): with the default attribute-aware error and with
# `vgeo build --normal-weight 0` (position and coverage error only: the error before issue 11's
# shading term). Stress N = 20 and 100, vgeo at 1 px, 4 frames, main at dcb864f (N); each through
# a scenes folder whose stress.toml names that .vgeo file. Timing only: no reference.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/posonly.txt
setup $o N
T0=$SECONDS
warm N
for r in 1 2; do
  for v in faithful pos; do
    d=/tmp/po-$v-r$r
    timeout 90 /tmp/vgeo-N bench --suite full --scenes-dir .gpu/posonly/$v --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== r$r $v rc=$? t=$((SECONDS - T0))" >> $o
    summary $d/bench.json sw tris >> $o 2>&1 || tail -3 $d.log >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
