#!/bin/bash
# Session 10, call 1: encoded pages. B = 78f5b62 (plain-stream pages), X = encoded pages at the old
# precision (21 position bits, 16 normal bits: images must equal B's), N = encoded pages at the new
# default precision (16+ position bits, 12 normal bits). vgeo at 1 px on the scene suite.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in B X N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
MODE=${1:-scenes}
gunzip -c .gpu/vgeo-B.gz > /tmp/vgeo-B2; chmod +x /tmp/vgeo-B2
RUNS=${2:-B X N}
for b in $RUNS; do
  if [ "$MODE" = scenes ]; then
    timeout 170 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$b > /tmp/$b.log 2>&1
  else
    timeout 170 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b > /tmp/$b.log 2>&1
  fi
  echo "== $b $MODE rc=$?" >> $OUT/log.txt
done
for d in $RUNS; do echo "=== $d" >> $OUT/log.txt; grep -E "^\| vgeo|^## " /tmp/$d/bench.md >> $OUT/log.txt; tail -3 /tmp/$d.log >> $OUT/log.txt; done
for p in "B X" "B N" "B B2"; do set -- $p
  for s in $(cd /tmp/$1/images 2>/dev/null && ls); do cmp -s /tmp/$1/images/$s /tmp/$2/images/$s && echo "$1=$2 same $s" || echo "$1/$2 DIFF $s"; done >> $OUT/images.txt 2>&1
done
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['B','X','N','B2']:
    try: j=json.load(open(f'/tmp/{b}/bench.json'))
    except Exception as e: print(b, e); continue
    for s in j['summary']:
        print(b, s['scene'], 'ms', round(s['gpu_ms_mean'],3), 'psnr', s.get('psnr_db'), 'B/tri', round(s.get('bytes_per_stored_triangle') or 0,2), 'geomMiB', round(s.get('geometry_bytes',0)/2**20,1), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
if [ "$MODE" != scenes ]; then
for mib in 8 32; do
  echo "=== lucy --geometry-budget $mib" >> $OUT/stream.txt
  timeout 60 /tmp/vgeo-N render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --geometry-budget $mib --stream-mib-per-frame 4 --frames 24 --stats -o /tmp/lucy-$mib.png >> $OUT/stream.txt 2>&1
  echo "rc=$?" >> $OUT/stream.txt
done
timeout 60 /tmp/vgeo-N render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --frames 2 --stats -o /tmp/lucy-all.png >> $OUT/stream.txt 2>&1
cmp /tmp/lucy-32.png /tmp/lucy-all.png && echo "lucy 32 MiB settled == all resident" >> $OUT/stream.txt
cmp /tmp/lucy-8.png /tmp/lucy-all.png && echo "lucy 8 MiB settled == all resident" >> $OUT/stream.txt
fi
mkdir -p /tmp/dc; for b in $RUNS; do cp /tmp/$b/images/drawcalls_vgeo_1px.png /tmp/dc/$b.png 2>/dev/null; done; tar czf $OUT/s10a-$MODE.tgz -C /tmp --exclude="*.png" $RUNS; tar czf $OUT/dc.tgz -C /tmp dc
