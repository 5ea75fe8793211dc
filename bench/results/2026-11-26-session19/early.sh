#!/bin/bash
# Session 19, device: a plain load before each visibility-buffer atomicMax (skip the atomic when
# the pixel already holds a nearer or equal value: values only grow, so a stale load is a safe
# lower bound), through --shader-dir .gpu/early (common/visbuffer.glsl), against main (N, be8adeb).
# Two interleaved rounds: stress N=20, 100 (4 frames), the four scenes (8), the close blade; then
# the lit images of both.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/early.txt
setup $o N
T0=$SECONDS
warm N
for r in 1 2; do
  for v in main early; do
    sd=""; [ $v = early ] && sd="--shader-dir .gpu/early"
    x=/tmp/ea-$v-r$r
    timeout 90 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 $sd --quiet --out $x-t > $x-t.log 2>&1
    timeout 120 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 $sd --quiet --out $x-s > $x-s.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for y in t s; do summary $x-$y/bench.json sw hw >> $o 2>&1; done
    timeout 60 /tmp/vgeo-N render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 $sd --out /tmp/c.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "== images (lit, 1920x1080, 1 px): early against main, t=$((SECONDS - T0))" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  timeout 60 /tmp/vgeo-N render $s --width 1920 --height 1080 --out /tmp/i-$n-main.png > /dev/null 2>&1
  timeout 60 /tmp/vgeo-N render $s --width 1920 --height 1080 --shader-dir .gpu/early --out /tmp/i-$n-early.png > /dev/null 2>&1
  echo "  $n: $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/i-$n-main.png /tmp/i-$n-early.png 2>&1)" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
