#!/bin/bash
# Session 39, call 3: X = V with `--shader-dir .gpu/x` (cull.glsl's in_cut written as test_cluster
# was at 5ddee74: no early return, the view's flags read first; test_cluster still calls it):
# its cull pipelines' statistics, runs A X X A on the big stress views; then V's error on stress
# N=20 at 192x108 (call 2's timed out at 40 s).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A V; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
printf '#!/bin/bash\nVGEO_SHADER_DIR=%s/.gpu/x exec /tmp/vgeo-V "$@"\n' $PWD > /tmp/vgeo-X; chmod +x /tmp/vgeo-X
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-X bench --suite full --scenes stress --stress-n 2 --frames 1 --modes vgeo --sweep 1 --quiet --out /tmp/st-X > $OUT/stats-X.log 2>&1
warm A
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
for r in Aa Xa Xb Ab; do
  timeout 100 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $OUT/$r-big > $OUT/$r-big.log 2>&1
  echo "== $r big rc=$? t=$((SECONDS - T0))" >> $o
done
pack
timeout 200 /tmp/vgeo-V bench --suite full --scenes stress --stress-n 20 --width 192 --height 108 --frames 2 --modes brute,vgeo --sweep 1 --quiet --out $OUT/eV-tiny108 > $OUT/eV-tiny108.log 2>&1
echo "== eV tiny108 rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
