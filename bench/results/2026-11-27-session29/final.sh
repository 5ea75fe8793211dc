#!/bin/bash
# Session 29, device call 2: N (or $BIN) = the release binary of the small-instance weight
# (SMALL_WEIGHT_RADIUS_PX 16, SMALL_WEIGHT_MIN 0.25, in vgeo's table rows and lod's level choice),
# measured as sessions 19 and 25-28 measured the final code: the four bench scenes in all three
# modes, lod and vgeo swept over 0.25-4 px, errors against brute at 4x4 samples per pixel, 8 frames;
# stress N=20 (2 frames, 0.5-2 px, with its reference); the stress scaling N = 20, 50, 100, 200
# (vgeo at 1 px, 4 frames); the close blade and the empty frame (`render --time 64`); the two
# hardware paths. Then the "tiny" check: stress N=20 at 384x216 and 192x108 (the instance sizes of
# N=100 and N=200 at 1080p) in all three modes at 1 px against its 4x4 reference; and M (main
# before the weight, 01b5e9c) on foliage and stress N=100/200 in the same call. One archive.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
B=${BIN:-N}
setup $o $B M
T0=$SECONDS
warm $B
d=/tmp/final
timeout 300 /tmp/vgeo-$B bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --sweep 0.25,0.5,1,2,4 --quiet --out $d/scenes > $d-scenes.log 2>&1
echo "== scenes rc=$? t=$((SECONDS - T0))" >> $o
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --frames 2 --sweep 0.5,1,2 --quiet --out $d/stress > $d-stress.log 2>&1
echo "== stress rc=$? t=$((SECONDS - T0))" >> $o
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20,50,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d/scaling > $d-scaling.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o
python3 bench/results/2026-11-26-session23/passes.py $d/scenes/bench.json >> $o 2>&1
python3 bench/results/2026-11-26-session23/passes.py $d/scaling/bench.json >> $o 2>&1
for s in close empty; do
  timeout 60 /tmp/vgeo-$B render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$B.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
done
echo "== hardware paths (render --time 64; default split, then every cluster in hardware)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml .gpu/close.toml; do
  for p in vertex mesh; do
    timeout 60 /tmp/vgeo-$B render $s --width 1920 --height 1080 --frames 8 --hw-path $p --time 64 --out /tmp/p.png 2>&1 | grep -E "timed" | sed "s|^|  $p $s |" >> $o
  done
done
for s in assets/scenes/outdoor.toml .gpu/close.toml; do
  for p in vertex mesh; do
    timeout 60 /tmp/vgeo-$B render $s --width 1920 --height 1080 --frames 8 --hw-path $p --hw-threshold 0 --time 16 --out /tmp/p.png 2>&1 | grep -E "timed" | sed "s|^|  $p all-HW $s |" >> $o
  done
done
for res in "384 216" "192 108"; do
  set -- $res
  timeout 200 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --sweep 1 --quiet --out $d/tiny$2 > $d-tiny$2.log 2>&1
  echo "== tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
done
for b in M $B; do
  timeout 100 /tmp/vgeo-$b bench --suite full --scenes foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d/fol-$b > /dev/null 2>&1
  timeout 100 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d/big-$b > /dev/null 2>&1
  echo "== $b foliage, stress 100/200 rc=$? t=$((SECONDS - T0))" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
cp $o $d/
rm -rf $d/*/images
cd $d && tar czf $OUT/final.tgz . && rm -f $OUT/log.txt
