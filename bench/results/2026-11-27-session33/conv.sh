#!/bin/bash
# Session 33, device call 2: where call 1's +0.5 % on stress N=200 (instance_cull +0.02 / +0.035
# ms) comes from, and a cheaper box decode. O = a0434d5, N = the box on the grid (call 1's
# binaries); N2 = N with the shader folder .gpu/sd/N2 (the cull's grid corners converted to float
# by the exponent trick, `uintBitsToFloat(c | 0x4b000000) - 2^23`, exact below 2^23, instead of an
# integer-to-float conversion); N3 = N2 and the rasterizers' vertex positions the same way.
# 1. Images: N2 and N3 against N, byte for byte (outdoor, indoor, foliage, drawcalls, close blade).
# 2. Times: stress N=100 / 200 (16-frame path) and the five scenes (4 frames), O N N2 N3 N3 N2 N O.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/conv.txt
setup $o
for b in O N; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm N
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (N2, N3 against N)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  timeout 60 /tmp/vgeo-N render $s --width 1920 --height 1080 --out /tmp/img-$n-N.png > /dev/null 2>&1
  for v in N2 N3; do
    timeout 60 /tmp/vgeo-N render $s --width 1920 --height 1080 --shader-dir .gpu/sd/$v --out /tmp/img-$n-$v.png > /dev/null 2>&1
    if cmp -s /tmp/img-$n-N.png /tmp/img-$n-$v.png; then r=same; else r=DIFFERENT; fi
    echo "  $n $v: $r" >> $o
  done
done
echo "== images t=$((SECONDS - T0))" >> $o
pack
run() {
  local name=$1 rep=$2
  local d=$OUT/$name$rep sd="" bin=N
  case $name in O) bin=O ;; N2|N3) sd="--shader-dir .gpu/sd/$name" ;; esac
  timeout 200 /tmp/vgeo-$bin bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$bin bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
  echo "== $name$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run O a; run N a; run N2 a; run N3 a; run N3 b; run N2 b; run N b; run O b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
