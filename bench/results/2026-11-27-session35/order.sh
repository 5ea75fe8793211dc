#!/bin/bash
# Session 35, device call 2: N = V (800e121) with each cluster's triangles stored in a band order
# (tricode::stored_order: breadth-first vertex numberings, the one whose max-delta code is
# shortest), so that the corner offsets take 4 bits instead of 5-6. The decoder is unchanged.
# 1. Images: N against V at 1080p (one frame): how many pixels differ (pngmax.py).
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), V N N V V N,
#    with per-pass times (raster_sw, emit_gbuffer) and bytes per stored triangle.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/order.txt
setup $o
for b in V N; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm N
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (N against V)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in V N; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  echo "  $n: $(python3 $D/pngmax.py /tmp/img-$n-V.png /tmp/img-$n-N.png 2>&1)" >> $o
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
run V a; run N a; run N b; run V b; run V c; run N c
for b in V N; do
  for s in .gpu/close.toml; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --time 64 --out /tmp/t.png > $OUT/close-$b.log 2>&1
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
