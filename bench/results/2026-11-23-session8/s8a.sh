#!/bin/bash
# Session 8, call 1: tiny clusters rasterized in the cull passes (T, default) against the same
# binary with --no-tiny-raster (N) and session 7's final binary (F): vgeo 1 px, images compared.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in F T; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
run() { # name binary extra-args [scenes-only]
  timeout 150 /tmp/vgeo-$2 bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$1-s $3 > /tmp/$1-s.log 2>&1
  echo "== $1 scenes rc=$?" >> $OUT/log.txt
  [ -n "$4" ] && return
  timeout 200 /tmp/vgeo-$2 bench --suite full --scenes stress --stress-n 20,100,200 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$1-t $3 > /tmp/$1-t.log 2>&1
  echo "== $1 stress rc=$?" >> $OUT/log.txt
}
run T T ""
run N T --no-tiny-raster
run F F "" scenes-only
for b in N F; do for d in s t; do [ -d /tmp/$b-$d ] || continue; for s in $(cd /tmp/T-$d/images && ls); do cmp -s /tmp/T-$d/images/$s /tmp/$b-$d/images/$s && echo "same $b $s" || echo "DIFF $b $s"; done; done; done > $OUT/images.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ["T","N","F"]:
    for d in [f'/tmp/{b}-s', f'/tmp/{b}-t']:
        try: j=json.load(open(d+'/bench.json'))
        except Exception as e: print(d, e); continue
        for s in j['summary']:
            print(b, s['scene'], round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
cp /tmp/T-s.log /tmp/T-t.log $OUT/ 2>/dev/null
tar czf $OUT/s8a.tgz -C /tmp --exclude='*.png' T-s T-t N-s N-t F-s F-t
