#!/bin/bash
# Session 12, call 3 (H100): N = cdbf0e0.
#  1. examples/stream_sizes: 16 unique meshes (the bunny subdivided 3 times, 4 copies, a seed
#     each), scenes of 4, 8 and 16 of them streamed from their .vgeo files along a 120-frame path
#     at 1920x1080 under 256 MiB (64 MiB per frame): sizes.md/json/svg (issue 13 acceptance 3)
#  2. vgeo bench on outdoor and indoor under 64 MiB: the settled streamed frame time beside the
#     same cameras all resident (issue 13 acceptance 2)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/stream_sizes.gz > /tmp/stream_sizes; chmod +x /tmp/stream_sizes
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
T0=$(date +%s)
timeout 420 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT --sizes 4,8,16 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
T1=$(date +%s)
timeout 120 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor --modes vgeo --sweep 1 --frames 8 --geometry-budget 64 --quiet --out /tmp/Nb > /tmp/Nb.log 2>&1
echo "== N streamed rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
cp /tmp/Nb/bench.md $OUT/Nb-bench.md 2>/dev/null; tail -3 /tmp/Nb.log >> $OUT/log.txt
