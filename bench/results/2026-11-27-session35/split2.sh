#!/bin/bash
# Session 35, device call 4: N3 = N (call 2: the band order) with a bit width per normal component
# as N2 (call 3), but the normals' y width rides in the high bits of the cluster's smallest x
# coordinate (above the triangle code's header, read in the same load) instead of the material
# width moving into the material word (N2: raster_sw +1-1.5 % against N). Format 9.
# 1. Images: N3 against N at 1080p (one frame), pngmax.py.
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), N N3 N3 N N N3 N3 N.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/split2.txt
setup $o
for b in N N3; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm N3
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (N3 against N)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in N N3; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  echo "  $n: $(python3 $D/pngmax.py /tmp/img-$n-N.png /tmp/img-$n-N3.png 2>&1)" >> $o
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
run N a; run N3 a; run N3 b; run N b; run N c; run N3 c; run N3 d; run N d
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
