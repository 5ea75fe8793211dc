#!/bin/bash
# Session 11, call 5: the final code (F = this session's last commit) with its image error against
# the 4x4-spp brute reference: the scene suite and stress N=20 in brute and vgeo at 1 px, then the
# streamed bench on outdoor under a 64 MiB budget (the bench's --geometry-budget on the H100).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-F.gz > /tmp/vgeo; chmod +x /tmp/vgeo
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
timeout 200 /tmp/vgeo bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,vgeo --sweep 1 --frames 8 --quiet --out /tmp/F > /tmp/F.log 2>&1
echo "== scenes rc=$?" >> $OUT/log.txt
timeout 200 /tmp/vgeo bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1 --frames 2 --quiet --out /tmp/Fs > /tmp/Fs.log 2>&1
echo "== stress rc=$?" >> $OUT/log.txt
timeout 120 /tmp/vgeo bench --suite full --scenes outdoor --modes vgeo --sweep 1 --frames 4 --geometry-budget 64 --quiet --out /tmp/Fb > /tmp/Fb.log 2>&1
echo "== streamed rc=$?" >> $OUT/log.txt
for d in F Fs Fb; do cp /tmp/$d/bench.md $OUT/$d-bench.md 2>/dev/null; tail -3 /tmp/$d.log >> $OUT/log.txt; done
