#!/bin/bash
# Session 43, call 4: is stress N=200's +0.1-0.2 % (S against A, all in `instance_cull (post)`)
# the code or the DAG? R = S's code with BuildOptions' default step ratio back at 0.5 (A's),
# its scenes built so (not landed). Stress N=100 / N=200: A S R R S A.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-S vgeo-R
T0=$SECONDS
run() { # FORM RUN KIND BENCH_ARGS...
  local f=$1 r=$2 k=$3; shift 3
  local n=$f$r-$k
  timeout 60 /tmp/vgeo-$f bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
BIG="--scenes stress --stress-n 100,200 --modes vgeo"
warm A
for fr in "A a" "S a" "R a" "R b" "S b" "A b"; do run $fr big $BIG; done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
