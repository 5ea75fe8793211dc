#!/bin/bash
# Session 6, third H100 call: the frame floor (nothing visible; one close mesh) after the
# uncleared GBuffer, and the suite's scenes against a14910b (vgeo-old), images compared.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
for b in vgeo vgeo-old; do gunzip -c .gpu/$b.gz > .gpu/$b; chmod +x .gpu/$b; done
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/log.txt
for b in vgeo-old vgeo; do
  for s in empty many close; do
    echo "=== $b $s" >> $OUT/floor.txt
    timeout 100 ./.gpu/$b render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s.png 2>&1 | grep -v "^built" >> $OUT/floor.txt
  done
done
for b in vgeo-old vgeo; do
  mkdir -p /tmp/s-$b
  timeout 150 ./.gpu/$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage,demo --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b > /tmp/s-$b/log.txt 2>&1
  echo "== scenes $b rc=$?" >> $OUT/log.txt
  grep -E "^\| vgeo" /tmp/s-$b/bench.md >> $OUT/log.txt
done
find /tmp/s-vgeo -name '*.png' | while read s; do n=${s#/tmp/s-vgeo/}; cmp -s $s /tmp/s-vgeo-old/$n && echo "same $n" || echo "DIFF $n"; done > $OUT/images.txt 2>&1
tar czf $OUT/bench.tgz -C /tmp --exclude='*.png' s-vgeo-old s-vgeo
cat $OUT/log.txt $OUT/images.txt; grep -E "===|GPU time|emit|shade|classify" $OUT/floor.txt
