#!/bin/bash
# Session 8, call 8: torus10M with temporary stage timings (P ...) at 1 and 16 threads.
gunzip -c .gpu/buildbench.gz > /tmp/buildbench; chmod +x /tmp/buildbench
/tmp/buildbench --bench torus10M > $OUT/log.txt 2>&1
