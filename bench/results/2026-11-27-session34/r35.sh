#!/bin/bash
# Session 34, device call 1: the step ratio 0.35 as the default, with the root chain.
# C = the code of 5a8c984 (the root chain landed; binary of 0b169f6, the same code), R = C with the
# default step ratio 0.35 (BuildOptions and `vgeo build --ratio`); each builds its meshes at load.
# 1. Images: R against C at 1080p (one frame): how many pixels differ (pngmax.py).
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), C R R C C R.
# 3. Error against the 4x4-spp reference at 1 px, brute and vgeo: the five scenes (2 frames), and
#    stress N=20 at 384x216 and 192x108 (the instance sizes of N=100 and N=200 at 1080p).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/r35.txt
setup $o
for b in C R; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm R
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (R against C)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in C R; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  echo "  $n: $(python3 $D/pngmax.py /tmp/img-$n-C.png /tmp/img-$n-R.png 2>&1)" >> $o
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
run C a; run R a; run R b; run C b; run C c; run R c
for b in R C; do
  d=$OUT/e$b
  timeout 120 /tmp/vgeo-$b bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== e$b scenes rc=$? t=$((SECONDS - T0))" >> $o
  for res in "384 216" "192 108"; do
    set -- $res
    timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $d-tiny$2 > $d-tiny$2.log 2>&1
    echo "== e$b tiny$2 rc=$? t=$((SECONDS - T0))" >> $o
  done
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
