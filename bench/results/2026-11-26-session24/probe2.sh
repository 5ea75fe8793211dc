#!/bin/bash
# Session 24, device: timing probes (images not vgeo's): F (raster_sw's small-cluster path draws
# nothing), S (the front path draws nothing), SL (S with only the small path and the box walk in
# the shader: no scanline code, no shared large-triangle pass) against M (main, 526eb64): what a
# lean shader of its own would give the small clusters. Foliage (8 frames), stress N = 20 / 100
# (4 frames), vgeo at 1 px; two interleaved rounds.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/probe2.txt
setup $o M
T0=$SECONDS
warm M
for r in 1 2; do
  for v in M F S SL; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-M bench $sd --suite full --scenes foliage --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-M bench $sd --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
