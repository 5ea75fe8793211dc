#!/bin/bash
# Session 12, call 4 (H100): M = c42c2ec (N + the GPU-driven lod baseline merged).
#  1. examples/stream_sizes as in s12c.sh (meshes made 4 at a time now)
#  2. the scene suite in brute, lod (now GPU-driven) and vgeo at 1 and 0.25 px against the
#     4x4-spp reference (issue 14 acceptance 2: vgeo against the new lod at equal error)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo-M; chmod +x /tmp/vgeo-M
gunzip -c .gpu/stream_sizes.gz > /tmp/stream_sizes; chmod +x /tmp/stream_sizes
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
T0=$(date +%s)
timeout 300 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT --sizes 4,8,16 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
T1=$(date +%s)
timeout 250 /tmp/vgeo-M bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,lod,vgeo --sweep 1,0.25 --frames 8 --quiet --out /tmp/M > /tmp/M.log 2>&1
echo "== M scenes rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
cp /tmp/M/bench.md $OUT/M-bench.md 2>/dev/null; tail -3 /tmp/M.log >> $OUT/log.txt
