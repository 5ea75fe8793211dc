#!/bin/bash
# Session 19, device (1920x1080, 1 px): raster_hw's vertex path over the cull's triangle list (N,
# .gpu/vgeo-N.gz) against main before it (B, .gpu/vgeo-B.gz: MAX_CLUSTER_TRIANGLES * 3 vertices
# per HW cluster). Issue 14 acceptance 3: every cluster to hardware (--hw-threshold 0) within 3x of
# the hybrid on foliage and stress N=100; the default split no slower than software only; mesh
# shaders against the vertex path. Then the close blade and the empty frame (acceptance 4), and
# images of N against B (hybrid on every scene, all-HW on foliage).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/hw.txt
setup $o B N
T0=$SECONDS
warm N
echo "== warm t=$((SECONDS - T0))" >> $o
# name:binary:--hw-threshold:--hw-path
CONFIGS="hw0-vertex:B:0:vertex hw0-vertex:N:0:vertex hw0-mesh:N:0:mesh default:B:64:auto default:N:64:auto swonly:N:100000:auto"
for scene in foliage stress; do
  extra="--frames 8"; limit=80
  [ $scene = stress ] && extra="--stress-n 100 --frames 4" && limit=100
  for cfg in $CONFIGS; do
    IFS=: read name b thr path <<< "$cfg"
    if [ $((SECONDS - T0 + limit)) -gt 400 ]; then echo "== skip $scene $name $b (time)" >> $o; continue; fi
    d=/tmp/hw-$scene-$name-$b; T1=$SECONDS
    timeout $limit /tmp/vgeo-$b bench --suite full --scenes $scene $extra --modes vgeo --sweep 1 \
      --hw-threshold $thr --hw-path $path --quiet --out $d > $d.log 2>&1
    echo "== $scene $name $b (--hw-threshold $thr --hw-path $path) rc=$? in $((SECONDS - T1)) s" >> $o
    summary $d/bench.json sw hw tris >> $o 2>&1 || tail -3 $d.log >> $o
    grep -E "^\| vgeo" $d/bench.md >> $o 2>/dev/null
    cp $d/bench.json $OUT/$scene-$name-$b.json 2>/dev/null
  done
done
for s in close empty; do
  for b in B N B N; do
    timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$b.png 2>&1 | grep -E "timed" | sed "s/^/  $s $b /" >> $o
  done
done
echo "== images (lit, 1920x1080, 1 px): pixels of N that differ from B, t=$((SECONDS - T0))" >> $o
if [ $((SECONDS - T0)) -lt 500 ]; then
  compare_images $o bench/results/2026-11-25-session15/pngdiff.py
  for b in B N; do
    timeout 60 /tmp/vgeo-$b render assets/scenes/foliage.toml --width 1920 --height 1080 --hw-threshold 0 --out /tmp/f0-$b.png > /dev/null 2>&1
  done
  echo "  foliage all-HW: $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/f0-B.png /tmp/f0-N.png 2>&1)" >> $o
fi
echo "== total $((SECONDS - T0)) s" >> $o
