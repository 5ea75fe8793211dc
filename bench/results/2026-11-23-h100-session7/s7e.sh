#!/bin/bash
# Session 7, call 4: the local walk also in the post phase (E16) and with up to 64 clusters (E64)
# against D (main phase only, 16): vgeo 1 px; images compared byte for byte with D's.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in D F; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
for b in D F; do
  timeout 120 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$b-s > /tmp/$b-s.log 2>&1
  echo "== $b scenes rc=$?" >> $OUT/log.txt
  timeout 120 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b-t > /tmp/$b-t.log 2>&1
  echo "== $b stress rc=$?" >> $OUT/log.txt
done
for b in F; do for d in s t; do for s in $(cd /tmp/D-$d/images && ls); do cmp -s /tmp/D-$d/images/$s /tmp/$b-$d/images/$s && echo "same $b $s" || echo "DIFF $b $s"; done; done; done > $OUT/images.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ["D","F"]:
    for d in [f'/tmp/{b}-s', f'/tmp/{b}-t']:
        try: j=json.load(open(d+'/bench.json'))
        except Exception as e: print(d, e); continue
        for s in j['summary']:
            print(b, s['scene'], round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
tar czf $OUT/s7e.tgz -C /tmp --exclude='*.png' D-s D-t F-s F-t
