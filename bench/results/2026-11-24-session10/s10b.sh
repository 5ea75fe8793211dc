#!/bin/bash
# Session 10, call 2: B (78f5b62) against N (encoded pages, default precision): image error of
# vgeo at 1 px against the 4x4-spp brute reference on the scene suite; the stress grid (N=20, 100);
# lucy streamed under budgets with N.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in B N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/log.txt
for b in B N; do
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,vgeo --sweep 1 --frames 8 --quiet --out /tmp/$b-e > /tmp/$b-e.log 2>&1
  echo "== $b error rc=$?" >> $OUT/log.txt
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b-t > /tmp/$b-t.log 2>&1
  echo "== $b stress rc=$?" >> $OUT/log.txt
done
python3 - >> $OUT/log.txt <<'PY'
import json
for d in ['B-e','N-e','B-t','N-t']:
    try: j=json.load(open(f'/tmp/{d}/bench.json'))
    except Exception as e: print(d, e); continue
    for s in j['summary']:
        print(d, s['scene'], s['mode'], s['error_px'], 'ms', round(s['gpu_ms_mean'],3), 'psnr', s.get('psnr_db') and round(s['psnr_db'],2), 'B/tri', round(s.get('bytes_per_stored_triangle') or 0,2), 'tris', round(s['triangles_mean']), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
for s in $(cd /tmp/B-t/images 2>/dev/null && ls); do cmp -s /tmp/B-t/images/$s /tmp/N-t/images/$s && echo "same $s" || echo "DIFF $s"; done >> $OUT/log.txt 2>&1
for mib in 8 32; do
  echo "=== lucy --geometry-budget $mib" >> $OUT/stream.txt
  timeout 60 /tmp/vgeo-N render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --geometry-budget $mib --stream-mib-per-frame 4 --frames 24 --stats -o /tmp/lucy-$mib.png >> $OUT/stream.txt 2>&1
  echo "rc=$?" >> $OUT/stream.txt
done
timeout 60 /tmp/vgeo-N render ../shared/assets/scanned/lucy.ply --width 1920 --height 1080 --frames 2 --stats -o /tmp/lucy-all.png >> $OUT/stream.txt 2>&1
cmp /tmp/lucy-32.png /tmp/lucy-all.png && echo "lucy 32 MiB settled == all resident" >> $OUT/stream.txt
cmp /tmp/lucy-8.png /tmp/lucy-all.png && echo "lucy 8 MiB settled == all resident" >> $OUT/stream.txt
tar czf $OUT/s10b.tgz -C /tmp --exclude='*.png' B-e N-e B-t N-t
