#!/bin/bash
# Session 34, device call 3: T = C (5a8c984's code) with the levels of one group (the whole mesh in
# one group, below the root chain's source of at most 2048 triangles) made like the root chain:
# each simplifies the source to 0.7 of the level before, its error the source's plus that one
# simplification's. T35 = T with the default step ratio 0.35.
# 1. Images: T against C at 1080p (one frame): how many pixels differ (pngmax.py).
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), C T T C C T;
#    T35's stress N=20 / 100 / 200 twice.
# 3. Error against the 4x4-spp reference at 1 px, brute and vgeo: T on the five scenes (2 frames)
#    and stress N=20 at 384x216 and 192x108 (C's: call 1); T35 at 192x108 and 384x216.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/top.txt
setup $o
for b in C T T35; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm T
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (T against C)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in C T; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  echo "  $n: $(python3 $D/pngmax.py /tmp/img-$n-C.png /tmp/img-$n-T.png 2>&1)" >> $o
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
run C a; run T a; run T b; run C b; run C c; run T c
for rep in a b; do
  timeout 200 /tmp/vgeo-T35 bench --suite full --scenes stress --stress-n 20,100,200 --modes vgeo --sweep 1 --quiet --out $OUT/T35$rep-big > $OUT/T35$rep-big.log 2>&1
  echo "== T35$rep big rc=$? t=$((SECONDS - T0))" >> $o
done
pack
d=$OUT/eT
timeout 120 /tmp/vgeo-T bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
echo "== eT scenes rc=$? t=$((SECONDS - T0))" >> $o
for b in T T35; do
  for res in "384 216" "192 108"; do
    set -- $res
    timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/e$b-tiny$2 > $OUT/e$b-tiny$2.log 2>&1
    echo "== e$b tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
    pack
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
