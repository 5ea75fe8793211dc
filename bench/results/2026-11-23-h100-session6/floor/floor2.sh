#!/bin/bash
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
gunzip -c .gpu/vgeo.gz > .gpu/vgeo; chmod +x .gpu/vgeo
r() { timeout 100 ./.gpu/vgeo render .gpu/empty.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/e.png "$@" 2>&1 | grep -E "GPU time|material|emit|shade"; }
echo "== plain"; r
echo "== noop shader"; r --shader-dir .gpu/sd-noop
echo "== raster emit"; r --emit raster
echo "== view albedo"; r --view albedo
echo "== 1280x720"; timeout 100 ./.gpu/vgeo render .gpu/empty.toml --width 1280 --height 720 --stats --frames 8 --out /tmp/e.png 2>&1 | grep -E "GPU time|material|emit|shade"
echo "== buffer visbuffer"; VGEO_VISBUFFER=buffer r
