#!/bin/bash
# Session 7, call 2: variant C (coverage summed over a group's pieces, position error summed along
# the chain): scenes and stress against a 4x4 reference; build throughput base (217d124) vs C.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in C base; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
date >> $OUT/log.txt
timeout 230 /tmp/vgeo-C bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 16 --reference-spp 16 --sweep 1,0.5,0.25 --quiet --out /tmp/C-scenes > /tmp/C-scenes.log 2>&1
echo "== C scenes rc=$?" >> $OUT/log.txt; date >> $OUT/log.txt
timeout 200 /tmp/vgeo-C bench --suite full --scenes stress --stress-n 4,16,20,100 --frames 4 --reference-spp 16 --sweep 1,0.25 --quiet --out /tmp/C-stress > /tmp/C-stress.log 2>&1
echo "== C stress rc=$?" >> $OUT/log.txt; date >> $OUT/log.txt
for r in 1 2 3 4 5; do for m in lucy bunny turbineblade; do for t in 16 1; do for b in base C; do
  s=$(/tmp/vgeo-$b build ../shared/assets/scanned/$m.ply -o /tmp/x.vgeo --threads $t --json 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "BUILD $b $m threads=$t run=$r seconds=$s" >> $OUT/build.txt
done; done; done; done
date >> $OUT/log.txt
for d in C-scenes C-stress; do echo "=== $d" >> $OUT/log.txt; grep -E "^\||^## |wall time" /tmp/$d/bench.md >> $OUT/log.txt; done
cp /tmp/*.log $OUT/ 2>/dev/null
tar czf $OUT/s7b.tgz -C /tmp --exclude='*.png' C-scenes C-stress
