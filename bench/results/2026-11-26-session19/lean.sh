#!/bin/bash
# Session 19, device: the upper bound of a lean raster_sw for clusters without large triangles.
# .gpu/lean/raster_sw.comp.glsl (through --shader-dir) is main's raster_sw without the
# workgroup's shared pass over large triangles (every triangle walked by its own invocation: the
# same pixels, slower on large ones), against main (N, be8adeb). Three interleaved rounds of
# stress N=20, 100 (4 frames), foliage, outdoor (8), and the close blade.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/lean.txt
setup $o N
T0=$SECONDS
warm N
for r in 1 2 3; do
  for v in main lean; do
    sd=""; [ $v = lean ] && sd="--shader-dir .gpu/lean"
    x=/tmp/le-$v-r$r
    timeout 90 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 $sd --quiet --out $x-t > $x-t.log 2>&1
    timeout 90 /tmp/vgeo-N bench --suite full --scenes foliage,outdoor --frames 8 --modes vgeo --sweep 1 $sd --quiet --out $x-s > $x-s.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for y in t s; do summary $x-$y/bench.json sw >> $o 2>&1; done
    timeout 60 /tmp/vgeo-N render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 $sd --out /tmp/c-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "  close images: $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/c-main.png /tmp/c-lean.png)" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
