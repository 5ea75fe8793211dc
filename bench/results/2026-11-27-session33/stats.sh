#!/bin/bash
# Session 33, device call 3: compiled statistics (VGEO_PIPELINE_STATS=1) of O's and N's pipelines
# (the close blade, one frame), and N2's shader folder.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stats.txt
setup $o
for b in O N; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
for b in O N; do
  VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-$b render .gpu/close.toml --width 640 --height 360 --out /tmp/x.png > $OUT/stats-$b.txt 2>&1
done
VGEO_PIPELINE_STATS=1 timeout 60 /tmp/vgeo-N render .gpu/close.toml --width 640 --height 360 --shader-dir .gpu/sd/N2 --out /tmp/x.png > $OUT/stats-N2.txt 2>&1
