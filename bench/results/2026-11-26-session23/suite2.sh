#!/bin/bash
# Session 23, device: this session's build V (small instances cut from the table, each cluster
# still tested; one thread emits at most the local walk's WALK_CLUSTERS in a view of few
# instances) against main N (8b14cf5): the four bench scenes (8 frames), stress N = 20 / 100 / 200
# (4 frames), vgeo at 1 px; the close blade and the empty frame (`render --time 64`); two
# interleaved rounds. Then the image error where the table serves nearly every instance: stress
# N = 20 at 384x216 and 768x432 (the instance sizes of N = 100 and 50 at 1920x1080), brute and
# vgeo at 0.5-2 px against the 4x4-spp reference, 2 frames, both builds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/suite2.txt
setup $o N V
T0=$SECONDS
warm N
warm V
for r in 1 2; do
  for b in N V; do
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
echo "== images N/V" >> $o
for x in s t; do
  for f in /tmp/su-N-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-V-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close empty; do cmp -s /tmp/$s-N.png /tmp/$s-V.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
for res in 384x216 768x432; do
  for b in N V; do
    d=$OUT/err-$res-$b
    timeout 120 /tmp/vgeo-$b bench --suite full --scenes-dir .gpu/po/w1 --scenes stress --stress-n 20 --width ${res%x*} --height ${res#*x} --frames 2 --modes brute,vgeo --sweep 0.5,1,2 --quiet --out $d > $d.log 2>&1
    echo "== error $res $b rc=$? t=$((SECONDS - T0))" >> $o
    grep "^| " $d/bench.md | grep -v "^| mode\|^|---" | cut -d'|' -f2-12 >> $o
    rm -rf $d
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
