#!/bin/bash
# Session 35, device call 3: N2 = N (call 2: the band order) with a bit width per normal component
# (format 9; was one width, the wider one's, for both). The decoded values are the same, so N2's
# images should be N's byte for byte.
# 1. Images: N2 against N at 1080p (one frame), pngmax.py.
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), V N N2 N2 N V V N2 N.
# 3. Error against the 4x4-spp reference at 1 px, brute and vgeo: N2 on the five scenes (2 frames)
#    and stress N=20 at 384x216 and 192x108.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/split.txt
setup $o
for b in V N N2; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm N2
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (N2 against N)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in N N2; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  echo "  $n: $(python3 $D/pngmax.py /tmp/img-$n-N.png /tmp/img-$n-N2.png 2>&1)" >> $o
done
echo "== images t=$((SECONDS - T0))" >> $o
pack
run() {
  local b=$1 rep=$2
  local d=$OUT/$b$rep
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $b$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $b$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run V a; run N a; run N2 a; run N2 b; run N b; run V b; run V c; run N2 c; run N c
b=N2
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
