#!/bin/bash
# Session 25, device: S12 and S20 (SW clusters up to 12 or 20 px across, instead of RASTER_SW_SMALL_PX = 7,
# to the small end of the SW list: two to a raster_sw workgroup) against F (main at fc3f919).
# Scenes outdoor, indoor, foliage, drawcalls (8 frames), stress N = 20 / 100 / 200 (4 frames), vgeo at 1 px; the
# close blade; two interleaved rounds; then whether their images equal M's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small.txt
setup $o F
T0=$SECONDS
warm F
for r in 1 2; do
  for v in F S12 S20; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-F render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
for v in S12 S20; do
  echo "== images F/$v" >> $o
  for x in s t; do
    for f in /tmp/su-F-r1-$x/images/*.png; do
      n=$(basename $f); cmp -s $f /tmp/su-$v-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
    done
  done
  cmp -s /tmp/close-F.png /tmp/close-$v.png && echo "  same close" >> $o || echo "  differ close" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz small.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
