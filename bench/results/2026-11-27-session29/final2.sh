#!/bin/bash
# Session 29, device call 4: N2 (or $BIN) = the release binary of the small-instance weight with
# the coverage part whole (SMALL_WEIGHT_RADIUS_PX 16, SMALL_WEIGHT_MIN 0.25; every test of vgeo's
# cut and lod's level choice), measured as final.sh measured call 3's binary but without the
# hardware-path timings and the M comparisons (the session's device time): the four bench scenes
# in all three modes, lod and vgeo swept over 0.25-4 px, errors against brute at 4x4 spp, 8
# frames; stress N=20 (2 frames, 0.5-2 px, with its reference); the stress scaling N = 20, 50,
# 100, 200 (vgeo at 1 px, 4 frames); the close blade and the empty frame (`render --time 64`);
# the "tiny" check (stress N=20 at 384x216 and 192x108, all three modes at 1 px, against its 4x4
# reference). The archive is rewritten after each step, so a cut call still brings back what ran.
. bench/results/2026-11-26-session17/common.sh
d=/tmp/final
mkdir -p $d
o=$d/log.txt
B=${BIN:-N2}
setup $o $B
T0=$SECONDS
pack() { rm -rf $d/*/images; (cd $d && tar czf $OUT/final.tgz .); }
warm $B
timeout 300 /tmp/vgeo-$B bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --sweep 0.25,0.5,1,2,4 --quiet --out $d/scenes > $d/scenes.log 2>&1
echo "== scenes rc=$? t=$((SECONDS - T0))" >> $o; pack
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20,50,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d/scaling > $d/scaling.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o; pack
for res in "384 216" "192 108"; do
  set -- $res
  timeout 200 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --sweep 1 --quiet --out $d/tiny$2 > $d/tiny$2.log 2>&1
  echo "== tiny$2 rc=$? t=$((SECONDS - T0))" >> $o; pack
done
for s in close empty; do
  timeout 60 /tmp/vgeo-$B render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$B.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
done
pack
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --frames 2 --sweep 0.5,1,2 --quiet --out $d/stress > $d/stress.log 2>&1
echo "== stress rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack
