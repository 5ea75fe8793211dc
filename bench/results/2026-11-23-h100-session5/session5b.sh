#!/bin/bash
# Session 5, second H100 call: the CPU cost of a host's frame, and the suite's scenes plus the
# demo at 1 px with their error against brute at 4x4 spp (this commit).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/log.txt
lscpu | grep "Model name" | tee -a $OUT/log.txt
timeout 170 ./.gpu/vgeo bench --suite full --record-cpu 8000,125000,1000000 --record-changed 0,10000 --frames 20 --out $OUT/rc > $OUT/rc.txt 2>&1
echo "record rc=$?" >> $OUT/log.txt
timeout 400 ./.gpu/vgeo bench --suite full --scenes outdoor,indoor,drawcalls,foliage,demo --modes brute,vgeo --sweep 1 --frames 8 --reference-spp 16 --quiet --out /tmp/s > /tmp/s.log 2>&1
echo "scenes rc=$?" >> $OUT/log.txt
cp /tmp/s/bench.md $OUT/scenes.md 2>/dev/null; tail -5 /tmp/s.log >> $OUT/log.txt
