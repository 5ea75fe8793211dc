#!/bin/bash
# Session 9, call 1: geometry pages (P) against the build before them (O = ec07c8e): vgeo at 1 px,
# GPU ms per pass, images compared byte for byte; then P streaming under budgets.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in O P; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv | tee $OUT/log.txt
for r in 1; do for b in O P; do
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$b-s$r > /tmp/$b-s$r.log 2>&1
  echo "== $b scenes run $r rc=$?" >> $OUT/log.txt
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b-t$r > /tmp/$b-t$r.log 2>&1
  echo "== $b stress run $r rc=$?" >> $OUT/log.txt
done; done
for d in O-s1 P-s1 O-t1 P-t1; do echo "=== $d" >> $OUT/log.txt; grep -E "^\| vgeo|^## " /tmp/$d/bench.md >> $OUT/log.txt; tail -3 /tmp/$d.log >> $OUT/log.txt; done
for s in $(cd /tmp/O-s1/images 2>/dev/null && ls); do cmp -s /tmp/O-s1/images/$s /tmp/P-s1/images/$s && echo "same $s" || echo "DIFF $s"; done > $OUT/images.txt 2>&1
for s in $(cd /tmp/O-t1/images 2>/dev/null && ls); do cmp -s /tmp/O-t1/images/$s /tmp/P-t1/images/$s && echo "same $s" || echo "DIFF $s"; done >> $OUT/images.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['O','P']:
    for d in [f'/tmp/{b}-s1', f'/tmp/{b}-t1', f'/tmp/{b}-s2', f'/tmp/{b}-t2']:
        try: j=json.load(open(d+'/bench.json'))
        except Exception as e: print(d, e); continue
        for s in j['summary']:
            print(d, s['scene'], round(s['gpu_ms_mean'],3), s.get('bytes_per_stored_triangle'), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
# Streaming on the H100: lucy under budgets, 24 frames.
for mib in 8 32; do
  echo "=== lucy --geometry-budget $mib" >> $OUT/stream.txt
  timeout 100 /tmp/vgeo-P render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --geometry-budget $mib --stream-mib-per-frame 4 --frames 24 --stats -o /tmp/lucy-$mib.png >> $OUT/stream.txt 2>&1
  echo "rc=$?" >> $OUT/stream.txt
done
timeout 100 /tmp/vgeo-P render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --frames 2 --stats -o /tmp/lucy-all.png >> $OUT/stream.txt 2>&1
cmp /tmp/lucy-32.png /tmp/lucy-all.png && echo "lucy 32 MiB settled == all resident" >> $OUT/stream.txt
cmp /tmp/lucy-8.png /tmp/lucy-all.png && echo "lucy 8 MiB settled == all resident" >> $OUT/stream.txt
tar czf $OUT/s9a.tgz -C /tmp --exclude='*.png' O-s1 P-s1 O-t1 P-t1 O-s2 P-s2 O-t2 P-t2
