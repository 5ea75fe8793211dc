#!/bin/bash
# Session 31, device call 3 (final): F = the final binary (occluder_select for frames without a
# previous HZB, cutoff at COLD_OCCLUDER_COVER = 4 screens; a big mesh's one-cluster table cut
# emitted on its instance's tests); B = F with the shader directory .gpu/sd/B, which restores
# dc2138c's instance_cull (no deferral in a cold frame) and cull.glsl (every table cluster
# tested): dc2138c's frame plus the occluder_select pass, which its frames do not read.
# (dc2138c's own binary did not fit the carry limit beside F's; its figures are call 1's.)
# 1. Images: each scene's lit image and the close blade's at 1920x1080, 1 px (one frame: a cold
#    one), F against B byte for byte.
# 2. Times: stress N=100 and 200 along the full suite's 16-frame path, the five scenes
#    (4 frames), B F F B; then F's five scenes along the full suite's 16-frame paths.
# 3. Error: stress N=20 at 192x108 (instances of N=200's size at 1080p), brute and vgeo at 1 px,
#    against its 4x4-spp reference (F).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/final.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-F.xz /tmp/vgeo-F
chmod +x /tmp/vgeo-F
ls -la /tmp/vgeo-F >> $o
warm F
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (F against B)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  timeout 60 /tmp/vgeo-F render $s --width 1920 --height 1080 --shader-dir .gpu/sd/B --out /tmp/img-$n-B.png > /tmp/img-$n-B.log 2>&1
  timeout 60 /tmp/vgeo-F render $s --width 1920 --height 1080 --out /tmp/img-$n-F.png > /tmp/img-$n-F.log 2>&1
  if cmp -s /tmp/img-$n-B.png /tmp/img-$n-F.png; then r=same; else r=DIFFERENT; fi
  echo "  $n: $r" >> $o
done
echo "== images t=$((SECONDS - T0))" >> $o
pack
run() {
  local name=$1 rep=$2
  local d=$OUT/$name$rep sd=""
  [ $name = B ] && sd="--shader-dir .gpu/sd/B"
  timeout 200 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-F bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
  echo "== $name$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run B a; run F a; run F b; run B b
timeout 200 /tmp/vgeo-F bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --modes vgeo --sweep 1 --quiet --out $OUT/F-scenes16 > $OUT/F-scenes16.log 2>&1
echo "== F scenes16 rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 200 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/F-tiny108 > $OUT/F-tiny108.log 2>&1
echo "== F tiny108 rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
