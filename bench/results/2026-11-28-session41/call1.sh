#!/bin/bash
# Session 41, call 1 (H200): N = this session's post-phase dispatch (instance_cull (post) a thread
# per deferred item, not per instance) against A = f0ec5ef on every bench scene, runs A N N A;
# N's errors at 1 px against the 4x4-spp reference (every scene, stress N=20 at 192x108); then,
# as time allows, session 40's next.sh streamed pair on stress N=20: N against S (N + the members' skip under
# partial residency when their creator group is resident, a shader folder) under 64 MiB.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-N
mkdir -p /tmp/sd/common
python3 - <<'P'
s = open('shaders_glsl/common/cull.glsl').read()
old = """        if (!fallback && !partial && group.members_creator != NO_GROUP_ID
            && self_error_px(inst, mesh, group.members_creator, scale, w) > view.error_px) {"""
new = """        if (!fallback && group.members_creator != NO_GROUP_ID
            && children_resident(mesh, group.members_creator)
            && self_error_px(inst, mesh, group.members_creator, scale, w) > view.error_px) {"""
assert s.count(old) == 1
open('/tmp/sd/common/cull.glsl', 'w').write(s.replace(old, new))
P
warm A
T0=$SECONDS
run() { # NAME BINARY SHADER_ARGS BENCH_ARGS...
  local n=$1 b=$2 sd=$3; shift 3
  timeout 150 /tmp/vgeo-$b bench --suite full $sd "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for r in Aa Na Nb Ab; do
  run $r-big ${r:0:1} "" --scenes stress --stress-n 100,200 --modes vgeo
  run $r-scenes ${r:0:1} "" $SC --modes vgeo
  pack
done
run eN-scenes N "" $SC --frames 2 --modes brute,vgeo
run eN-tiny108 N "" --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
pack
# The streamed pair on stress N=20 only (where S's skip applies: walked instances of a streaming
# mesh), N and S alternating.
ST="--scenes stress --stress-n 20 --geometry-budget 64 --stream-mib-per-frame 64 --modes vgeo"
for r in Na Sa Sb Nb; do
  [ $((SECONDS - T0)) -gt 500 ] && break
  sd=""; [ ${r:0:1} = S ] && sd="--shader-dir /tmp/sd"
  run ${r}streamed N "$sd" $ST
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
