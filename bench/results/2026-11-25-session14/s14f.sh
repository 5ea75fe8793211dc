#!/bin/bash
# Session 14, call 7 (H100): G = 7874ed5 against H = bba7dcd (a triangle that cannot be snapped
# carries its depth plane, one dot product a fragment), vgeo at 1 px, call 3's settings (16 frames),
# interleaved, images compared.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in G H; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
for r in 1 2; do for b in G H; do
  timeout 100 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b-$r > /tmp/s-$b-$r.log 2>&1
  echo "== $b $r rc=$?" >> $OUT/log.txt
done; done
find /tmp/s-H-1 -name '*.png' | while read s; do n=${s#/tmp/s-H-1/}; cmp -s $s /tmp/s-G-1/$n && echo "same $n" || echo "DIFF $n"; done >> $OUT/log.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for r in [1,2]:
  for b in ['G','H']:
    j=json.load(open(f'/tmp/s-{b}-{r}/bench.json'))
    for s in j['summary']:
        print(b, r, s.get('scene'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if n.startswith('raster_hw')])
PY
