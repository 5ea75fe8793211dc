#!/bin/bash
# Session 18, device host (call 2): build throughput, issue 11's base 217d124 (.gpu/vgeo-base.gz)
# against N (.gpu/vgeo-N.gz: main at 65bef90, duplicates found by bucketing), for issue 11
# acceptance 6: session 16's script (pinned threads, base and N interleaved, medians), 7 rounds.
ROUNDS=7 bash bench/results/2026-11-26-session16/build.sh
