#!/bin/bash
# Session 27, device: M2 = main's shaders (0f00b91); H1 = M2 whose raster_hw fragment shader
# makes no atomic (a diagnostic: what the hardware path costs without its atomics; wrong images);
# H2 = M2 whose raster_hw fragment shader loads the visibility buffer first and skips the atomic
# when the stored value is at least its own; P = M2 whose project_fixed drops its isnan/isinf
# checks for two comparisons (the same vertices rejected). All through --shader-dir on the binary
# S. Pipeline statistics, then two interleaved rounds (H1 in the first only) of the bench scenes
# (8 frames), stress N = 20 / 100 / 200 (4 frames), the close blade, meadow.toml; images against M2.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/hw.txt
setup $o S
T0=$SECONDS
VS="M2 H1 H2 P"
for v in $VS; do
  VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-S render --shader-dir .gpu/sd/$v assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v rc=$?" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "raster_sw|raster_hw" >> $o
done
warm S
for r in 1 2; do
  for v in $VS; do
    [ $r = 2 ] && [ $v = H1 ] && continue
    sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-S render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
    timeout 100 /tmp/vgeo-S render $sd .gpu/meadow.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/meadow-$v.png 2>&1 | grep -E "timed" | sed "s/^/  meadow /" >> $o
  done
done
for v in $VS; do
  [ $v = M2 ] && continue
  echo "== images M2/$v" >> $o
  for x in s t; do
    for f in /tmp/su-M2-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  for s in close meadow; do cmp -s /tmp/$s-M2.png /tmp/$s-$v.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz hw.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
