#!/bin/bash
# Session 12, call 6 (H100): stream_sizes with the cold camera cut (issue 13 acceptance 2: frames to settle, resident against used).
#  1. examples/stream_sizes as in s12c.sh (meshes made 4 at a time now)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo-M; chmod +x /tmp/vgeo-M
gunzip -c .gpu/stream_sizes.gz > /tmp/stream_sizes; chmod +x /tmp/stream_sizes
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
T0=$(date +%s)
timeout 420 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT --sizes 4,8,16 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
cat $OUT/sizes.md >> $OUT/log.txt
