#!/bin/bash
# Prepared in session 42 for the next session's first device call (not run). First, here:
# bash bench/results/2026-11-28-session42/prep-next.sh (the shader folders, in .gpu/).
# Question: is A's stress N=100 figure one draw of a spread that M's +0.2..+0.4 % lies in? A's
# code compiled in equivalent forms (the same cut and image on every all-resident scene): AC =
# A's own shaders compiled at start-up (control), AV = A with V (row 0 first), AP = A with P
# (mesh_partial() false); M = 4164bda, MP = M with P. Stress N=100 / N=200, each form twice,
# interleaved: A M AC AV AP MP, then the reverse. ~300 s.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M
T0=$SECONDS
run() { # FORM RUN
  local f=$1 r=$2 b=${1:0:1} env=()
  [ ${#f} = 2 ] && env=(VGEO_SHADER_DIR=.gpu/sh${b}-${f:1:1})
  env "${env[@]}" timeout 80 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $OUT/$f$r-big > $OUT/$f$r-big.log 2>&1
  echo "== $f$r-big rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
warm A
for f in A M AC AV AP MP; do run $f a; done
for f in MP AP AV AC M A; do run $f b; done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
# Then: python3 bench/results/2026-11-28-session38/table.py CALL A M AC AV AP MP
