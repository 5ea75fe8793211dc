#!/bin/bash
# Session 42, call 6 (the device time left: ~250 s). K = M (4164bda) with emit_tiny_cut's
# partial-residency branch in a function of its own that also marks the drawn row's pages used
# (the count-of-one and plain-loop paths no longer call mark_used): the same cut, requests and
# usage marks (tests/cull.rs), the all-resident hot path without its two mark_used branches
# (VGEO_SHADER_DIR=.gpu/sh-K1, this commit's shaders_glsl); A = f0ec5ef. Stress N=100 / N=200
# A K K A, then, while time is left, A K on stress N=20, foliage and drawcalls (the other
# scenes whose instance_cull binary K changes; outdoor / indoor lie 4-6 % under A).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M
T0=$SECONDS
run() { # NAME BENCH_ARGS... (K is M with a shader folder)
  local n=$1; shift
  local b=${n:0:1} env=()
  [ $b = K ] && { b=M; env=(VGEO_SHADER_DIR=.gpu/sh-K1); }
  env "${env[@]}" timeout 60 /tmp/vgeo-$b bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
warm A
for r in Aa Ka Kb Ab; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
done
for r in Ac Kc; do
  [ $((SECONDS - T0)) -lt 110 ] && run $r-scenes --scenes stress,foliage,drawcalls --stress-n 20 --modes vgeo
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
