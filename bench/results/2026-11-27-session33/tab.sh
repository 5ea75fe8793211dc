#!/bin/bash
# Session 33, device call 4: T = N (call 1: a cluster's box as grid coordinates in its cull words)
# with the sphere of a small-instance table row of one cluster stored in the table, so that
# instance_cull emits such a cluster without decoding its box (call 2: N's instance_cull +0.06 ms
# on stress N=200, where nearly every instance is one such cluster), against O = a0434d5.
# 1. Images: each scene's lit image and the close blade's at 1920x1080, 1 px (one frame), T
#    against O byte for byte.
# 2. Times: stress N=100 and 200 along the full suite's 16-frame path, the five scenes (4 frames),
#    O T T O O T.
# 3. The close blade and the empty frame, `render --time 64`.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/tab.txt
setup $o
for b in O T; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm T
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (T against O)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in O T; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --out /tmp/img-$n-$b.png > /dev/null 2>&1
  done
  if cmp -s /tmp/img-$n-O.png /tmp/img-$n-T.png; then r=same; else r=DIFFERENT; fi
  echo "  $n: $r" >> $o
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
run O a; run T a; run T b; run O b; run O c; run T c
for b in O T; do
  timeout 60 /tmp/vgeo-$b render .gpu/close.toml --width 1920 --height 1080 --time 64 > $OUT/close-$b.log 2>&1
  timeout 60 /tmp/vgeo-$b render .gpu/empty.toml --width 1920 --height 1080 --time 64 > $OUT/empty-$b.log 2>&1
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
