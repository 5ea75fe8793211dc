#!/bin/bash
# Session 15 (H100), after call 5: the hardware rasterizer is given raster_sw's snapped vertex
# (common/raster.glsl::hw_position) instead of the clip position. Same binary as call 5
# (.gpu/vgeo-M.gz) with VGEO_SHADER_DIR=.gpu/hwpos (the three changed shader files). Per scene,
# view triangles: --raster sw, --raster hw (vertex pulling), --raster hw --hw-path mesh and auto;
# pngdiff.py counts the pixels that differ from sw's. Lit images of foliage too.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo; chmod +x /tmp/vgeo; V=/tmp/vgeo
export VGEO_SHADER_DIR=$PWD/.gpu/hwpos
T0=$SECONDS
for s in outdoor indoor drawcalls foliage; do
  views=triangles; [ $s = foliage ] && views="triangles lit"
  for view in $views; do
    for r in sw hw hwmesh auto; do
      case $r in hwmesh) a="--raster hw --hw-path mesh";; *) a="--raster $r";; esac
      timeout 90 $V render assets/scenes/$s.toml --width 1920 --height 1080 --view $view $a --out /tmp/$s-$view-$r.png > /tmp/$s-$view-$r.log 2>&1
      echo "render $s $view $r rc=$? t=$((SECONDS - T0))" >> $OUT/swhw2.txt
      [ $r = sw ] && grep -i "error\|warn" /tmp/$s-$view-$r.log | head -3 >> $OUT/swhw2.txt
    done
    python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/$s-$view-sw.png /tmp/$s-$view-hw.png /tmp/$s-$view-hwmesh.png /tmp/$s-$view-auto.png >> $OUT/swhw2.txt 2>&1
  done
done
echo "== total $((SECONDS - T0)) s" >> $OUT/swhw2.txt
