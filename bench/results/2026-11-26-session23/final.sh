#!/bin/bash
# Session 23, device: the final build W (small instances cut from the table in views of at least
# WALK_WIDE_INSTANCES instances, each cluster still tested) against main N (8b14cf5): the four
# bench scenes (8 frames), stress N = 20 / 100 / 200 (4 frames), vgeo at 1 px; the close blade and
# the empty frame (`render --time 64`); two interleaved rounds, then whether the images are the
# same. Then W's image error at 1920x1080 against the 4x4-spp reference where the table is used:
# foliage (brute, vgeo 1 px, 2 frames) and stress N = 20 (1 frame).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/final.txt
setup $o N W
T0=$SECONDS
warm N
warm W
for r in 1 2; do
  for b in N W; do
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
echo "== images N/W" >> $o
for x in s t; do
  for f in /tmp/su-N-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-W-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-N.png /tmp/$s-W.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
d=$OUT/err-foliage
timeout 200 /tmp/vgeo-W bench --suite full --scenes foliage --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== error foliage W rc=$? t=$((SECONDS - T0))" >> $o
grep "^| " $d/bench.md | grep -v "^| mode\|^|---" | cut -d'|' -f2-12 >> $o
rm -rf $d/images $d/*.svg
d=$OUT/err-stress
timeout 200 /tmp/vgeo-W bench --suite full --scenes stress --stress-n 20 --frames 1 --modes brute,vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== error stress N=20 W rc=$? t=$((SECONDS - T0))" >> $o
grep "^| " $d/bench.md | grep -v "^| mode\|^|---" | cut -d'|' -f2-12 >> $o
rm -rf $d/images $d/*.svg
echo "== total $((SECONDS - T0)) s" >> $o
