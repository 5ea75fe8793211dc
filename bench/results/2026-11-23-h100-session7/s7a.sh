#!/bin/bash
# Session 7, call 1: the suite's scenes against a 4x4 reference with the coverage error
# (B: lost area summed over a group's pieces; A: the worst piece), and the frame before (old).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A B base; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/vgeo.gz > /tmp/vgeo-old; chmod +x /tmp/vgeo-old
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
/tmp/vgeo-B info 2>&1 | head -5 >> $OUT/log.txt
date >> $OUT/log.txt
timeout 330 /tmp/vgeo-B bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 16 --reference-spp 16 --quiet --out /tmp/B-scenes > /tmp/B-scenes.log 2>&1
echo "== B scenes rc=$?" >> $OUT/log.txt; date >> $OUT/log.txt
timeout 150 /tmp/vgeo-A bench --suite full --scenes foliage --frames 16 --reference-spp 16 --sweep 1,0.5 --quiet --out /tmp/A-foliage > /tmp/A-foliage.log 2>&1
echo "== A foliage rc=$?" >> $OUT/log.txt; date >> $OUT/log.txt
timeout 60 /tmp/vgeo-old bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/old-scenes > /tmp/old-scenes.log 2>&1
echo "== old scenes rc=$?" >> $OUT/log.txt; date >> $OUT/log.txt
for d in B-scenes A-foliage old-scenes; do echo "=== $d" >> $OUT/log.txt; grep -E "^\||^## |wall time" /tmp/$d/bench.md >> $OUT/log.txt; done
cp /tmp/*.log $OUT/ 2>/dev/null
tar czf $OUT/s7a.tgz -C /tmp --exclude='*.png' B-scenes A-foliage old-scenes
