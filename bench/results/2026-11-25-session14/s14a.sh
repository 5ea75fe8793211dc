#!/bin/bash
# Session 14, call 1 (H100): where main (2755f8e) stands on issue 14's frame goals.
#  1. the floor: nothing visible (1 and 64 materials) and one close mesh, `vgeo render --stats`
#  2. stress N=100 and N=20 at 1 and 2 px (N=20 with brute for the error), per-pass times
#  3. foliage at 1 px, the default split and software only
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-M.gz > /tmp/vgeo; chmod +x /tmp/vgeo
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
for s in empty many close; do
  echo "=== $s" >> $OUT/floor.txt
  timeout 60 /tmp/vgeo render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s.png >> $OUT/floor.txt 2>&1
done
timeout 200 /tmp/vgeo bench --suite full --scenes stress --stress-n 100 --modes vgeo --sweep 1,2 --frames 4 --quiet --out /tmp/t100 > /tmp/t100.log 2>&1
echo "== stress100 rc=$?" >> $OUT/log.txt
timeout 150 /tmp/vgeo bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1,2 --frames 4 --quiet --out /tmp/t20 > /tmp/t20.log 2>&1
echo "== stress20 rc=$?" >> $OUT/log.txt
timeout 120 /tmp/vgeo bench --suite full --scenes foliage --modes vgeo --sweep 1 --frames 8 --quiet --out /tmp/f32 > /tmp/f32.log 2>&1
echo "== foliage rc=$?" >> $OUT/log.txt
timeout 120 /tmp/vgeo bench --suite full --scenes foliage --modes vgeo --sweep 1 --frames 8 --hw-threshold 100000 --quiet --out /tmp/fsw > /tmp/fsw.log 2>&1
echo "== foliage sw rc=$?" >> $OUT/log.txt
python3 - >> $OUT/log.txt <<'PY'
import json
for d in ['/tmp/t100','/tmp/t20','/tmp/f32','/tmp/fsw']:
    try: j=json.load(open(d+'/bench.json'))
    except Exception as e: print(d, e); continue
    for s in j['summary']:
        print(d, s.get('scene'), s.get('mode'), s.get('error_px'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.02])
PY
for d in t100 t20 f32 fsw; do cp /tmp/$d/bench.md $OUT/$d-bench.md 2>/dev/null; tail -2 /tmp/$d.log >> $OUT/log.txt; done
echo "== done $SECONDS s" >> $OUT/log.txt
