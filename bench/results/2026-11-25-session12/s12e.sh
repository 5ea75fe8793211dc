#!/bin/bash
# Session 12, call 5 (H100): M = c42c2ec. Where the settled streamed frame's extra time goes:
# `vgeo render SCENE --time 200 --stats` per pass, all resident and under --geometry-budget 64
# (30 frames to settle first), outdoor and indoor, the scenes' own cameras, 1920x1080.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo-M; chmod +x /tmp/vgeo-M
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
for s in outdoor indoor; do
  for b in none 64; do
    extra=""; [ $b != none ] && extra="--geometry-budget $b"
    for rep in 1 2; do
      echo "== $s budget=$b rep=$rep" >> $OUT/passes.txt
      timeout 60 /tmp/vgeo-M render assets/scenes/$s.toml --width 1920 --height 1080 --frames 30 --time 200 --stats $extra -o /tmp/$s-$b.png 2>&1 | grep -E "^timed|^  [a-z_]+( \(post\))? +[0-9.]+ ms|^triangles|^  main:|^  frame 30:" >> $OUT/passes.txt
    done
  done
  cmp /tmp/$s-none.png /tmp/$s-64.png >> $OUT/log.txt 2>&1 && echo "$s: streamed image equals all-resident" >> $OUT/log.txt
done
