#!/bin/bash
# Prepared in session 27 for a later session's device call (not yet run): what the hardware path
# pays for a ground box's hidden faces. foliage.toml and outdoor.toml against copies whose ground
# is the box's top face alone (ground_quad.obj; on lavapipe at 640x360 the images are identical
# to the boxes'). Each scene: `render --frames 8 --stats` (the last frame's passes, raster_hw
# among them) and `render --time 64` (the mean frame), two interleaved rounds. Carry the release
# binary as .gpu/vgeo-N.gz. If the quad halves raster_hw (0.15 ms on both scenes with the box),
# culling faces turned away in the hardware path for closed meshes seen from outside is worth
# building: foliage is 0.075 ms over its 3 ms goal.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/next.txt
setup $o N
N=bench/results/2026-11-27-session27/next
warm N
for r in 1 2; do
  for s in assets/scenes/foliage.toml $N/foliage_quad.toml assets/scenes/outdoor.toml $N/outdoor_quad.toml; do
    echo "== r$r $s" >> $o
    timeout 120 /tmp/vgeo-N render $s --width 1920 --height 1080 --frames 8 --stats --out /tmp/s.png 2>&1 | grep -E "GPU time|raster_|instance_cull|cluster_cull|emit_|depth_|shade|classify|ms" >> $o
    timeout 120 /tmp/vgeo-N render $s --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/t.png 2>&1 | grep -E "timed" >> $o
  done
done
