#!/bin/bash
# Session 43, call 2: S (the culls' pipelines without the partial-residency code for frames in
# which no mesh is partial: SPEC_CULL_STREAMING) against A (f0ec5ef): stress N=100 / N=200
# A S S A twice, every scene A S S A, S's errors at 1 px, S streamed under 64 MiB (each camera
# settled, then timed against the same cameras all resident), the cull pipelines' statistics.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-S
T0=$SECONDS
run() { # FORM RUN KIND BENCH_ARGS...
  local f=$1 r=$2 k=$3; shift 3
  local n=$f$r-$k; [ $r = e ] && n=e$f-$k
  timeout 100 /tmp/vgeo-$f bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
for b in A S; do
  VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-$b render assets/scenes/outdoor.toml --width 64 --height 64 -o /tmp/x.png 2>&1 | grep "pipeline statistics" > $OUT/stats-$b.txt
done
BIG="--scenes stress --stress-n 100,200 --modes vgeo"
warm A
for fr in "A a" "S a" "S b" "A b" "A c" "S c" "S d" "A d"; do run $fr big $BIG; done
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for fr in "A c" "S c" "S d" "A d"; do run $fr scenes $SC --modes vgeo; done
[ $((SECONDS - T0)) -lt 420 ] && run S e scenes $SC --frames 2 --modes brute,vgeo
[ $((SECONDS - T0)) -lt 470 ] && run S e tiny108 --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
[ $((SECONDS - T0)) -lt 500 ] && run S s streamed $SC --geometry-budget 64 --stream-mib-per-frame 64 --modes vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
