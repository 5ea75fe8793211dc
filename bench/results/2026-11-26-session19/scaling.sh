#!/bin/bash
# Session 19, device: binary N = main at be8adeb (shade four pixels a thread).
# 1. Issue 14 acceptance 5: vgeo's frame time against instance count (stress N = 20..100, 8 K to
#    1 M instances) and against scene triangles, 1 px, 4 frames each: bench.md and the plots
#    stress_scaling.svg (against scene triangles) and stress_instances.svg (against instances).
# 2. Issue 14 acceptance 3 (the default split no slower than software only on every scene): vgeo
#    at 1 px with --hw-threshold 64 (the default), 128 and 100000 (software only but the near
#    plane's clusters), two interleaved rounds, on the bench scenes and stress N=20.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o N
T0=$SECONDS
warm N
d=/tmp/scaling
timeout 240 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20,30,40,50,60,70,80,90,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o
mkdir -p $OUT/scaling
cp $d/bench.md $d/*.svg $OUT/scaling/ 2>/dev/null
summary $d/bench.json tris >> $o 2>&1
for r in 1 2; do
  for thr in 64 128 100000; do
    if [ $((SECONDS - T0)) -gt 480 ]; then echo "== skip r$r $thr (time)" >> $o; continue; fi
    x=/tmp/thr-$thr-r$r
    timeout 60 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --frames 4 --modes vgeo --sweep 1 --hw-threshold $thr --quiet --out $x-t > $x-t.log 2>&1
    timeout 120 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --hw-threshold $thr --quiet --out $x-s > $x-s.log 2>&1
    echo "== r$r --hw-threshold $thr t=$((SECONDS - T0))" >> $o
    for y in t s; do summary $x-$y/bench.json sw hw >> $o 2>&1; done
    for y in t s; do grep -E "^\| vgeo" $x-$y/bench.md | head -5 >> $o; done
    timeout 60 /tmp/vgeo-N render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --hw-threshold $thr --out /tmp/c.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
