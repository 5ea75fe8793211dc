#!/bin/bash
# Session 34, device call 6: W = V (b33599e, the code of 3dc63af for these scenes) with the default
# step ratio 0.35 and SMALL_WEIGHT_MIN 0.3 (call 2: what keeps the smallest instances within 1 dB
# of brute at 0.35), against V.
# 1. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), V W W V V W.
# 2. Error against the 4x4-spp reference at 1 px, brute and vgeo: W on the five scenes (2 frames)
#    and stress N=20 at 384x216 and 192x108 (V's: call 4).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/w.txt
setup $o
for b in V W; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm W
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
run V a; run W a; run W b; run V b; run V c; run W c
d=$OUT/eW
timeout 120 /tmp/vgeo-W bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
echo "== eW scenes rc=$? t=$((SECONDS - T0))" >> $o
pack
for res in "192 108" "384 216"; do
  set -- $res
  timeout 60 /tmp/vgeo-W bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-tiny$2 > $d-tiny$2.log 2>&1
  echo "== eW tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
