#!/bin/bash
# Session 34, device call 5: V = U (call 4) with the narrow walk bound (views of fewer than
# WALK_WIDE_INSTANCES instances) counting every cluster again, as C's: U's bound let outdoor's and
# drawcalls' instances walk longer in instance_cull (+8.8 % / +2.0 %). The cut is U's (the bound
# only decides where a walk runs), so its images and errors are call 4's.
# Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), C V V C C V.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/v.txt
setup $o
for b in C V; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm V
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local b=$1 rep=$2
  local d=$OUT/$b$rep
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $b$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $b$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run C a; run V a; run V b; run C b; run C c; run V c
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
