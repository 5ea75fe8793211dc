#!/bin/bash
# Session 8, call 4: `cargo bench --bench build` (ec07c8e + torus10M) on the H100 host: 1 and 16
# threads; torus10M with phase times (VGEO_PHASES=1).
gunzip -c .gpu/buildbench.gz > /tmp/buildbench; chmod +x /tmp/buildbench
lscpu | grep -E "Model name|^CPU\(s\)" > $OUT/log.txt
VGEO_SHARED_ASSETS=$PWD/.gpu/assets /tmp/buildbench --bench >> $OUT/log.txt 2>&1
VGEO_PHASES=1 /tmp/buildbench --bench torus10M >> $OUT/log.txt 2> $OUT/phases10M.txt
