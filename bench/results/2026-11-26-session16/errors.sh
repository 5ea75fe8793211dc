#!/bin/bash
# Session 16, call 12 (H100, 1920x1080, 1 px): this session's vgeo figures with their errors
# against the supersampled reference (brute at 4x4 spp, box-filtered), HEAD's code (.gpu/vgeo-H.gz,
# e8ad74d). Modes brute (1 spp: the floor) and vgeo. outdoor, indoor, drawcalls, foliage: 8 frames;
# stress N=20: 2 frames (its reference is 16 brute frames of 1.6 G triangles each). BIN=X runs
# .gpu/vgeo-X.gz instead (session 17: BIN=N).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-${BIN:-H}.gz > /tmp/vgeo; chmod +x /tmp/vgeo
T0=$SECONDS
timeout 200 /tmp/vgeo bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes brute,vgeo --sweep 1 --frames 8 --out /tmp/e-s > $OUT/errors-scenes.log 2>&1
echo "scenes rc=$? t=$((SECONDS - T0))" >> $OUT/errors-scenes.log
cp /tmp/e-s/bench.md $OUT/errors-scenes-bench.md 2>/dev/null
timeout 330 /tmp/vgeo bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1 --frames 2 --out /tmp/e-t > $OUT/errors-stress.log 2>&1
echo "stress rc=$? t=$((SECONDS - T0))" >> $OUT/errors-stress.log
cp /tmp/e-t/bench.md $OUT/errors-stress-bench.md 2>/dev/null
