#!/bin/bash
# Session 26, device: raster_sw's small path for clusters of up to 170 vertices (B, the binary
# built from this change: both paths' shared data in one array, three words a vertex) against
# main's shaders (F, `--shader-dir .gpu/sd/F`: raster_sw and cull.glsl of 6ebc4e0, clusters of at
# most 127 vertices) and A (main's layout with shared arrays twice as large, 255 vertices).
# Scenes outdoor, indoor, foliage, drawcalls (8 frames), stress N = 20 / 100 / 200 (4 frames), vgeo
# at 1 px; the close blade; two interleaved rounds; then whether the images equal F's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small170.txt
setup $o B
T0=$SECONDS
warm B
for r in 1 2; do
  for v in F A B; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-B bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-B bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-B render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
for v in A B; do
  echo "== images F/$v" >> $o
  for x in s t; do
    for f in /tmp/su-F-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  cmp -s /tmp/close-F.png /tmp/close-$v.png && echo "  same close" >> $o || echo "  differ close" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz small170.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
