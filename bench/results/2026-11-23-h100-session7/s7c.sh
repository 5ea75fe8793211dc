#!/bin/bash
# Session 7, call 3: the local BVH walk of small instances (D) against C (the same builder and cut,
# global queue only): vgeo at 1 px, GPU ms per pass; images compared byte for byte.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in C D; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
for r in 1; do for b in C D; do
  timeout 140 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$b-s$r > /tmp/$b-s$r.log 2>&1
  echo "== $b scenes run $r rc=$?" >> $OUT/log.txt
  timeout 140 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b-t$r > /tmp/$b-t$r.log 2>&1
  echo "== $b stress run $r rc=$?" >> $OUT/log.txt
done; done
for d in C-s1 D-s1 C-t1 D-t1; do echo "=== $d" >> $OUT/log.txt; grep -E "^\| vgeo|^## " /tmp/$d/bench.md >> $OUT/log.txt; done
for s in $(cd /tmp/C-s1/images 2>/dev/null && ls); do cmp -s /tmp/C-s1/images/$s /tmp/D-s1/images/$s && echo "same $s" || echo "DIFF $s"; done > $OUT/images.txt 2>&1
for s in $(cd /tmp/C-t1/images 2>/dev/null && ls); do cmp -s /tmp/C-t1/images/$s /tmp/D-t1/images/$s && echo "same $s" || echo "DIFF $s"; done >> $OUT/images.txt 2>&1
ls /tmp/C-s1 >> $OUT/images.txt
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['C','D']:
    for d in [f'/tmp/{b}-s1', f'/tmp/{b}-t1', f'/tmp/{b}-s2', f'/tmp/{b}-t2']:
        try: j=json.load(open(d+'/bench.json'))
        except Exception as e: print(d, e); continue
        for s in j['summary']:
            print(d, s['scene'], round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
tar czf $OUT/s7c.tgz -C /tmp --exclude='*.png' C-s1 D-s1 C-t1 D-t1
