#!/bin/bash
# Prepared in session 38 for the next session's first device call (not run here): the committed
# shared runs (V = main at the session's last commit: the `shared` variant between 4,096 and 65,535 instances,
# main's code elsewhere) against H = 5ddee74 and A = f0ec5ef; every bench scene at the full
# suite's path of 16 frames, stress N=20 at 4 frames as well; runs A H V V H A; then V's
# error at 1 px against the 4x4-spp reference.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing-v.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A H V; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
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
run A a; run H a; run V a; run V b; run H b; run A b
if [ $((SECONDS - T0)) -lt 380 ]; then
  timeout 40 /tmp/vgeo-V bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eV-tiny108 > $OUT/eV-tiny108.log 2>&1
  echo "== eV tiny108 rc=$? t=$((SECONDS - T0))" >> $o
  pack
fi
if [ $((SECONDS - T0)) -lt 420 ]; then
  timeout 90 /tmp/vgeo-V bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eV-scenes > $OUT/eV-scenes.log 2>&1
  echo "== eV scenes rc=$? t=$((SECONDS - T0))" >> $o
fi
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
