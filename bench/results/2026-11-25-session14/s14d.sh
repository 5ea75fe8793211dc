#!/bin/bash
# Session 14, call 5 (H100): F = c0b84ac (main with the floor, the cull ranges, the mesh-shader
# path merged and auto = vertex).
#  1. the floor, `vgeo render --stats --frames 8` at 1920x1080, 3 rounds
#  2. the suite at 1 px in brute, lod and vgeo against brute at 4x4 spp (8 frames), stress N=20
#     (brute, vgeo) and N=100 (vgeo)
#  3. the SW/HW split: vgeo at 1 px with --hw-threshold 16, 64, 128 and software only
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
V=/tmp/vgeo; cp .gpu/vgeo $V; chmod +x $V
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
$V render .gpu/close.toml --width 1920 --height 1080 --frames 60 --out /tmp/warm.png > /dev/null 2>&1
for r in 1 2 3; do for s in empty many close; do
  echo "=== F $s $r" >> $OUT/floor.txt
  timeout 60 $V render .gpu/$s.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/$s.png 2>&1 | grep -E "GPU time|^  [a-z_]+( \(post\))? +[0-9.]+ ms|main:" >> $OUT/floor.txt
done; done
timeout 200 $V bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,lod,vgeo --sweep 1 --frames 8 --quiet --out /tmp/N > /tmp/N.log 2>&1
echo "== scenes rc=$? $SECONDS s" >> $OUT/log.txt
timeout 150 $V bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1 --frames 4 --quiet --out /tmp/Ns > /tmp/Ns.log 2>&1
echo "== stress20 rc=$? $SECONDS s" >> $OUT/log.txt
timeout 60 $V bench --suite full --scenes stress --stress-n 100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/Nt > /tmp/Nt.log 2>&1
echo "== stress100 rc=$? $SECONDS s" >> $OUT/log.txt
for t in 16 64 128 100000; do
  timeout 60 $V bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 8 --hw-threshold $t --quiet --out /tmp/h$t > /tmp/h$t.log 2>&1
  echo "== hw-threshold $t rc=$? $SECONDS s" >> $OUT/log.txt
done
python3 - >> $OUT/log.txt <<'PY'
import json
for d in ['N','Ns','Nt','h16','h64','h128','h100000']:
    try: j=json.load(open(f'/tmp/{d}/bench.json'))
    except Exception as e: print(d, e); continue
    for s in j['summary']:
        if s.get('mode')!='vgeo': continue
        print(d, s.get('scene'), round(s['gpu_ms_mean'],3), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.015])
PY
cp /tmp/N/bench.md $OUT/N-bench.md; cp /tmp/Ns/bench.md $OUT/Ns-bench.md; cp /tmp/Nt/bench.md $OUT/Nt-bench.md
tar czf $OUT/jsons.tgz -C /tmp N/bench.json Ns/bench.json Nt/bench.json h16/bench.json h64/bench.json h128/bench.json h100000/bench.json 2>/dev/null
echo "== done $SECONDS s" >> $OUT/log.txt
