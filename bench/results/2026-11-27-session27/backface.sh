#!/bin/bash
# Session 27, device: a diagnostic of backface culling. P = main's shaders with project_fixed's
# two comparisons (call 3's P); PC = P whose raster_sw drops every triangle facing away (snapped
# area > 0 before the swap), on every mesh: right only for closed meshes seen from outside (the
# stress blade), wrong for open ones (foliage's blades). Both through --shader-dir on the binary S.
# Two interleaved rounds of the bench scenes (8 frames) and stress N = 20 / 100 / 200 (4 frames);
# images against P.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/backface.txt
setup $o S
T0=$SECONDS
VS="P PC"
warm S
for r in 1 2; do
  for v in $VS; do
    sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-S bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
  done
done
for v in $VS; do
  [ $v = P ] && continue
  echo "== images P/$v" >> $o
  for x in s t; do
    for f in /tmp/su-P-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz backface.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
