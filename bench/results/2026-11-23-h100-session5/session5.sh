#!/bin/bash
# Session 5 H100 run: the suite's GPU figures before (vgeo-new: the session-4 build, the frame of
# session 3) and after (vgeo: this commit, embedding + dynamic scene merged), vgeo mode at 1 px,
# interleaved; the first run (demo) timing.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
./.gpu/vgeo info 2>&1 | tee -a $OUT/log.txt
for r in 1 2; do
  for b in vgeo-new vgeo; do
    mkdir -p /tmp/s-$b-$r
    timeout 150 ./.gpu/$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b-$r > /tmp/s-$b-$r/log.txt 2>&1
    echo "== scenes $b run $r rc=$?" >> $OUT/log.txt
    grep -E "^\|" /tmp/s-$b-$r/bench.md | head -40 >> $OUT/log.txt
  done
done
for b in vgeo-new vgeo; do
  mkdir -p /tmp/t-$b
  timeout 150 ./.gpu/$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/t-$b > /tmp/t-$b/log.txt 2>&1
  echo "== stress $b rc=$?" >> $OUT/log.txt
  grep -E "^\|" /tmp/t-$b/bench.md | head -40 >> $OUT/log.txt
done
# Images of the two builds: identical means the same cut, so the same error as measured before.
for s in /tmp/s-vgeo-1/*.png; do n=$(basename $s); cmp -s $s /tmp/s-vgeo-new-1/$n && echo "same $n" || echo "DIFF $n"; done >> $OUT/images.txt 2>&1
( time ./.gpu/vgeo ) >> $OUT/demo.txt 2>&1
tar czf $OUT/bench.tgz -C /tmp --exclude='*.png' s-vgeo-new-1 s-vgeo-1 s-vgeo-new-2 s-vgeo-2 t-vgeo-new t-vgeo
