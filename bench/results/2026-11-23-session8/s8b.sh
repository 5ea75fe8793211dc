#!/bin/bash
# Session 8, call 2: tiny clusters (any triangle count) rasterized in the cull when their bound is at
# most 2, 4 or 8 px across (P2, P4, P8) against P4 with --no-tiny-raster (N): vgeo 1 px.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in P2 P4 P8; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
run() { # name binary extra-args
  timeout 100 /tmp/vgeo-$2 bench --suite full --scenes outdoor,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$1-s $3 > /tmp/$1-s.log 2>&1
  echo "== $1 scenes rc=$?" >> $OUT/log.txt
  timeout 100 /tmp/vgeo-$2 bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$1-t $3 > /tmp/$1-t.log 2>&1
  echo "== $1 stress rc=$?" >> $OUT/log.txt
}
run N P4 --no-tiny-raster
run P2 P2 ""
run P4 P4 ""
run P8 P8 ""
for b in P2 P4 P8; do for d in s t; do [ -d /tmp/$b-$d ] || continue; for s in $(cd /tmp/N-$d/images && ls); do cmp -s /tmp/N-$d/images/$s /tmp/$b-$d/images/$s && echo "same $b $s" || echo "DIFF $b $s"; done; done; done > $OUT/images.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ["N","P2","P4","P8"]:
    for d in [f'/tmp/{b}-s', f'/tmp/{b}-t']:
        try: j=json.load(open(d+'/bench.json'))
        except Exception as e: print(d, e); continue
        for s in j['summary']:
            print(b, s['scene'], round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
tar czf $OUT/s8b.tgz -C /tmp --exclude='*.png' N-s N-t P2-s P2-t P4-s P4-t P8-s P8-t
