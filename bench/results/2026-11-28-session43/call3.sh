#!/bin/bash
# Session 43, call 3: S streamed under 64 MiB (each camera settled, then timed against the same
# cameras all resident: S runs the culls' resident pipelines only there); stress N=100 / N=200
# A S T T S A, T = S with the post phase's instance_cull dispatched over at least the view's
# instances (as A did) rather than exactly its deferred items (a test of where S's +0.005 ms in
# N=200's `instance_cull (post)` comes from; not landed).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-S vgeo-T
T0=$SECONDS
run() { # FORM RUN KIND BENCH_ARGS...
  local f=$1 r=$2 k=$3 t=$4; shift 4
  local n=$f$r-$k
  timeout $t /tmp/vgeo-$f bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
BIG="--scenes stress --stress-n 100,200 --modes vgeo"
warm A
for fr in "A a" "S a" "T a" "T b" "S b" "A b"; do run $fr big 60 $BIG; done
run S s streamed 170 --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --geometry-budget 64 --stream-mib-per-frame 64 --modes vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
