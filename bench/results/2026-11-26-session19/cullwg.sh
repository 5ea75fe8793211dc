#!/bin/bash
# Session 19, device: the persistent cluster_cull's workgroup count (VGEO_CULL_WORKGROUPS; default
# 256 on a GPU) against the close blade's and the empty frame's time (issue 14 acceptance 4), and
# what it does to larger scenes (outdoor, indoor, stress N=20 and N=100), binary B (main).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/cullwg.txt
setup $o B
T0=$SECONDS
warm B
for r in 1 2; do
  for wg in 32 64 128 256 512; do
    for s in close empty; do
      VGEO_CULL_WORKGROUPS=$wg timeout 60 /tmp/vgeo-B render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s.png 2>&1 | grep -E "timed" | sed "s/^/  r$r wg $wg $s /" >> $o
    done
  done
done
echo "== t=$((SECONDS - T0))" >> $o
VGEO_CULL_WORKGROUPS=256 timeout 60 /tmp/vgeo-B render .gpu/close.toml --width 1920 --height 1080 --frames 8 --stats --out /tmp/c.png 2>&1 | grep -E "cull|GPU time" | sed "s/^/  wg 256 /" >> $o
VGEO_CULL_WORKGROUPS=64 timeout 60 /tmp/vgeo-B render .gpu/close.toml --width 1920 --height 1080 --frames 8 --stats --out /tmp/c.png 2>&1 | grep -E "cull|GPU time" | sed "s/^/  wg 64 /" >> $o
for wg in 64 128 256 512; do
  if [ $((SECONDS - T0)) -gt 420 ]; then echo "== skip wg $wg (time)" >> $o; continue; fi
  d=/tmp/wg-$wg
  VGEO_CULL_WORKGROUPS=$wg timeout 90 /tmp/vgeo-B bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
  VGEO_CULL_WORKGROUPS=$wg timeout 90 /tmp/vgeo-B bench --suite full --scenes outdoor,indoor,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
  echo "== wg $wg t=$((SECONDS - T0))" >> $o
  for x in t s; do summary $d-$x/bench.json >> $o 2>&1; done
done
echo "== total $((SECONDS - T0)) s" >> $o
