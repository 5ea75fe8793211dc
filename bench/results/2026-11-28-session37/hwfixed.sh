#!/bin/bash
# Session 37, device call 3: indoor and foliage with the SW/HW split held (--hw-threshold 32 and
# 64) instead of chosen per run, A (f0ec5ef) against E (call 2's E: the stored grid apart from the
# build grid, the default step ratio 0.35), interleaved (A E E A A E per split).
o=$OUT/hwfixed.txt
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in A E; do python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
timeout 60 /tmp/vgeo-A bench --suite full --scenes indoor --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
T0=$SECONDS
for h in 32 64; do
  for r in Aa Ea Eb Ab Ac Ec; do
    t=${r:0:1}
    timeout 100 /tmp/vgeo-$t bench --suite full --scenes indoor,foliage --frames 4 --modes vgeo --sweep 1 --hw-threshold $h --quiet --out $OUT/$r-h$h > $OUT/$r-h$h.log 2>&1
    echo "== $r h$h rc=$? t=$((SECONDS - T0))" >> $o
  done
done
cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images . && find $OUT -mindepth 1 -delete && cp /tmp/h.tgz $OUT/h.tgz
