#!/bin/bash
# Session 8, call 7: build times, base (217d124), cur (ec07c8e) and new (parallel preparation),
# 1 and 16 threads, 5 interleaved runs; then `cargo bench --bench build` (new) incl. torus10M.
for b in base cur new; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/buildbench.gz > /tmp/buildbench; chmod +x /tmp/buildbench
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
lscpu | grep -E "Model name|^CPU\(s\)" > $OUT/log.txt
for r in 1 2 3 4 5; do for m in lucy bunny turbineblade; do for t in 16 1; do for b in base cur new; do
  s=$(/tmp/vgeo-$b build ../shared/assets/scanned/$m.ply -o /tmp/x.vgeo --threads $t --json 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "BUILD $b $m threads=$t run=$r seconds=$s" >> $OUT/build.txt
done; done; done; done
python3 - >> $OUT/log.txt <<'PY'
import collections, statistics, os
d = collections.defaultdict(list)
for l in open(os.environ['OUT'] + '/build.txt'):
    p = l.split(); d[(p[1], p[2], p[3])].append(float(p[5].split('=')[1]))
for (b, m, t), v in sorted(d.items(), key=lambda x: (x[0][1], x[0][2], x[0][0])):
    base = statistics.median(d[('base', m, t)])
    print(f"{m:13s} {t:10s} {b:6s} median {statistics.median(v):.4f} s  {100*(statistics.median(v)/base-1):+.0f} % vs base")
PY
VGEO_SHARED_ASSETS=$PWD/.gpu/assets /tmp/buildbench --bench >> $OUT/log.txt 2>&1
VGEO_PHASES=1 /tmp/buildbench --bench torus10M >> $OUT/log.txt 2> $OUT/phases10M.txt
