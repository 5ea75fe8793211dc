#!/bin/bash
# Session 27, device: F = the release binary of 03340c9 (a vertex's transform by explicit fused
# multiply-adds), against M3 = the same binary with `--shader-dir .gpu/sd/M3` (fc5abdc's shaders:
# separate multiplies and adds). Pipeline statistics of raster_sw; two interleaved rounds of the
# bench scenes (8 frames) and stress N = 20 / 100 / 200 (4 frames); which images differ. Then F as
# sessions 19, 25 and 26 measured the final code: the four bench scenes in all three modes, lod
# and vgeo swept over 0.25-4 px, errors against brute at 4x4 samples per pixel, 8 frames; stress
# N=20 (2 frames, 0.5-2 px, with its reference); the stress scaling N = 20, 50, 100, 200 (vgeo at
# 1 px, 4 frames); the close blade and the empty frame (`render --time 64`). One archive.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o F
T0=$SECONDS
for v in M3 F; do
  sd=""; [ $v = M3 ] && sd="--shader-dir .gpu/sd/M3"
  VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-F render $sd assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "raster_sw|raster_hw / VS" >> $o
done
warm F
for r in 1 2; do
  for v in M3 F; do
    sd=""; [ $v = M3 ] && sd="--shader-dir .gpu/sd/M3"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
  done
done
echo "== images M3/F" >> $o
for x in s t; do
  for f in /tmp/su-M3-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-F-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
d=/tmp/final
timeout 300 /tmp/vgeo-F bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --sweep 0.25,0.5,1,2,4 --quiet --out $d/scenes > $d-scenes.log 2>&1
echo "== scenes rc=$? t=$((SECONDS - T0))" >> $o
timeout 150 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20 --frames 2 --sweep 0.5,1,2 --quiet --out $d/stress > $d-stress.log 2>&1
echo "== stress rc=$? t=$((SECONDS - T0))" >> $o
timeout 150 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20,50,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d/scaling > $d-scaling.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o
python3 bench/results/2026-11-26-session23/passes.py $d/scenes/bench.json >> $o 2>&1
python3 bench/results/2026-11-26-session23/passes.py $d/scaling/bench.json >> $o 2>&1
for s in close empty; do
  timeout 60 /tmp/vgeo-F render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-F.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
cp $o $d/
rm -rf $d/*/images
cd $d && tar czf $OUT/final.tgz . && rm -f $OUT/log.txt
