#!/bin/bash
# Session 23, device: every frame of the suite with this session's build U (small instances cut
# from the table, each cluster still tested) and U with the 64-thread raster_sw (US2, .gpu/sd/S2
# through --shader-dir), against main N (8b14cf5): the four bench scenes (8 frames), stress
# N = 20 / 100 / 200 (4 frames), vgeo at 1 px; the close blade and the empty frame
# (`render --time 64`). Two interleaved rounds; then whether US2's images equal U's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/suite.txt
setup $o N U
T0=$SECONDS
warm N
warm U
for r in 1 2; do
  for v in N U US2; do
    b=${v:0:1}; sd=""; [ $v = US2 ] && sd="--shader-dir .gpu/sd/S2"
    d=/tmp/su-$v-r$r
    timeout 120 /tmp/vgeo-$b bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$b bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render $sd .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$v.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images" >> $o
for x in s t; do
  for f in /tmp/su-U-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-US2-r1-$x/images/$n && echo "  same U/US2 $n" >> $o || echo "  DIFFER U/US2 $n" >> $o
    cmp -s $f /tmp/su-N-r1-$x/images/$n && echo "  same N/U $n" >> $o || echo "  differ N/U $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-U.png /tmp/$s-US2.png && echo "  same U/US2 $s" >> $o || echo "  DIFFER U/US2 $s" >> $o; done
echo "== total $((SECONDS - T0)) s" >> $o
