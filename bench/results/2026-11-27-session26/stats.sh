#!/bin/bash
# Session 26, device: what the driver compiled (VGEO_PIPELINE_STATS=1, VK_KHR_pipeline_executable_
# properties): every pipeline's statistics as `vgeo render` creates them on foliage (1080p, vgeo at
# 1 px), with `vgeo info`'s line on it.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stats.txt
setup $o S
/tmp/vgeo-S info 2>&1 | grep -i "pipeline stat" >> $o
VGEO_PIPELINE_STATS=1 timeout 120 /tmp/vgeo-S render assets/scenes/foliage.toml --width 1920 --height 1080 --frames 2 --stats --out /tmp/f.png > /tmp/f.log 2>&1
echo "rc=$?" >> $o
grep "pipeline statistics" /tmp/f.log >> $o
grep -E "raster_sw|GPU time" /tmp/f.log >> $o
