#!/bin/bash
# Session 27, device: instance_cull's code. I0 = main's shaders (f1de57c); I1 = one call site per
# kind of work (the post phase's three loops one index range, the main phase's instance path
# shared with the post phase's, the local walk's first node taken from its stack); I2 = I1 with
# the local walk's stack in shared memory instead of local memory. All through `--shader-dir` on
# the binary S (f9896af; its Rust code is f1de57c's). The pipelines' statistics (registers,
# local memory, binary size) of each, then two interleaved rounds of the bench scenes (8 frames),
# stress N = 20 / 100 / 200 (4 frames), the close blade, meadow.toml; images against I0.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/cull.txt
setup $o S
T0=$SECONDS
VS="I0 I1 I2"
for v in $VS; do
  VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-S render --shader-dir .gpu/sd/$v assets/scenes/foliage.toml --width 1920 --height 1080 --frames 1 --out /tmp/st-$v.png > /tmp/st-$v.log 2>&1
  echo "== stats $v rc=$?" >> $o
  grep "pipeline statistics" /tmp/st-$v.log | grep -E "instance_cull|cluster_cull" >> $o
done
warm S
for r in 1 2; do
  for v in $VS; do
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
  [ $v = I0 ] && continue
  echo "== images I0/$v" >> $o
  for x in s t; do
    for f in /tmp/su-I0-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  for s in close meadow; do cmp -s /tmp/$s-I0.png /tmp/$s-$v.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz cull.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
