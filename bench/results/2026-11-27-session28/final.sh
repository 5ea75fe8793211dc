#!/bin/bash
# Session 28, device: B (or $BIN) = the release binary of 44779a4 (call 3; call 4 ran L, see
# lodcull.sh) (the hardware path without a closed
# solid's faces turned away from outside), as sessions 19 and 25-27 measured the final code: the four
# bench scenes in all three modes, lod and vgeo swept over 0.25-4 px, errors against brute at 4x4
# samples per pixel, 8 frames; stress N=20 (2 frames, 0.5-2 px, with its reference); the stress
# scaling N = 20, 50, 100, 200 (vgeo at 1 px, 4 frames); the close blade and the empty frame
# (`render --time 64`); the two hardware paths (vertex pulling, mesh shaders) timed with the
# default split and every cluster in hardware. One archive.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
B=${BIN:-B}
setup $o $B
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
echo "== total $((SECONDS - T0)) s" >> $o
cp $o $d/
rm -rf $d/*/images
cd $d && tar czf $OUT/final.tgz . && rm -f $OUT/log.txt
