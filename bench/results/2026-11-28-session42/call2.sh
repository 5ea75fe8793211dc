#!/bin/bash
# Session 42, call 2. V = M (main 4164bda, .gpu/vgeo-M.xz) with emit_tiny_cut testing row 0
# first (VGEO_SHADER_DIR=.gpu/sh-V, this commit's shaders_glsl); C = M with its own shaders
# compiled at start-up (.gpu/sh-C, 4164bda's shaders_glsl: does the runtime compile match the
# build's?); A = f0ec5ef. Stress N=100 / N=200 A V M C V A M C, then A V V A on every scene,
# then V's errors at 1 px (issue 13's acceptance 5).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M
warm A
T0=$SECONDS
run() { # NAME BENCH_ARGS... (binary: the name's first letter; V and C are M with a shader folder)
  local n=$1; shift
  local b=${n:0:1}; [ "$b" = e ] && b=${n:1:1}
  local env=()
  case $b in V) env=(VGEO_SHADER_DIR=.gpu/sh-V); b=M;; C) env=(VGEO_SHADER_DIR=.gpu/sh-C); b=M;; esac
  env "${env[@]}" timeout 150 /tmp/vgeo-$b bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
for r in Aa Va Ma Ca Vb Ab Mb Cb; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
done
pack
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for r in Ac Vc Vd Ad; do
  run $r-scenes $SC --modes vgeo
  pack
done
[ $((SECONDS - T0)) -lt 400 ] && run eV-scenes $SC --frames 2 --modes brute,vgeo
pack
[ $((SECONDS - T0)) -lt 470 ] && run eV-tiny108 --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
