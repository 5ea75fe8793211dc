#!/bin/bash
# Session 35, device call 5: the scans built at --ratio 0.35 with this session's encoding (N3 =
# 9310ff3's binary, whose code 280190b keeps) against N3 at the default 0.5: the stress and outdoor
# scenes name .vgeo files built on this host (`vgeo build --ratio 0.35`; outdoor's ground box is
# built at load). Bytes per stored triangle, times (A = default, B = 0.35; A B B A A B) and error at
# 1 px against the 4x4-spp reference (B: stress N=20 at 192x108 and 384x216, stress and outdoor).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/at35.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-N3.xz /tmp/vgeo-N3
chmod +x /tmp/vgeo-N3
S=/tmp/s35; mkdir -p $S
for m in turbineblade bunny lucy; do
  /tmp/vgeo-N3 build ../shared/assets/scanned/$m.ply --ratio 0.35 -o $S/$m.vgeo > $OUT/build-$m.log 2>&1
done
for s in stress outdoor; do
  sed -e "s#\"../../../shared/assets/scanned/\([a-z]*\).ply\"#\"$S/\1.vgeo\"#" assets/scenes/$s.toml > $S/$s.toml
done
grep -h "path =" $S/*.toml >> $o
warm N3
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local b=$1 rep=$2 dir=assets/scenes
  [ $b = B ] && dir=$S
  local d=$OUT/$b$rep
  timeout 200 /tmp/vgeo-N3 bench --suite full --scenes-dir $dir --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $b$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-N3 bench --suite full --scenes-dir $dir --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $b$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run B a; run B b; run A b; run A c; run B c
for res in "192 108" "384 216"; do
  set -- $res
  timeout 60 /tmp/vgeo-N3 bench --suite full --scenes-dir $S --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eB-tiny$2 > $OUT/eB-tiny$2.log 2>&1
  echo "== eB tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
timeout 120 /tmp/vgeo-N3 bench --suite full --scenes-dir $S --scenes stress,outdoor --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eB-scenes > $OUT/eB-scenes.log 2>&1
echo "== eB scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
