#!/bin/bash
# Session 36, device call 1: the scans built at --ratio 0.35 with the default ratio's root chain
# (H = this session's build, which takes the chain's source from the levels at 0.5) against the
# same scans at 0.35 without it (B35 = main at the session's start, 87a0762) and against the
# default 0.5 (A = 87a0762 with the repository's scene files, whose .vgeo files are byte for byte
# H's at 0.5). The stress and outdoor scenes name .vgeo files built on this host. Times (A H B H A
# B A H B), the bytes per stored triangle, and the error at 1 px against the 4x4-spp reference: H
# and B35 at stress N=20 at 192x108 and 384x216 and the two scenes at 1080p, A at 192x108.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/sh35.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base H; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
for v in H:H B:base; do
  t=${v%%:*}; b=${v##*:}; S=/tmp/s$t; mkdir -p $S
  for m in turbineblade bunny lucy; do
    /usr/bin/time -f "$t $m %e s %M KB" /tmp/vgeo-$b build ../shared/assets/scanned/$m.ply --ratio 0.35 -o $S/$m.vgeo > $OUT/build-$t-$m.log 2>> $o
  done
  for s in stress outdoor; do
    sed -e "s#\"../../../shared/assets/scanned/\([a-z]*\).ply\"#\"$S/\1.vgeo\"#" assets/scenes/$s.toml > $S/$s.toml
  done
done
grep -h "path =" /tmp/sH/*.toml >> $o
cp /tmp/vgeo-base /tmp/vgeo-B; cp /tmp/vgeo-base /tmp/vgeo-A
timeout 60 /tmp/vgeo-H bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 dir=assets/scenes
  [ $t != A ] && dir=/tmp/s$t
  local d=$OUT/$t$rep
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes-dir $dir --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes-dir $dir --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run H a; run B a; run H b; run A b; run B b; run A c; run H c; run B c
err() {
  local t=$1 w=$2 h=$3 dir=/tmp/s$1
  [ $t = A ] && dir=assets/scenes
  timeout 60 /tmp/vgeo-$t bench --suite full --scenes-dir $dir --scenes stress --stress-n 20 --width $w --height $h --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$t-tiny$h > $OUT/e$t-tiny$h.log 2>&1
  echo "== e$t tiny$h rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
err H 192 108; err B 192 108; err A 192 108; err H 384 216; err B 384 216
timeout 120 /tmp/vgeo-H bench --suite full --scenes-dir /tmp/sH --scenes stress,outdoor --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eH-scenes > $OUT/eH-scenes.log 2>&1
echo "== eH scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
