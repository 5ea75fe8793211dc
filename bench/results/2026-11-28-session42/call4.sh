#!/bin/bash
# Session 42, call 4. H = main 4164bda with the post phase's instance_cull on the instance grid
# (direct dispatch, a thread per instance, as A) in views of 65536 instances or more
# (POST_GRID_INSTANCES), indirect below (release, stripped, .gpu/vgeo-H.xz); M = 4164bda;
# A = f0ec5ef. Calls 1-3 found stress N=200's post-phase instance_cull +0.005 ms against A with
# M and P alike: is it the indirect dispatch? Stress N=100 / N=200 A H M H A M (the other scenes
# have fewer than 65536 instances: H records their frames as M does).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-M vgeo-H
warm A
T0=$SECONDS
run() { # NAME BENCH_ARGS...
  local n=$1; shift
  timeout 100 /tmp/vgeo-${n:0:1} bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
for r in Aa Ha Ma Hb Ab Mb; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
