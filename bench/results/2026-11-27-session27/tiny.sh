#!/bin/bash
# Session 27, device: M4 = main's shaders (03340c9); T1 = M4 whose instance_cull skips the
# instance's HZB test for meshes that take their table at any size (grass clumps: their table's
# clusters are each tested); D1 = M4 whose cluster_vertex_clip decodes the position alone (no
# normal fields); TD = T1 + D1. All through --shader-dir on the binary F (03340c9). Pipeline
# statistics (instance_cull, raster_sw), then two interleaved rounds of the bench scenes
# (8 frames) and stress N = 20 / 100 / 200 (4 frames); images against M4.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tiny.txt
setup $o F
T0=$SECONDS
VS="M4 T1 D1 TD"
for v in $VS; do
  VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-F render --shader-dir .gpu/sd/$v assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v rc=$?" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "instance_cull|raster_sw" >> $o
done
warm F
for r in 1 2; do
  for v in $VS; do
    sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
  done
done
for v in $VS; do
  [ $v = M4 ] && continue
  echo "== images M4/$v" >> $o
  for x in s t; do
    for f in /tmp/su-M4-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz tiny.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
