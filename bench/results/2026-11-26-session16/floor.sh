#!/bin/bash
# Session 16, call 11 (H100, 1920x1080, 1 px): issue 14 acceptance 4's two frames timed as the
# bench times (`render --time 64`: back to back after a warm-up, render_path_timed, so without the
# cull's statistics since 59f10e4), the close turbine blade and a frame with nothing visible, each
# three times; and the same frames' single read-back figure (`--stats`, statistics on).
# .gpu/vgeo-S.gz is 59f10e4's code.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-S.gz > /tmp/vgeo; chmod +x /tmp/vgeo
o=$OUT/floor.txt
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
for r in 1 2 3; do
  for s in close empty; do
    echo "== $s r$r" >> $o
    timeout 60 /tmp/vgeo render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --stats --time 64 --out /tmp/$s.png 2>&1 | grep -E "GPU time|timed" >> $o
  done
done
