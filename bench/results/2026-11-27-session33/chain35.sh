#!/bin/bash
# Session 33, device call 7: with C's root chain (call 6), (1) the scans at --ratio 0.35 against the
# default 0.5 (each built here by C, named by copies of the stress and outdoor scene files; outdoor's
# box built at load): stress N=100 / 200 (16-frame path), stress N=20 and outdoor (4 frames), order
# 0.5 0.35 0.35 0.5; error of stress N=20 at 384x216 and 192x108 at 1 px at 0.35;
# (2) error against the 4x4-spp reference of drawcalls and foliage (2 frames), N and C, 1 px.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/chain35.txt
setup $o
for b in N C; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
S=../shared/assets/scanned
for r in 0.5 0.35; do
  mkdir -p /tmp/sc$r
  for m in turbineblade bunny lucy; do
    /tmp/vgeo-C build $S/$m.ply --ratio $r -o /tmp/sc$r/$m.vgeo > $OUT/build$r-$m.log 2>&1
  done
  for s in stress outdoor; do
    sed -e "s#../../../shared/assets/scanned/\([a-z]*\).ply#/tmp/sc$r/\1.vgeo#" assets/scenes/$s.toml > /tmp/sc$r/$s.toml
  done
done
warm C
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local r=$1 rep=$2
  local d=$OUT/r$r$rep
  timeout 200 /tmp/vgeo-C bench --suite full --scenes-dir /tmp/sc$r --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== r$r$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-C bench --suite full --scenes-dir /tmp/sc$r --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== r$r$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run 0.5 a; run 0.35 a; run 0.35 b; run 0.5 b
for res in "384 216" "192 108"; do
  set -- $res
  timeout 80 /tmp/vgeo-C bench --suite full --scenes-dir /tmp/sc0.35 --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e35-tiny$2 > $OUT/e35-tiny$2.log 2>&1
  echo "== e35 tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
done
pack
for b in N C; do
  timeout 120 /tmp/vgeo-$b bench --suite full --scenes drawcalls,foliage --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$b-scenes > $OUT/e$b-scenes.log 2>&1
  echo "== e$b scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
