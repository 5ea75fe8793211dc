#!/bin/bash
# Session 39, call 2: V = c970623 (main) against A = f0ec5ef, and W = V with `--shader-dir .gpu/w`
# (cull.glsl's test_cluster written inline as at 5ddee74, in_cut kept for the shared runs only),
# runs A V W W V A on the big stress views and the scenes at the suite's 16 frames; each build's
# cull pipelines' statistics (VGEO_PIPELINE_STATS=1); then V's error at 1 px against the 4x4-spp
# reference (stress N=20 at 192x108 and every scene).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A V; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
printf '#!/bin/bash\nVGEO_SHADER_DIR=%s/.gpu/w exec /tmp/vgeo-V "$@"\n' $PWD > /tmp/vgeo-W; chmod +x /tmp/vgeo-W
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
for b in A V W; do
  VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 2 --frames 1 --modes vgeo --sweep 1 --quiet --out /tmp/st-$b > $OUT/stats-$b.log 2>&1
done
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local t=$1 rep=$2 d=$OUT/$1$2
  timeout 100 /tmp/vgeo-$t bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $t$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 100 /tmp/vgeo-$t bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $t$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run A a; run V a; run W a; run W b; run V b; run A b
timeout 40 /tmp/vgeo-V bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eV-tiny108 > $OUT/eV-tiny108.log 2>&1
echo "== eV tiny108 rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 90 /tmp/vgeo-V bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eV-scenes > $OUT/eV-scenes.log 2>&1
echo "== eV scenes rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
