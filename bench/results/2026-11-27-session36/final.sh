#!/bin/bash
# Session 36, device call 2: the session's final build (N) with the scans at --ratio 0.35 against
# the default 0.5 (A = 87a0762 with the repository's scene files). Since call 1 the bunny too takes
# the default's root chain at 0.35 (the guard on the first level of one group changed); the blade
# and lucy build as in call 1. Build times (N at 0.35, A's binary at 0.35 and 0.5), run times (A N
# N A A N), bytes per stored triangle, and N's error at 1 px against the 4x4-spp reference.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/final.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base N; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
cp /tmp/vgeo-base /tmp/vgeo-A
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
S=/tmp/sN; mkdir -p $S /tmp/x
for m in turbineblade bunny lucy; do
  /usr/bin/time -f "N 0.35 $m %e s %M KB" /tmp/vgeo-N build ../shared/assets/scanned/$m.ply --ratio 0.35 -o $S/$m.vgeo > $OUT/build-N-$m.log 2>> $o
  /usr/bin/time -f "A 0.35 $m %e s %M KB" /tmp/vgeo-A build ../shared/assets/scanned/$m.ply --ratio 0.35 -o /tmp/x/$m.vgeo > /dev/null 2>> $o
  /usr/bin/time -f "A 0.5 $m %e s %M KB" /tmp/vgeo-A build ../shared/assets/scanned/$m.ply -o /tmp/x/$m.vgeo > /dev/null 2>> $o
  /usr/bin/time -f "N 0.5 $m %e s %M KB" /tmp/vgeo-N build ../shared/assets/scanned/$m.ply -o /tmp/x/n-$m.vgeo > /dev/null 2>> $o
  cmp -s /tmp/x/$m.vgeo /tmp/x/n-$m.vgeo && echo "$m at 0.5: N's file is A's byte for byte" >> $o
done
for s in stress outdoor; do
  sed -e "s#\"../../../shared/assets/scanned/\([a-z]*\).ply\"#\"$S/\1.vgeo\"#" assets/scenes/$s.toml > $S/$s.toml
done
grep -h "path =" $S/*.toml >> $o
timeout 60 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 dir=assets/scenes
  [ $t = N ] && dir=$S
  local d=$OUT/$t$rep
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes-dir $dir --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes-dir $dir --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run N a; run N b; run A b; run A c; run N c
timeout 60 /tmp/vgeo-N bench --suite full --scenes-dir $S --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eN-tiny108 > $OUT/eN-tiny108.log 2>&1
echo "== eN tiny108 rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 120 /tmp/vgeo-N bench --suite full --scenes-dir $S --scenes stress,outdoor --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eN-scenes > $OUT/eN-scenes.log 2>&1
echo "== eN scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
