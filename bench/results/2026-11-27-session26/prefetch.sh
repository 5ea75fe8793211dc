#!/bin/bash
# Session 26, device: raster_sw reading the next cluster's list entry and visible entry a step
# ahead (E1, `--shader-dir .gpu/sd/E1`, both paths) against B (the binary: small path up to 170
# vertices). Two interleaved rounds; images against B.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/prefetch.txt
setup $o B
T0=$SECONDS
warm B
for r in 1 2; do
  for v in B E1; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-B bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-B bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-B render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
for v in E1; do
  echo "== images B/$v" >> $o
  for x in s t; do
    for f in /tmp/su-B-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  cmp -s /tmp/close-B.png /tmp/close-$v.png && echo "  same close" >> $o || echo "  differ close" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz prefetch.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
