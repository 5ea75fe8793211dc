#!/bin/bash
# Session 15 (issue 14 item 4: the SW/HW split chosen by measured cost), H100, 1920x1080.
# S = branch `split`: a cluster goes to the hardware rasterizer when its triangles' edge-length
# equivalent (sqrt(2 x their area-weighted mean area), stored by the builder, projected at the
# cluster's nearest point) exceeds --hw-threshold pixels. H = bba7dcd (main's frame: the old
# estimate, cluster diameter / sqrt(triangles / 2)), run in the same call as the baseline.
# Binaries: .gpu/vgeo-S.gz (required), .gpu/vgeo-H.gz (optional). vgeo at 1 px, `vgeo bench
# --suite full --modes vgeo --sweep 1`, per configuration two runs: the scenes outdoor, indoor,
# foliage, drawcalls (8 frames) and stress N=20 and N=100 (4 frames).
#   round 1: S at --hw-threshold 8, 16, 32, 64; S software only (100000: only near-plane clusters
#            to HW); S hardware only (0); H at 32 (its default)
#   round 2 (noise): S at 16, 32, 64 and H at 32 again, while the time budget lasts
# A run starts only if it ends within 540 s even at its timeout. Images of every configuration
# are compared with S at 32's (the split must not change a pixel: SW and HW are bit-identical).
# Outputs ($OUT, 4 files): log.txt (device, runs, image comparison), summary.txt (GPU ms per
# scene and configuration, clusters to HW, raster passes), bench-S32.md, jsons.tgz (bench.json
# of every run).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in S H; do
  if [ -f .gpu/vgeo-$b.gz ]; then gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; fi
done
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > $OUT/log.txt 2>&1
/tmp/vgeo-S info >> $OUT/log.txt 2>&1
T0=$(date +%s)
mkdir -p /tmp/split
# One configuration: binary, threshold, round.
run() {
  local b=$1 t=$2 r=$3
  local V=/tmp/vgeo-$b
  [ -x $V ] || { echo "== skip $b $t: no binary" >> $OUT/log.txt; return; }
  for part in scenes stress; do
    local args="--scenes outdoor,indoor,foliage,drawcalls --frames 8" limit=90
    [ $part = stress ] && args="--scenes stress --stress-n 20,100 --frames 4" && limit=90
    if [ $(( $(date +%s) - T0 + limit )) -gt 540 ]; then
      echo "== skip $b $t $part r$r (time budget)" >> $OUT/log.txt; continue
    fi
    local d=/tmp/split/$b-$t-$part-r$r T1=$(date +%s)
    timeout $limit $V bench --suite full $args --modes vgeo --sweep 1 --hw-threshold $t \
      --quiet --out $d > $d.log 2>&1
    echo "== $b --hw-threshold $t $part r$r rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
    tail -1 $d.log >> $OUT/log.txt
  done
}
# Warm-up (GPU clocks).
/tmp/vgeo-S bench --suite full --scenes outdoor --modes vgeo --sweep 1 --frames 8 --quiet --out /tmp/split/warm > /dev/null 2>&1
for t in 32 8 16 64 100000 0; do run S $t 1; done
run H 32 1
for t in 16 32 64; do run S $t 2; done
run H 32 2
echo "== total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
# Images against S at 32 (round 1).
for d in /tmp/split/*-r1 /tmp/split/*-r2; do
  [ -d $d ] || continue
  part=${d%-r*}; part=${part##*-}
  ref=/tmp/split/S-32-$part-r1
  n=0; diff=0
  for s in $(cd $d && find . -name '*.png'); do
    n=$((n + 1)); cmp -s $d/$s $ref/$s || diff=$((diff + 1))
  done
  echo "images $(basename $d): $diff of $n differ from S-32-$part-r1" >> $OUT/log.txt
done
cp /tmp/split/S-32-scenes-r1/bench.md $OUT/bench-S32.md 2>/dev/null
cat /tmp/split/S-32-stress-r1/bench.md >> $OUT/bench-S32.md 2>/dev/null
tar czf $OUT/jsons.tgz -C /tmp/split $(cd /tmp/split && ls -d *-r? | sed 's|$|/bench.json|') 2>/dev/null
python3 - > $OUT/summary.txt 2>&1 <<'PY'
import json, glob, os, re
rows = {}   # scene -> {config: (ms, hw, clusters, sw_ms, hw_ms)}
configs = []
for d in sorted(glob.glob('/tmp/split/*-r?')):
    m = re.match(r'(\w)-(\d+)-(scenes|stress)-r(\d)', os.path.basename(d))
    if not m:
        continue
    b, t, _, r = m.groups()
    cfg = f'{b}{t}' + ('' if r == '1' else f'.r{r}')
    try:
        j = json.load(open(d + '/bench.json'))
    except Exception as e:
        print(d, 'no bench.json:', e)
        continue
    if cfg not in configs:
        configs.append(cfg)
    for s in j['summary']:
        if s.get('mode') != 'vgeo':
            continue
        p = dict()
        for n, ms in s['passes_mean']:
            k = n.split(' ')[0]
            p[k] = p.get(k, 0.0) + ms
        rows.setdefault(s['scene'], {})[cfg] = (s['gpu_ms_mean'], s.get('hw_clusters_mean'),
            s.get('clusters_mean'), p.get('raster_sw', 0.0), p.get('raster_hw', 0.0),
            s['triangles_mean'])
def order(c):
    b, rest = c[0], c[1:]
    t, _, r = rest.partition('.')
    return (r, b != 'S', int(t) if t != '0' else -1)
configs.sort(key=order)
print('vgeo at 1 px, GPU ms (mean over the path); S = split by triangle size, H = old estimate;')
print('S0 = all to HW, S100000 = software only (near-plane clusters still HW)\n')
print(f"{'scene':<14}" + ''.join(f'{c:>10}' for c in configs))
for sc in sorted(rows):
    print(f'{sc:<14}' + ''.join(f"{rows[sc][c][0]:>10.3f}" if c in rows[sc] else f"{'-':>10}" for c in configs))
print('\nclusters to HW / clusters drawn (S only; H does not report it)\n')
for sc in sorted(rows):
    cells = []
    for c in configs:
        v = rows[sc].get(c)
        cells.append(f'{v[1]:.0f}/{v[2]:.0f}' if v and v[1] is not None and v[2] else '-')
    print(f'{sc:<14}' + ''.join(f'{x:>16}' for x in cells))
print('\nraster_sw + raster_hw ms (both phases)\n')
for sc in sorted(rows):
    cells = []
    for c in configs:
        v = rows[sc].get(c)
        cells.append(f'{v[3]:.3f}+{v[4]:.3f}' if v else '-')
    print(f'{sc:<14}' + ''.join(f'{x:>14}' for x in cells))
print('\ntriangles drawn (the split must not change them)\n')
for sc in sorted(rows):
    tris = sorted({round(v[5]) for v in rows[sc].values()})
    print(f'{sc:<14} {tris}')
PY
echo "== done $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
