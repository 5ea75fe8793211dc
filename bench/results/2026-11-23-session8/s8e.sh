#!/bin/bash
# Session 8, call 5: torus10M build with temporary stage timings inside prepare (P) and before
# level-0 clustering (T), 1 and 16 threads.
gunzip -c .gpu/buildbench.gz > /tmp/buildbench; chmod +x /tmp/buildbench
/tmp/buildbench --bench torus10M > $OUT/log.txt 2>&1
