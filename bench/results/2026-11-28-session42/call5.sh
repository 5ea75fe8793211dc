#!/bin/bash
# Session 42, call 5: the cull pipelines' statistics (VGEO_PIPELINE_STATS=1: registers, binary
# size, stack) of A = f0ec5ef, M = 4164bda and P = M with mesh_partial() false (.gpu/sh-P),
# whose stress N=100 / N=200 frame times calls 1-4 compared.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M
for b in A M P; do
  bin=$b; env=()
  [ $b = P ] && { bin=M; env=(VGEO_SHADER_DIR=.gpu/sh-P); }
  env "${env[@]}" VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-$bin render assets/scenes/outdoor.toml --width 64 --height 64 -o /tmp/x.png 2>&1 | grep "pipeline statistics" > $OUT/stats-$b.txt
  echo "== $b rc=$?" >> $o
done
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
