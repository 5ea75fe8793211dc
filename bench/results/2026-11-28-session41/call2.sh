#!/bin/bash
# Session 41, call 2 (H200): F = main at b8908f4 (the post phase's dispatch by deferred items,
# its counts read with the tail's other counters; process_node's members' skip under partial
# residency) against A = f0ec5ef on every bench scene, runs A F F A; F's errors at 1 px against
# the 4x4-spp reference (every scene, stress N=20 at 192x108); then F streamed under 64 MiB on
# every scene (each camera settled, then timed against the same cameras all resident).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-F
warm A
T0=$SECONDS
run() { # NAME BINARY BENCH_ARGS...
  local n=$1 b=$2; shift 2
  timeout 150 /tmp/vgeo-$b bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for r in Aa Fa Fb Ab; do
  run $r-big ${r:0:1} --scenes stress --stress-n 100,200 --modes vgeo
  run $r-scenes ${r:0:1} $SC --modes vgeo
  pack
done
run eF-scenes F $SC --frames 2 --modes brute,vgeo
run eF-tiny108 F --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
pack
[ $((SECONDS - T0)) -lt 430 ] && run Fstreamed F $SC --geometry-budget 64 --stream-mib-per-frame 64 --modes vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
