#!/bin/bash
# Session 25, device: prefiltered normals (the builder's kept vertices take meshoptimizer's solved
# normal, `VGEO_PREFILTER=1`) and the normal weight (`VGEO_NW`), both read by an experimental build
# P from the environment. Per configuration: stress N = 20 at 384x216 (instances of N = 100's size
# at 1080p) with its 4x4-spp reference; the four scenes' error at 1 px (2 frames); stress N = 20 at
# 1080p with its reference; stress N = 100 and 200 timed (vgeo, 4 frames).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/pf.txt
setup $o P
T0=$SECONDS
run() {
  local name=$1; shift
  local d=$OUT/$name
  timeout 200 env "$@" /tmp/vgeo-P bench --suite full --scenes stress --stress-n 20 --width 384 --height 216 --frames 2 --modes brute,vgeo --sweep 1,2 --quiet --out $d-tiny > $d-tiny.log 2>&1
  echo "== $name tiny rc=$? t=$((SECONDS - T0))" >> $o
  case $name in N025|P025T) return ;; esac
  timeout 200 env "$@" /tmp/vgeo-P bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $name scenes rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 env "$@" /tmp/vgeo-P bench --suite full --scenes stress --stress-n 20 --frames 1 --modes brute,vgeo --sweep 1 --quiet --out $d-s20 > $d-s20.log 2>&1
  echo "== $name s20 rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 env "$@" /tmp/vgeo-P bench --suite full --scenes stress --stress-n 100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $name big rc=$? t=$((SECONDS - T0))" >> $o
}
# Call 1 ran B, P025 (its tiny output lost), P05, N025 and P1 but brought back only 8 files;
# call 3 runs the rest and packs everything into one archive.
for c in ${CONFIGS:-B P025 P05 N025 P1}; do
  case $c in
    B) run B VGEO_NONE=1 ;;
    P1) run P1 VGEO_PREFILTER=1 ;;
    P05) run P05 VGEO_PREFILTER=1 VGEO_NW=0.5 ;;
    P025) run P025 VGEO_PREFILTER=1 VGEO_NW=0.25 ;;
    N025) run N025 VGEO_NW=0.25 ;;
    P025T) run P025T VGEO_PREFILTER=1 VGEO_NW=0.25 ;;
    P01) run P01 VGEO_PREFILTER=1 VGEO_NW=0.1 ;;
  esac
done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/pf.tgz --exclude='*.png' --exclude='*.svg' --exclude=images . && rm -rf $OUT/* && mv /tmp/pf.tgz $OUT/
