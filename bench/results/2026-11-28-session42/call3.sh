#!/bin/bash
# Session 42, call 3. P = M (main 4164bda, .gpu/vgeo-M.xz) with cull.glsl's mesh_partial()
# returning false (VGEO_SHADER_DIR=.gpu/sh-P: 4164bda's shaders_glsl so changed), i.e. the cull
# compiled without its partial-residency code, what a pipeline variant for scenes whose meshes
# are all resident would run; A = f0ec5ef. Does the partial-residency code's presence cost the
# all-resident frame (stress N=100 +0.2..+0.4 % against A)? Stress N=100 / N=200 A P M P A M,
# then A P P A on every scene, then P's errors at 1 px (issue 13's acceptance 5).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M
warm A
T0=$SECONDS
run() { # NAME BENCH_ARGS... (binary: the name's first letter; P is M with a shader folder)
  local n=$1; shift
  local b=${n:0:1}; [ "$b" = e ] && b=${n:1:1}
  local env=()
  case $b in P) env=(VGEO_SHADER_DIR=.gpu/sh-P); b=M;; esac
  env "${env[@]}" timeout 150 /tmp/vgeo-$b bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
for r in Aa Pa Ma Pb Ab Mb; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
done
pack
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for r in Ac Pc Pd Ad; do
  run $r-scenes $SC --modes vgeo
  pack
done
[ $((SECONDS - T0)) -lt 330 ] && run eP-scenes $SC --frames 2 --modes brute,vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
