#!/bin/bash
# Session 37, device call 2: the stated precision apart from the build grid. P = f0ec5ef with the
# DAG built on the grid as before (at least 16 bits) and the pages storing positions on the stated
# grid (at least 14 bits, 1/64 of the median edge: blade 15, bunny 14, lucy 14), the default step
# ratio 0.5; E = P with the default ratio 0.35; A = f0ec5ef. Every bench scene with the
# repository's scene files: build bytes, run times (A P E / E P A / P A E), bytes per stored
# triangle, P's and E's error at 1 px against the 4x4-spp reference (every scene at 1080p, stress
# N=20 at 192x108), and each scene's lit image (vgeo render, 1080p, 1 px) by A, P and E in
# images.tar, compared here.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stored.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A P E; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
mkdir -p /tmp/x
for b in A P E; do for m in turbineblade bunny lucy; do
  /usr/bin/time -f "$b $m %e s %M KB" /tmp/vgeo-$b build ../shared/assets/scanned/$m.ply -o /tmp/x/$b-$m.vgeo > /tmp/x/$b-$m.log 2>> $o
  grep -h "pages:" /tmp/x/$b-$m.log | sed "s/^/$b $m /" >> $o
done; done
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz --exclude=images.tar . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 d=$OUT/$1$2
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run P a; run E a; run E b; run P b; run A b; run P c; run A c; run E c
for t in P E; do
  timeout 60 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$t-tiny108 > $OUT/e$t-tiny108.log 2>&1
  echo "== e$t tiny108 rc=$? t=$((SECONDS - T0))" >> $o
  timeout 150 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$t-scenes > $OUT/e$t-scenes.log 2>&1
  echo "== e$t scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
mkdir -p /tmp/img
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in A P E; do timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --out /tmp/img/$n-$b.png > /dev/null 2>&1; done
done
(cd /tmp/img && tar cf $OUT/images.tar *.png)
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz ! -name images.tar -delete
