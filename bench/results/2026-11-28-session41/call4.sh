#!/bin/bash
# Session 41, call 4 (H200): G = F (b8908f4) with the post phase's instance_cull dispatch capped
# at max(4096 workgroups, the main phase's) (this session's cluster_cull.comp.glsl as a shader
# folder, the new constant written out: F's binary does not define it). Call 2 found F's stress
# N=100 / N=200 +0.3 / +0.1 % against A, instance_cull (post) +0.001 / +0.007 ms: a thread per
# deferred item launches more workgroups than the instance count did where the items outnumber
# the instances. Runs A F G G F A on stress N=100, N=200; A G G A on the other scenes.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-F
mkdir -p /tmp/sd
sed 's/POST_CULL_FILL_WORKGROUPS/4096u/' shaders_glsl/cluster_cull.comp.glsl > /tmp/sd/cluster_cull.comp.glsl
grep -c 4096u /tmp/sd/cluster_cull.comp.glsl >> $o
warm A
T0=$SECONDS
run() { # NAME BENCH_ARGS...
  local n=$1; shift
  local b=${n:0:1} sd=""
  [ $b = G ] && { b=F; sd="--shader-dir /tmp/sd"; }
  timeout 100 /tmp/vgeo-$b bench --suite full $sd "$@" --modes vgeo --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
for r in Aa Fa Ga Gb Fb Ab; do
  run $r-big --scenes stress --stress-n 100,200
done
pack
for r in Ac Gc Gd Ad; do
  [ $((SECONDS - T0)) -gt 240 ] && break
  run $r-scenes --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
