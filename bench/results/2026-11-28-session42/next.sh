#!/bin/bash
# Prepared in session 42 for the next session's first device call (not run). First, here:
# bash bench/results/2026-11-28-session42/prep-next.sh (the shader folders, in .gpu/), and
# check .gpu/ holds vgeo-A.xz (f0ec5ef), vgeo-M.xz (4164bda), vgeo-N.xz (43506df: main at
# session 42's end, cluster_cull's tail reading the deferred counts unconditionally).
# 1. Is A's stress N=100 figure one draw of a spread that M's +0.2..+0.4 % lies in? A's code
#    compiled in equivalent forms (the same cut and image on every all-resident scene): AC = A's
#    own shaders compiled at start-up (control), AV = A with V (row 0 first), AP = A with P
#    (mesh_partial() false); M, N, and MP = M with P. Stress N=100 / N=200, each form twice,
#    interleaved.
# 2. N against A on every scene (A N N A) and N's errors at 1 px (issue 13's acceptance 5).
# ~520 s.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M vgeo-N
T0=$SECONDS
run() { # FORM RUN KIND BENCH_ARGS... (a form of two letters: binary, then its .gpu/sh<B>-<X>)
  local f=$1 r=$2 k=$3 b=${1:0:1} env=(); shift 3
  [ ${#f} = 2 ] && env=(VGEO_SHADER_DIR=.gpu/sh${b}-${f:1:1})
  local n=$f$r-$k; [ $r = e ] && n=e$f-$k  # error runs: e<FORM>-*, as table.py reads them
  env "${env[@]}" timeout 100 /tmp/vgeo-$b bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
BIG="--scenes stress --stress-n 100,200 --modes vgeo"
warm A
for f in A M N AC AV AP MP; do run $f a big $BIG; done
for f in MP AP AV AC N M A; do run $f b big $BIG; done
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for fr in "A c" "N c" "N d" "A d"; do run $fr scenes $SC --modes vgeo; done
[ $((SECONDS - T0)) -lt 470 ] && run N e scenes $SC --frames 2 --modes brute,vgeo
[ $((SECONDS - T0)) -lt 530 ] && run N e tiny108 --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
# Then: python3 bench/results/2026-11-28-session38/table.py CALL A M N AC AV AP MP
