#!/bin/bash
# Session 31, device call 1: H = the session's starting binary (dc2138c); shader-directory variants:
# C8 / C4 = a frame without a previous HZB (the first of a path, a camera cut) draws in its main
#   phase only instances whose radius is at least 8 / 4 px and defers the rest to the post phase,
#   which tests them against the HZB of what the main phase drew;
# S1 = a small instance whose table cut is one cluster emits it without testing that cluster
#   again (the instance's own test used the mesh's box); C8S1 = both.
# Stress N=100 and 200 along the full suite's 16-frame path (its default) and foliage, outdoor,
# indoor, drawcalls, stress N=20 (4 frames), vgeo at 1 px.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/probe.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-H.xz /tmp/vgeo-H
chmod +x /tmp/vgeo-H
warm H
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 scenes=$2 rep=$3
  local d=$OUT/$name$rep
  local sd=""
  [ "$name" != H ] && sd="--shader-dir .gpu/sd/$name"
  timeout 200 /tmp/vgeo-H bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name$rep big rc=$? t=$((SECONDS - T0))" >> $o
  if [ $scenes = 1 ]; then
    timeout 200 /tmp/vgeo-H bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
    echo "== $name$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  fi
  pack
}
run H 1 a; run C8 1 a; run S1 1 a; run C8S1 1 a; run C4 0 a; run H 1 b; run C8S1 1 b; run S1 0 b; run C8 0 b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
