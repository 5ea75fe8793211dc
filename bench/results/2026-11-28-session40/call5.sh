#!/bin/bash
# Session 40, call 5 (H200, the session's last device time): P = W with each table row's pages
# listed in the table (a row is checked for residency page by page, not cluster by cluster:
# call 4 left stress N=20 streamed +17.5 % against all resident). P's streamed bench as calls 3
# and 4 (every scene, 64 MiB, settled cameras against all resident), then P with every page
# resident on stress N=20 / 100 / 200 (one run: against call 4's Z and W across calls).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/timing.txt
setup_xz $o vgeo-P
warm P
T0=$SECONDS
timeout 120 /tmp/vgeo-P bench --suite full --scenes stress,outdoor,indoor,foliage,drawcalls --stress-n 20 --modes vgeo --sweep 1 --geometry-budget 64 --stream-mib-per-frame 64 --quiet --out $OUT/Pstreamed > $OUT/Pstreamed.log 2>&1
echo "== P streamed rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 45 /tmp/vgeo-P bench --suite full --scenes stress --stress-n 20,100,200 --modes vgeo --sweep 1 --quiet --out $OUT/Pa-stress > $OUT/Pa-stress.log 2>&1
echo "== Pa stress rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
