#!/bin/bash
# Session 18 (H100 host): issue 13 acceptance 2, the cold camera cut after this session's change
# (a cluster drawn for want of its absent children asks for them only when its box meets the
# frustum, tested corner by corner: the box's sphere reached past the near plane from clusters
# wholly behind the camera). stream_sizes as in session 14 (../2026-11-25-session14/stream.sh):
# 16 unique meshes (bunny subdivided 3 levels, 4 copies each), sizes 4, 8, 16 under 256 MiB,
# 1920x1080, 120 frames along the path; the log now has the cold cut per mesh (used, needed,
# resident pages, other).
# Expects under .gpu/: the loader .debs, assets/scanned/bunny.ply, stream_sizes.gz (stripped
# target/release/examples/stream_sizes of this commit). Writes under $OUT; under 7 minutes.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
gunzip -c .gpu/stream_sizes.gz > /tmp/stream_sizes; chmod +x /tmp/stream_sizes
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
nproc >> $OUT/log.txt
T0=$(date +%s)
timeout 400 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT --sizes 4,8,16 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
cat $OUT/sizes.md >> $OUT/log.txt
grep "cold cut" $OUT/sizes-log.txt >> $OUT/log.txt
echo "== total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
