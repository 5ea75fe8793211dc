#!/bin/bash
# Session 16, call 7: why S (.gpu/vgeo-S.gz, cull statistics per invocation) timed out in
# `vgeo bench` on the device in call 6: short runs with their logs.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in N S; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
o=$OUT/diag.txt
nvidia-smi > $o 2>&1
for b in S N; do
  echo "== $b render foliage --stats" >> $o
  ( time timeout 40 /tmp/vgeo-$b render assets/scenes/foliage.toml --width 1920 --height 1080 --stats --out /tmp/f-$b.png ) >> $o 2>&1
  echo "== $b bench stress 20, 2 frames" >> $o
  ( time timeout 60 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20 --frames 2 --modes vgeo --sweep 1 --out /tmp/b-$b ) 2>&1 | tail -25 >> $o
done
dmesg 2>/dev/null | grep -i xid | tail -5 >> $o
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,utilization.gpu --format=csv >> $o 2>&1
