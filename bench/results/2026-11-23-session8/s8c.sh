#!/bin/bash
# Session 8, call 3: build throughput, base (217d124) against ec07c8e (cur) and the crease-collapse
# experiment (C, VGEO_CREASE_PERM=1), 1 and 16 threads, 5 interleaved runs; lucy also with
# --crease-deg 180 (the same input as base: smooth normals, no splits).
for b in base cur C; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
lscpu | grep -E "Model name|^CPU\(s\)" > $OUT/log.txt
for r in 1 2 3 4 5; do for m in lucy bunny turbineblade; do for t in 16 1; do for b in base cur C; do
  e=""; [ $b = C ] && e="VGEO_CREASE_PERM=1"
  s=$(env $e /tmp/vgeo-$b build ../shared/assets/scanned/$m.ply -o /tmp/x.vgeo --threads $t --json 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "BUILD $b $m threads=$t run=$r seconds=$s" >> $OUT/build.txt
done; done; done
for t in 16 1; do s=$(/tmp/vgeo-cur build ../shared/assets/scanned/lucy.ply -o /tmp/x.vgeo --threads $t --crease-deg 180 --json 2>/dev/null | grep '"seconds"' | tr -dc '0-9.'); echo "BUILD cur-c180 lucy threads=$t run=$r seconds=$s" >> $OUT/build.txt; done
done
python3 - >> $OUT/log.txt <<'PY'
import collections, statistics, os
d = collections.defaultdict(list)
for l in open(os.environ['OUT'] + '/build.txt'):
    p = l.split(); d[(p[1], p[2], p[3])].append(float(p[5].split('=')[1]))
for (b, m, t), v in sorted(d.items(), key=lambda x: (x[0][1], x[0][2], x[0][0])):
    base = statistics.median(d[('base', m, t)])
    print(f"{m:13s} {t:10s} {b:8s} median {statistics.median(v):.4f} s  {100*(statistics.median(v)/base-1):+.0f} % vs base")
PY
