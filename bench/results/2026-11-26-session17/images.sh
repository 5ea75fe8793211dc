#!/bin/bash
# Session 17, device (1920x1080, 1 px): each scene's lit image and the close blade's, H (main
# before, 233b13b) against N (the max-delta triangle code, triangles of several materials kept
# unrotated): pixels that differ and by how much (pngdiff.py --max).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in H N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
o=$OUT/images.txt
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
for s in outdoor indoor foliage drawcalls; do
  for b in H N; do
    timeout 60 /tmp/vgeo-$b render assets/scenes/$s.toml --width 1920 --height 1080 --out /tmp/img-$s-$b.png > /dev/null 2>&1
  done
  echo "  $s: $(python3 bench/results/2026-11-26-session17/pngmax.py /tmp/img-$s-H.png /tmp/img-$s-N.png 2>&1)" >> $o
done
for b in H N; do
  timeout 60 /tmp/vgeo-$b render .gpu/close.toml --width 1920 --height 1080 --out /tmp/close-$b.png > /dev/null 2>&1
done
echo "  close: $(python3 bench/results/2026-11-26-session17/pngmax.py /tmp/close-H.png /tmp/close-N.png 2>&1)" >> $o
