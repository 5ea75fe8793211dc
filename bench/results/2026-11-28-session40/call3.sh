#!/bin/bash
# Session 40, call 3 (H200): issue 13's acceptance 2, the settled streamed frame against the same
# cameras all resident on every bench scene: Z = main (9a2025b), `vgeo bench --suite full` at its
# 16 frames a path, 1 px, streamed under 64 MiB (64 MiB a step at most); each camera settles
# (streaming between frames until nothing is uploaded) before it is timed, then the same cameras
# with every page resident are timed the same way (bench.md's streamed table).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stream-bench.txt
setup_xz $o vgeo-Z
warm Z
T0=$SECONDS
timeout 280 /tmp/vgeo-Z bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --geometry-budget 64 --stream-mib-per-frame 64 --quiet --out $OUT/streamed > $OUT/streamed.log 2>&1
echo "== streamed rc=$? t=$((SECONDS - T0))" >> $o
pack
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
