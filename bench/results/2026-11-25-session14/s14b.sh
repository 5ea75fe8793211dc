#!/bin/bash
# Session 14, call 2 (H100): the frame floor, M = main 2755f8e against P = c85ee5e (single-dispatch
# depth pyramid, post-phase pyramid skipped when the post phase drew nothing, coalesced
# material_classify), interleaved, `vgeo render --stats --frames 8` at 1920x1080; then the suite's
# scenes at 1 px in vgeo mode (images compared byte for byte).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in M P; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
for r in 1 2; do for b in M P; do for s in empty many close; do
  echo "=== $b $s $r" >> $OUT/floor.txt
  timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s-$b.png 2>&1 | grep -E "GPU time|^  [a-z_]+( \(post\))? +[0-9.]+ ms|frame 8" >> $OUT/floor.txt
done; done; done
for s in empty many close; do cmp /tmp/$s-M.png /tmp/$s-P.png >> $OUT/log.txt 2>&1 && echo "same image $s" >> $OUT/log.txt; done
for b in M P; do
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b > /tmp/s-$b.log 2>&1
  echo "== scenes $b rc=$?" >> $OUT/log.txt
done
find /tmp/s-P -name '*.png' | while read s; do n=${s#/tmp/s-P/}; cmp -s $s /tmp/s-M/$n && echo "same $n" || echo "DIFF $n"; done >> $OUT/log.txt 2>&1
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['M','P']:
    try: j=json.load(open(f'/tmp/s-{b}/bench.json'))
    except Exception as e: print(b, e); continue
    for s in j['summary']:
        print(b, s.get('scene'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.015])
PY
echo "== done $SECONDS s" >> $OUT/log.txt
