#!/bin/bash
# Session 14, call 3 (H100): M = main 2755f8e, Q = ae7233f (single-dispatch depth pyramid,
# post-phase pyramid skipped when the post phase drew nothing, coalesced material_classify and
# pyramid reads), R = edbc590 (Q + cluster_cull tests leaf clusters in ranges of 8 on the queue).
#  1. the floor, interleaved, `vgeo render --stats --frames 8` at 1920x1080 (3 rounds)
#  2. the suite's scenes + stress N=20/N=100 at 1 px in vgeo mode, M and R (images compared)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in M Q R; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
/tmp/vgeo-M render .gpu/close.toml --width 1920 --height 1080 --frames 60 --out /tmp/warm.png > /dev/null 2>&1
for r in 1 2 3; do for b in M Q R; do for s in empty many close; do
  echo "=== $b $s $r" >> $OUT/floor.txt
  timeout 60 /tmp/vgeo-$b render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s-$b.png 2>&1 | grep -E "GPU time|^  [a-z_]+( \(post\))? +[0-9.]+ ms|frame 8|main:" >> $OUT/floor.txt
done; done; done
for b in Q R; do for s in empty many close; do cmp /tmp/$s-M.png /tmp/$s-$b.png >> $OUT/log.txt 2>&1 && echo "same image $b $s" >> $OUT/log.txt; done; done
for b in M R; do
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,drawcalls,foliage --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/s-$b > /tmp/s-$b.log 2>&1
  echo "== scenes $b rc=$?" >> $OUT/log.txt; tail -3 /tmp/s-$b.log >> $OUT/log.txt
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/t-$b > /tmp/t-$b.log 2>&1
  echo "== stress $b rc=$?" >> $OUT/log.txt; tail -3 /tmp/t-$b.log >> $OUT/log.txt
done
for d in s t; do find /tmp/$d-R -name '*.png' | while read s; do n=${s#/tmp/$d-R/}; cmp -s $s /tmp/$d-M/$n && echo "same $n" || echo "DIFF $n"; done >> $OUT/log.txt 2>&1; done
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['M','R']:
  for d in ['s','t']:
    try: j=json.load(open(f'/tmp/{d}-{b}/bench.json'))
    except Exception as e: print(b, e); continue
    for s in j['summary']:
        print(b, s.get('scene'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.015])
PY
for b in M R; do cp /tmp/s-$b/bench.md $OUT/s-$b-bench.md; cp /tmp/t-$b/bench.md $OUT/t-$b-bench.md; done 2>/dev/null
echo "== done $SECONDS s" >> $OUT/log.txt
