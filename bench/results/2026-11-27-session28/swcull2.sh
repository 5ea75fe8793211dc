#!/bin/bash
# Session 28, device, call 6: S2 = S of call 5 with the list flags computed where the cull holds
# the instance and its mesh (a bit test for a mesh that is no closed solid). L = the release binary
# of a374f70 (hardware path and lod only). raster_sw's pipeline statistics; two interleaved rounds
# of the bench scenes (8 frames) and stress N = 20 / 100 / 200 (4 frames), vgeo at 1 px; which
# images differ (the bench images are listed too, to see why call 5 found none). Then final.sh
# with S2 (errors: the README tables if S2 is kept). Outputs: cmp.txt, final.tgz.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/cmp.txt
setup $o L S2
T0=$SECONDS
for v in L S2; do
  VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-$v render assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "raster_sw" >> $o
done
warm S2
for r in 1 2; do
  for v in L S2; do
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-$v render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "== images L/S2" >> $o
ls /tmp/su-L-r1-s /tmp/su-L-r1-s/images 2>&1 | head -20 >> $o
for x in s t; do
  for f in /tmp/su-L-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-S2-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
cmp -s /tmp/close-L.png /tmp/close-S2.png && echo "  same close" >> $o || echo "  differ close" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
BIN=S2 bash bench/results/2026-11-27-session28/final.sh
