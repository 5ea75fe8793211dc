#!/bin/bash
# Session 35, device call 1: the default step ratio 0.35 on top of session 34's whole-mesh levels.
# V = 800e121 (main at the session's start); V35 = V with BuildOptions::simplify_ratio 0.35.
# Session 34 measured 0.35 before the whole-mesh levels (R against C: the smallest instances 1.03 dB
# below brute) and with the 0.3 small-instance weight (W, one run); this is 0.35 alone on V.
# 1. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), V V35 V35 V V V35.
# 2. Error against the 4x4-spp reference at 1 px, brute and vgeo: V35 on the five scenes (2 frames)
#    and stress N=20 at 384x216 and 192x108 (V's: session 34 call 4, U's cut).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/r35.txt
setup $o
for b in V V35; do
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
run V a; run V35 a; run V35 b; run V b; run V c; run V35 c
b=V35
for res in "192 108" "384 216"; do
  set -- $res
  timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$b-tiny$2 > $OUT/e$b-tiny$2.log 2>&1
  echo "== e$b tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
timeout 120 /tmp/vgeo-$b bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$b-scenes > $OUT/e$b-scenes.log 2>&1
echo "== e$b scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
