#!/bin/bash
# Session 15 (H100): do the SW and HW rasterizers give the same image on the H100? (On lavapipe
# tests/frame.rs checks the visibility buffers bit for bit.) `vgeo render` of outdoor, indoor,
# foliage and drawcalls at 1920x1080, 1 px, with --raster sw, --raster hw and auto (the default
# split), views lit and triangles (a colour per triangle: any visibility difference shows), then
# pngdiff.py counts the pixels that differ from --raster sw's. Binary: .gpu/vgeo-M.gz.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo; chmod +x /tmp/vgeo; V=/tmp/vgeo
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/swhw.txt 2>&1
T0=$SECONDS
for s in outdoor indoor drawcalls foliage; do
  for view in triangles lit; do
    for r in sw hw auto; do
      timeout 90 $V render assets/scenes/$s.toml --width 1920 --height 1080 --view $view --raster $r --out /tmp/$s-$view-$r.png > /tmp/$s-$view-$r.log 2>&1
      echo "render $s $view $r rc=$? t=$((SECONDS - T0))" >> $OUT/swhw.txt
    done
    python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/$s-$view-sw.png /tmp/$s-$view-hw.png /tmp/$s-$view-auto.png >> $OUT/swhw.txt 2>&1
  done
done
# The first differing scene's images come back for a look.
for s in outdoor indoor drawcalls foliage; do
  if grep -q "$s-triangles-hw.png: [1-9]" $OUT/swhw.txt; then
    cp /tmp/$s-triangles-sw.png /tmp/$s-triangles-hw.png $OUT/ 2>/dev/null; break
  fi
done
echo "== total $((SECONDS - T0)) s" >> $OUT/swhw.txt
