#!/bin/bash
# Session 14, call 6 (H100): G = 7874ed5 (main with both branches merged).
#  1. the scenes at 1 px in vgeo mode with call 3's settings (16 frames): does the merge cost
#     raster_hw anything against R (edbc590, call 3)?
#  2. stream.sh: the cold camera cut (issue 13 acceptance 2) at 4, 8 and 16 unique meshes.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo.gz > /tmp/vgeo; chmod +x /tmp/vgeo
timeout 100 /tmp/vgeo bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-G > /tmp/s-G.log 2>&1
echo "rc=$?" > $OUT/ab.txt
python3 - >> $OUT/ab.txt <<'PY'
import json
j=json.load(open('/tmp/s-G/bench.json'))
for s in j['summary']:
    print('G', s.get('scene'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.015])
PY
OUT_MAIN=$OUT
bash bench/results/2026-11-25-session14/stream.sh
cat $OUT_MAIN/ab.txt >> $OUT_MAIN/log.txt
