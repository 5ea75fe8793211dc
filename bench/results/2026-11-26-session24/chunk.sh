#!/bin/bash
# Session 24, device: the large-triangle constants after 153543a: C16 and C64 (RASTER_SW_CHUNK 16 and
# 64 instead of 32) and B128 (RASTER_SW_BIG_BOX_PIXELS 128 instead of 64) against D (153543a's
# raster_sw), all through --shader-dir on the 526eb64 binary.
# Scenes outdoor, indoor, foliage (8 frames), stress N = 20 / 100 (4 frames), vgeo at 1 px; the
# close blade; two interleaved rounds; then whether their images equal D's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/chunk.txt
setup $o M
T0=$SECONDS
warm M
for r in 1 2; do
  for v in D C16 C64 B128; do
    sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-M bench $sd --suite full --scenes outdoor,indoor,foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-M bench $sd --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-M render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
for v in C16 C64 B128; do
  echo "== images D/$v" >> $o
  for x in s t; do
    for f in /tmp/su-D-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  cmp -s /tmp/close-D.png /tmp/close-$v.png && echo "  same close" >> $o || echo "  differ close" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
