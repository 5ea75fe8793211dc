#!/bin/bash
# Session 23, device: X (W plus the small SW clusters' list: clusters projecting to at most
# RASTER_SW_SMALL_PX = 7 px across fill the SW list from its end, and raster_sw draws them two to
# a workgroup, two triangles a thread, no shared pass) against W (the table, committed 979ba24)
# and main N (8b14cf5): the four bench scenes (8 frames), stress N = 20 / 100 / 200 (4 frames),
# vgeo at 1 px; the close blade and the empty frame; two interleaved rounds; then whether X's
# images equal W's, and X's error on foliage and stress N=20 against the 4x4-spp reference.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small.txt
setup $o N W X
T0=$SECONDS
warm N
warm W
for r in 1 2; do
  for b in N W X; do
    d=/tmp/su-$b-r$r
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $b t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    for s in close empty; do
      timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$b.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
    done
  done
done
echo "== images W/X" >> $o
for x in s t; do
  for f in /tmp/su-W-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-X-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-W.png /tmp/$s-X.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
d=$OUT/err-foliage
timeout 200 /tmp/vgeo-X bench --suite full --scenes foliage --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== error foliage X rc=$? t=$((SECONDS - T0))" >> $o
grep "^| " $d/bench.md | grep -v "^| mode\|^|---" | cut -d'|' -f2-12 >> $o
rm -rf $d/images $d/*.svg
d=$OUT/err-stress
timeout 200 /tmp/vgeo-X bench --suite full --scenes stress --stress-n 20 --frames 1 --modes brute,vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== error stress N=20 X rc=$? t=$((SECONDS - T0))" >> $o
grep "^| " $d/bench.md | grep -v "^| mode\|^|---" | cut -d'|' -f2-12 >> $o
rm -rf $d/images $d/*.svg
echo "== total $((SECONDS - T0)) s" >> $o
