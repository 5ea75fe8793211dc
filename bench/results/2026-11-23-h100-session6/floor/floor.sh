#!/bin/bash
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
gunzip -c .gpu/vgeo.gz > .gpu/vgeo; chmod +x .gpu/vgeo
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for s in empty many close; do
  echo "=== $s"; timeout 100 ./.gpu/vgeo render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s.png 2>&1 | grep -v "^built"
done
