#!/bin/bash
# Session 36, device call 4: a build whose default step ratio is 0.35 (D: d3a42c0 with
# BuildOptions::default().simplify_ratio and `vgeo build --ratio` at 0.35, the root chain still
# 0.5's) against 87a0762 (A, the default 0.5) on every bench scene with the repository's scene
# files: run times (A D D A A D), bytes per stored triangle, and D's error at 1 px against the
# 4x4-spp reference on indoor, foliage and drawcalls (call 3 has stress and outdoor at 0.35).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/default35.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base D; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
cp /tmp/vgeo-base /tmp/vgeo-A
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
timeout 60 /tmp/vgeo-D bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 d=$OUT/$1$2
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run D a; run D b; run A b; run A c; run D c
timeout 150 /tmp/vgeo-D bench --suite full --scenes indoor,foliage,drawcalls --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eD-scenes > $OUT/eD-scenes.log 2>&1
echo "== eD scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
