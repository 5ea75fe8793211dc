#!/bin/bash
# Session 23, device: Z (Y, whose post phase rebuilt no HZB when it drew only small clusters:
# depth_pyramid's dispatch now counts them) against W (979ba24): the four bench scenes (8 frames),
# stress N = 20 / 100 / 200 (4 frames), vgeo at 1 px; the close blade and the empty frame; two
# interleaved rounds; then whether Z's images equal W's.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/small3.txt
setup $o W Z
T0=$SECONDS
warm Z
warm W
for r in 1 2; do
  for b in W Z; do
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
echo "== images W/Z" >> $o
for x in s t; do
  for f in /tmp/su-W-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-Z-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-W.png /tmp/$s-Z.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
echo "== total $((SECONDS - T0)) s" >> $o
