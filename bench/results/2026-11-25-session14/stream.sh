#!/bin/bash
# Session 14 (H100 host): issue 13 acceptance 2, the cold camera cut after this session's streaming
# changes (a load set no longer takes a page being read, so no slot is lost; the always-resident
# prefix ends at a page boundary; pages filled from the next 16 groups; no request for a group
# whose LOD sphere is outside the frustum). stream_sizes as in
# session 12 (bench/results/2026-11-25-session12/s12f.sh): 16 unique meshes (bunny subdivided
# 3 levels, 4 copies each), sizes 4, 8, 16 under 256 MiB, 1920x1080; sizes.md now has a second
# table for the cold cut: frames to settle, resident, used, resident/used, needed (closure of the
# used pages), other, always resident, slot rounding.
# Expects under .gpu/: the loader .debs, assets/ (../shared/assets), vgeo.gz (release `vgeo` of
# this branch) and stream_sizes.gz (target/release/examples/stream_sizes of this branch);
# optionally stream_sizes-base.gz (the same example at 2755f8e, session 13) for a baseline at
# size 4 on the same machine, run only if time is left. Writes under $OUT; under 8 minutes.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo.gz > /tmp/vgeo; chmod +x /tmp/vgeo
gunzip -c .gpu/stream_sizes.gz > /tmp/stream_sizes; chmod +x /tmp/stream_sizes
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
nproc >> $OUT/log.txt
T0=$(date +%s)
timeout 330 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT --sizes 4,8,16 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
cat $OUT/sizes.md >> $OUT/log.txt
grep "cold cut" $OUT/sizes-log.txt >> $OUT/log.txt
# One mesh's pages (count, always resident, bytes) as the new builder laid them out.
timeout 20 /tmp/vgeo info /tmp/big/m0.vgeo > $OUT/m0-info.txt 2>&1
# The session-13 example at size 4 on the same machine (its own meshes: the page layout differs).
if [ -f .gpu/stream_sizes-base.gz ] && [ $(( $(date +%s) - T0 )) -lt 300 ]; then
  gunzip -c .gpu/stream_sizes-base.gz > /tmp/stream_sizes-base; chmod +x /tmp/stream_sizes-base
  mkdir -p $OUT/base
  T1=$(date +%s)
  timeout $(( 440 - $(date +%s) + T0 )) /tmp/stream_sizes-base --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big-base --out $OUT/base --sizes 4 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 120 --size 1920x1080 > $OUT/base/sizes-log.txt 2>&1
  echo "== base size 4 rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
  cat $OUT/base/sizes.md >> $OUT/log.txt 2>/dev/null
fi
echo "== total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
