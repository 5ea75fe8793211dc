#!/bin/bash
# Prepared in session 41 for the next session's first device call (not run): M = main (the
# post phase's dispatch args as three words, CullCounters 448 bytes, release, stripped,
# .gpu/vgeo-M.xz) against A = f0ec5ef (.gpu/vgeo-A.xz) and F = b8908f4 (452 bytes,
# .gpu/vgeo-F.xz): is stress N=100's +0.3-0.4 % (N=200 +0.1 %) against A the counters' pad word
# moving the frame buffers after them? Runs A F M M F A on stress N=100 / N=200, then A M M A on
# every other scene (issue 13's acceptance 5: frame times no worse than A's), then M's errors.
# M: main at session 41's end (its cluster_cull tail also reads the deferred counts
# only in the main phase).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-A vgeo-F vgeo-M
# Where the frame's buffers lie on this device (the alignment it asks for; M only: A and F
# predate VGEO_LOG_ALLOCATIONS).
VGEO_LOG_ALLOCATIONS=1 timeout 60 /tmp/vgeo-M render assets/scenes/outdoor.toml --width 1920 --height 1080 -o /tmp/a.png 2>&1 | grep allocation > $OUT/alloc-M.txt
warm A
T0=$SECONDS
run() { # NAME BENCH_ARGS...
  local n=$1; shift
  timeout 100 /tmp/vgeo-${n:0:1} bench --suite full "$@" --sweep 1 --quiet --out $OUT/$n > $OUT/$n.log 2>&1
  echo "== $n rc=$? t=$((SECONDS - T0))" >> $o
}
for r in Aa Fa Ma Mb Fb Ab; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
done
# L = M with every buffer on a 256-byte boundary (VGEO_BUFFER_ALIGN, no rebuild; a copy of M
# under its own letter for table.py): does the layout move these frames at all?
cp /tmp/vgeo-M /tmp/vgeo-L
export VGEO_BUFFER_ALIGN=256
for r in La Lb; do
  run $r-big --scenes stress --stress-n 100,200 --modes vgeo
done
unset VGEO_BUFFER_ALIGN
pack
SC="--scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20"
for r in Ac Mc Md Ad; do
  run $r-scenes $SC --modes vgeo
  pack
done
[ $((SECONDS - T0)) -lt 420 ] && run eM-scenes $SC --frames 2 --modes brute,vgeo
[ $((SECONDS - T0)) -lt 480 ] && run eM-tiny108 --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
