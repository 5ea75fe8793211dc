#!/bin/bash
# Session 37, device call 4: the session's commit (F = e3405ef: the stored grid apart from the
# build grid, the default step ratio 0.35; call 2's E but that a cluster's SW/HW size code now
# comes from its stored positions) against f0ec5ef (A) on every bench scene with the repository's
# scene files: build bytes and times, run times (A F F A A F), bytes per stored triangle, and F's
# error at 1 px against the 4x4-spp reference (every scene at 1080p, stress N=20 at 192x108).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/final.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A F; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
mkdir -p /tmp/x
for b in A F; do for m in turbineblade bunny lucy; do
  /usr/bin/time -f "$b $m %e s %M KB" /tmp/vgeo-$b build ../shared/assets/scanned/$m.ply -o /tmp/x/$b-$m.vgeo > /tmp/x/$b-$m.log 2>> $o
  grep -h "pages:" /tmp/x/$b-$m.log | sed "s/^/$b $m /" >> $o
done; done
for m in turbineblade bunny lucy; do timeout 60 /tmp/vgeo-F verify /tmp/x/F-$m.vgeo > /tmp/x/v-$m.log 2>&1; echo "F verify $m rc=$? $(tail -1 /tmp/x/v-$m.log)" >> $o; done
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 d=$OUT/$1$2
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run F a; run F b; run A b; run A c; run F c
timeout 60 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eF-tiny108 > $OUT/eF-tiny108.log 2>&1
echo "== eF tiny108 rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 150 /tmp/vgeo-F bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eF-scenes > $OUT/eF-scenes.log 2>&1
echo "== eF scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
