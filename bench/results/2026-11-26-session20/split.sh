#!/bin/bash
# Session 20, device: the SW/HW split chosen by measured cost (`--hw-threshold auto`, the new
# default), for issue 14 acceptance 3 (the default split no slower than software only on every
# scene). Binary N = main with frame/split.rs.
# 1. vgeo at 1 px on stress N=20 (4 frames) and the four bench scenes (8 frames), with
#    --hw-threshold auto, 64 (the old fixed default) and 100000 (software only but the near plane's
#    clusters), three interleaved rounds; bench.md's clusters column says which split auto timed.
# 2. The close blade and the empty frame (`render --time 64`) the same way.
# 3. No pixel changes: each scene's lit image after 40 frames with auto (the tuner probing along
#    the way) against the one with 64, byte for byte (pngdiff).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o N
T0=$SECONDS
warm N
for r in 1 2 3; do
  for thr in auto 64 100000; do
    if [ $((SECONDS - T0)) -gt 500 ]; then echo "== skip r$r $thr (time)" >> $o; continue; fi
    x=/tmp/thr-$thr-r$r
    timeout 90 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --frames 4 --modes vgeo --sweep 1 --hw-threshold $thr --quiet --out $x-t > $x-t.log 2>&1
    timeout 150 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --hw-threshold $thr --quiet --out $x-s > $x-s.log 2>&1
    echo "== r$r --hw-threshold $thr t=$((SECONDS - T0))" >> $o
    for y in t s; do summary $x-$y/bench.json sw hw >> $o 2>&1; done
    for y in t s; do grep -E "^\| vgeo" $x-$y/bench.md | cut -d'|' -f1-7 >> $o; done
    for s in .gpu/close.toml .gpu/empty.toml; do
      timeout 60 /tmp/vgeo-N render $s --width 1920 --height 1080 --frames 8 --time 64 --hw-threshold $thr --out /tmp/c.png 2>&1 | grep -E "timed|split" | sed "s/^/  $(basename $s .toml) /" >> $o
    done
  done
done
mkdir -p $OUT/r1-auto && cp /tmp/thr-auto-r1-s/bench.md $OUT/r1-auto/scenes.md && cp /tmp/thr-auto-r1-t/bench.md $OUT/r1-auto/stress.md
echo "== images (auto after 40 frames against 64)" >> $o
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  timeout 120 /tmp/vgeo-N render $s --width 1920 --height 1080 --frames 40 --out /tmp/img-$n-auto.png > /dev/null 2>&1
  timeout 120 /tmp/vgeo-N render $s --width 1920 --height 1080 --frames 40 --hw-threshold 64 --out /tmp/img-$n-64.png > /dev/null 2>&1
  echo "  $n: cmp $(cmp -s /tmp/img-$n-auto.png /tmp/img-$n-64.png && echo identical || echo DIFFER); $(python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/img-$n-64.png /tmp/img-$n-auto.png 2>&1)" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
