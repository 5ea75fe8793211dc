#!/bin/bash
# Session 8, call 6: `cargo bench --bench build` after the parallel preparation (morton order of
# (code, index) pairs, triangles mapped in parallel, Level0 by counting sort), 1 and 16 threads.
gunzip -c .gpu/buildbench.gz > /tmp/buildbench; chmod +x /tmp/buildbench
lscpu | grep -E "Model name|^CPU\(s\)" > $OUT/log.txt
VGEO_SHARED_ASSETS=$PWD/.gpu/assets /tmp/buildbench --bench >> $OUT/log.txt 2>&1
VGEO_PHASES=1 /tmp/buildbench --bench torus10M >> $OUT/log.txt 2> $OUT/phases10M.txt
