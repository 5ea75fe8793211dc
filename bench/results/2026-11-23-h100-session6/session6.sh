#!/bin/bash
# Session 6 H100 run: before (vgeo-old: a14910b, session 5) and after (vgeo: this commit, the
# two-dispatch depth_pyramid): the CPU cost of a host's frame, and the suite's GPU figures at 1 px
# (vgeo mode), interleaved; images compared (same HZB, so the same cut and image).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
for b in vgeo vgeo-old; do gunzip -c .gpu/$b.gz > .gpu/$b; chmod +x .gpu/$b; done
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/log.txt
lscpu | grep -E "Model name|^CPU\(s\)|MHz" | tee -a $OUT/log.txt
for r in 1 2; do
  for b in vgeo-old vgeo; do
    timeout 120 ./.gpu/$b bench --suite full --record-cpu 8000,1000000 --record-changed 0 --frames 100 --out /tmp/rc-$b-$r > /tmp/rc-$b-$r.txt 2>&1
    echo "== record $b run $r rc=$?" >> $OUT/log.txt
    grep -E "^\|" /tmp/rc-$b-$r/record_cpu.md >> $OUT/log.txt
  done
done
timeout 150 ./.gpu/vgeo bench --suite full --record-cpu 8000,125000,1000000 --record-changed 0,10000 --frames 100 --out /tmp/rc-full > /tmp/rc-full.txt 2>&1
echo "== record full rc=$?" >> $OUT/log.txt
cp /tmp/rc-full/record_cpu.md /tmp/rc-full/record_cpu.json $OUT/ 2>/dev/null
for r in 1 2; do
  for b in vgeo-old vgeo; do
    mkdir -p /tmp/s-$b-$r
    timeout 150 ./.gpu/$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage,demo --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b-$r > /tmp/s-$b-$r/log.txt 2>&1
    echo "== scenes $b run $r rc=$?" >> $OUT/log.txt
    grep -E "^\|" /tmp/s-$b-$r/bench.md | head -40 >> $OUT/log.txt
  done
done
find /tmp/s-vgeo-1 -name '*.png' | while read s; do n=${s#/tmp/s-vgeo-1/}; cmp -s $s /tmp/s-vgeo-old-1/$n && echo "same $n" || echo "DIFF $n"; done > $OUT/images.txt 2>&1
tar czf $OUT/bench.tgz -C /tmp --exclude='*.png' s-vgeo-old-1 s-vgeo-1 s-vgeo-old-2 s-vgeo-2 rc-vgeo-old-1 rc-vgeo-1 rc-vgeo-old-2 rc-vgeo-2
