#!/bin/bash
# Session 32, device call 2: the DAG's simplification ratio (0.5, the default; 0.35; 0.25) on the
# stress and outdoor scenes, binary O = d30e715 (main). The scans are built beforehand by O
# (`vgeo build --ratio R`, files in .gpu/rx/) and named by copies of the scene files
# (.gpu/sc-R/: the same scenes, the scans' paths replaced; outdoor's box is built at load).
# 1. Times: stress N=100 and 200 along the full suite's 16-frame path, stress N=20 and outdoor
#    (4 frames), at 1 px, per ratio, twice (order 0.5 0.35 0.25 0.25 0.35 0.5).
# 2. Error against the 4x4-spp reference: outdoor (2 frames) and stress N=20 at 384x216 (the
#    instance size of N=100 at 1080p), brute and vgeo at 0.5, 1, 1.5 and 2 px, ratios 0.5 and 0.25.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/ratio.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-O.xz /tmp/vgeo-O
chmod +x /tmp/vgeo-O
warm O
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local r=$1 rep=$2 d=$OUT/r$1$2
  timeout 200 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $r$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $r$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run 0.5 a; run 0.35 a; run 0.25 a; run 0.25 b; run 0.35 b; run 0.5 b
for r in 0.5 0.25; do
  d=$OUT/e$r
  timeout 80 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes outdoor --frames 2 --modes brute,vgeo --sweep 0.5,1,1.5,2 --quiet --out $d-outdoor > $d-outdoor.log 2>&1
  echo "== e$r outdoor rc=$? t=$((SECONDS - T0))" >> $o
  timeout 80 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes stress --stress-n 20 --width 384 --height 216 --frames 2 --modes brute,vgeo --sweep 0.5,1,1.5,2 --quiet --out $d-tiny216 > $d-tiny216.log 2>&1
  echo "== e$r tiny216 rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
