#!/bin/bash
# Session 33, device call 5: T's instance_cull on stress N=200 (+0.05 ms against O in call 4, the
# same registers, 512 B more shared memory per workgroup): V1 = T with the shader folder
# .gpu/sd/V1, where the cull's box helpers take the mesh's grid (a vec4: origin, step) instead of
# the whole MeshGpu. Compiled statistics of V1; stress N=100 / 200 (16-frame path), O T V1 V1 T O.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/v1.txt
setup $o
for b in O T; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-T render .gpu/close.toml --width 640 --height 360 --shader-dir .gpu/sd/V1 --out /tmp/x.png 2>&1 | grep "instance_cull\|cluster_cull" >> $o
VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-T render .gpu/close.toml --width 640 --height 360 --out /tmp/x.png 2>&1 | grep "instance_cull\|cluster_cull" >> $o
warm T
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 rep=$2
  local d=$OUT/$name$rep sd="" bin=T
  case $name in O) bin=O ;; V1) sd="--shader-dir .gpu/sd/V1" ;; esac
  timeout 200 /tmp/vgeo-$bin bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name$rep big rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run O a; run T a; run V1 a; run V1 b; run T b; run O b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
