#!/bin/bash
# Session 27, device: M = main's shaders (1c37859) through --shader-dir; MB = M with
# VGEO_VISBUFFER=buffer (the visibility buffer a uint64 storage buffer with buffer atomics instead
# of the R64 image with image atomics); A = M whose raster_sw tests a triangle's pixel box before
# its area (most triangles of a far instance cover no pixel centre). All on the binary S (its
# Rust code is main's). Pipeline statistics of raster_sw, then two interleaved rounds of the bench
# scenes (8 frames), stress N = 20 / 100 / 200 (4 frames), the close blade, meadow.toml; images
# against M.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/sw.txt
setup $o S
T0=$SECONDS
VS="M MB A"
for v in $VS; do
  env=""; [ $v = MB ] && env="VGEO_VISBUFFER=buffer"
  env $env VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-S render --shader-dir .gpu/sd/${v%B} assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v rc=$?" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "raster_sw|raster_hw" >> $o
done
warm S
for r in 1 2; do
  for v in $VS; do
    sd="--shader-dir .gpu/sd/${v%B}"; env=""; [ $v = MB ] && env="VGEO_VISBUFFER=buffer"
    d=/tmp/su-$v-r$r
    env $env timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    env $env timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    env $env timeout 60 /tmp/vgeo-S render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
    env $env timeout 100 /tmp/vgeo-S render $sd .gpu/meadow.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/meadow-$v.png 2>&1 | grep -E "timed" | sed "s/^/  meadow /" >> $o
  done
done
for v in $VS; do
  [ $v = M ] && continue
  echo "== images M/$v" >> $o
  for x in s t; do
    for f in /tmp/su-M-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  for s in close meadow; do cmp -s /tmp/$s-M.png /tmp/$s-$v.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz sw.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
