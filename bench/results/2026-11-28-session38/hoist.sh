#!/bin/bash
# Session 38, device call 4 (what device time was left): U (call 3's T, but that a run's instance
# and mesh are loaded once per run, not per cluster: a thread's own small-instance cut reads them
# once, as before) against H (5ddee74) on the stress scenes alone (N=20, 100, 200; 16 frames),
# runs H U U H.
o=$OUT/hoist.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in H U; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
T0=$SECONDS
for r in Ha Ua Ub Hb; do
  timeout 50 /tmp/vgeo-${r:0:1} bench --suite full --scenes stress --stress-n 20,100,200 --modes vgeo --sweep 1 --quiet --out $OUT/$r-stress > $OUT/$r-stress.log 2>&1
  echo "== $r rc=$? t=$((SECONDS - T0))" >> $o
done
cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images . && find $OUT -mindepth 1 -delete && cp /tmp/h.tgz $OUT/h.tgz
