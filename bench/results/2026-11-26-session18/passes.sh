#!/bin/bash
# Session 18, H100 (call 3): where the close blade's frame goes (issue 14 acceptance 4: one close
# mesh at most 0.3 ms; nothing visible at most 0.1 ms), with this session's final binary
# (.gpu/vgeo.gz, stripped release build of main): each frame timed back to back (`--time 64`,
# three runs) and one frame's per-pass GPU times with the counters read (`--stats`).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo.gz > /tmp/vgeo; chmod +x /tmp/vgeo
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
for s in close empty; do
  for r in 1 2 3; do
    echo "== $s run $r" >> $OUT/log.txt
    /tmp/vgeo render .gpu/$s.toml --width 1920 --height 1080 --frames 4 --time 64 -o /tmp/$s.png 2>&1 | grep -E "timed|GPU time" >> $OUT/log.txt
  done
  echo "== $s passes" >> $OUT/log.txt
  /tmp/vgeo render .gpu/$s.toml --width 1920 --height 1080 --frames 4 --stats -o /tmp/$s.png >> $OUT/log.txt 2>&1
done
