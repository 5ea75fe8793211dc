#!/bin/bash
# Session 40, call 2 (H200): Z = main (9a2025b) against
# A = f0ec5ef on every bench scene at the suite's 16 frames, runs A Z Z A; then Z's error at 1 px
# against the 4x4-spp reference (every scene, and stress N=20 at 192x108).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A Z; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
for r in Aa Za Zb Ab; do
  timeout 100 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $OUT/$r-big > $OUT/$r-big.log 2>&1
  echo "== $r big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 100 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --quiet --out $OUT/$r-scenes > $OUT/$r-scenes.log 2>&1
  echo "== $r scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
timeout 100 /tmp/vgeo-Z bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eZ-scenes > $OUT/eZ-scenes.log 2>&1
echo "== eZ scenes rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 100 /tmp/vgeo-Z bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eZ-tiny108 > $OUT/eZ-tiny108.log 2>&1
echo "== eZ tiny108 rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
