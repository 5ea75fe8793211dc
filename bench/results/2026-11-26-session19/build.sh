#!/bin/bash
# Session 19, device host: build throughput (issue 11 acceptance 6: at most 25 % slower than
# 217d124), issue 11's base (.gpu/vgeo-base.gz) against N (.gpu/vgeo-N.gz, main at dcb864f).
# Session 16's script (bench/results/2026-11-26-session16/build.sh: the build's own `seconds`,
# one thread pinned to one core, two to two, 16 unpinned, base and N interleaved) with
# ROUNDS rounds (default 5 here).
ROUNDS=${ROUNDS:-5} bash bench/results/2026-11-26-session16/build.sh
