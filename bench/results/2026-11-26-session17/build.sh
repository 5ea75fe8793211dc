#!/bin/bash
# Session 17, device host (call 6): build throughput, issue 11's base 217d124 (.gpu/vgeo-base.gz)
# against N (.gpu/vgeo-N.gz: main with the max-delta triangle code), for issue 11 acceptance 6:
# session 16's script (pinned threads, base and N interleaved, medians), five rounds.
ROUNDS=5 bash bench/results/2026-11-26-session16/build.sh
