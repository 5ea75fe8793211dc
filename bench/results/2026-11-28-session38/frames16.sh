#!/bin/bash
# Session 38, device call 1: main (H = 5ddee74: positions at the stated precision, the step ratio
# 0.35) against f0ec5ef (A, before: 0.5 and the 16-bit floor) on every bench scene at the full
# suite's own path of 16 frames (session 37's call 4 timed stress N=20 and the scenes at 4), runs
# A H H A A H; stress N=20 at 4 frames as well (call 4's setting); then H's error at 1 px against
# the 4x4-spp reference (every scene at 1080p, stress N=20 at 192x108).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/frames16.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A H; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 d=$OUT/$1$2
  timeout 100 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 100 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  timeout 60 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-n20f4 > $d-n20f4.log 2>&1
  echo "== $t$rep n20f4 rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run H a; run H b; run A b; run A c; run H c
if [ $((SECONDS - T0)) -lt 380 ]; then
  timeout 50 /tmp/vgeo-H bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eH-tiny108 > $OUT/eH-tiny108.log 2>&1
  echo "== eH tiny108 rc=$? t=$((SECONDS - T0))" >> $o
  pack
fi
if [ $((SECONDS - T0)) -lt 420 ]; then
  timeout 120 /tmp/vgeo-H bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eH-scenes > $OUT/eH-scenes.log 2>&1
  echo "== eH scenes rc=$? t=$((SECONDS - T0))" >> $o
fi
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
