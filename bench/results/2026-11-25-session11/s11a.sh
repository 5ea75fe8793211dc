#!/bin/bash
# Session 11, call 1: cluster records in pages. B = aff0447 (96-byte cluster records resident),
# N = this session's pages that carry their clusters (8-byte locators resident). vgeo at 1 px on
# the scene suite and the stress grid: frame time, image error, GPU bytes; images compared.
# Call 1 ran as is (the scenes failed: hard/ assets not carried); call 2 ran `s11a.sh 2`: the scenes
# only, then N's stress grid twice more (is its N=100 image the same from run to run?). Call 4 ran
# `s11a.sh 4 "B N2 B2 N2b"`: N2 = N with a group's page slot read once for its members in the
# cull (`9a27045` + that change), each binary twice, interleaved.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in B N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/log.txt
/tmp/vgeo-N info 2>&1 | head -20 >> $OUT/log.txt
CALL=${1:-1}
BINS=${2:-B N}
for b in $BINS; do g=.gpu/vgeo-${b%[0-9b]}.gz; [ "$b" = N2 ] || [ "$b" = N2b ] && g=.gpu/vgeo-N2.gz; [ -f $g ] && { gunzip -c $g > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; }; done
for b in $BINS; do
  timeout 150 /tmp/vgeo-$b bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 16 --quiet --out /tmp/$b > /tmp/$b.log 2>&1
  echo "== $b scenes rc=$?" >> $OUT/log.txt
  [ "$CALL" != 1 ] && continue
  timeout 100 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$b-s > /tmp/$b-s.log 2>&1
  echo "== $b stress rc=$?" >> $OUT/log.txt
done
if [ "$CALL" = 2 ]; then
  for r in N-s N-s2; do timeout 80 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20,100 --modes vgeo --sweep 1 --frames 4 --quiet --out /tmp/$r > /tmp/$r.log 2>&1; done
  for s in $(cd /tmp/N-s/images && ls); do cmp -s /tmp/N-s/images/$s /tmp/N-s2/images/$s && echo "N-s=N-s2 same $s" || echo "N-s/N-s2 DIFF $s"; done >> $OUT/images.txt 2>&1
fi
[ "$CALL" = 4 ] && for s in $(cd /tmp/B/images && ls); do for c in N2 B2 N2b; do cmp -s /tmp/B/images/$s /tmp/$c/images/$s && echo "B=$c same $s" || echo "B/$c DIFF $s"; done; done >> $OUT/images.txt 2>&1
for d in B N B-s N-s; do echo "=== $d" >> $OUT/log.txt; grep -E "^\| vgeo|^## " /tmp/$d/bench.md >> $OUT/log.txt; tail -3 /tmp/$d.log >> $OUT/log.txt; done
for p in "B N" "B-s N-s"; do set -- $p
  for s in $(cd /tmp/$1/images 2>/dev/null && ls); do cmp -s /tmp/$1/images/$s /tmp/$2/images/$s && echo "$1=$2 same $s" || echo "$1/$2 DIFF $s"; done >> $OUT/images.txt 2>&1
done
python3 - >> $OUT/log.txt <<'PY'
import json
for b in ['B','N','B-s','N-s','N2','B2','N2b']:
    try: j=json.load(open(f'/tmp/{b}/bench.json'))
    except Exception as e: print(b, e); continue
    for s in j['summary']:
        print(b, s['scene'], 'ms', round(s['gpu_ms_mean'],3), 'psnr', s.get('psnr_db'), 'B/tri', round(s.get('bytes_per_stored_triangle') or 0,2), 'geomMiB', round(s.get('geometry_bytes',0)/2**20,1), [(n,round(t,3)) for n,t in s['passes_mean'] if t>0.05])
PY
