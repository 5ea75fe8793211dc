#!/bin/bash
# Session 22, device host: lucy subdivided to 1.6 M triangles (subdivide_mesh --levels 2), base =
# 217d124 against G = e6e8494 (this session's builder), back to back per round, at one, two
# (pinned as in build.sh) and sixteen threads.
for b in base G; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 > /dev/null 2>&1
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
for r in $(seq ${ROUNDS:-5}); do for t in 1 2 16; do
  case $t in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; *) pin="";; esac
  for b in base G; do
    s=$($pin /tmp/vgeo-$b build /tmp/lucy16.ply -o /tmp/x.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
    echo "build lucy16 t$t $b $s" >> $OUT/lucy16.txt
  done
done; done
python3 - $OUT/lucy16.txt > $OUT/lucy16-log.txt <<'PY'
import sys, statistics as st, collections
seq = collections.defaultdict(list)
for l in open(sys.argv[1]):
    _, m, t, b, s = l.split(); seq[t].append((b, float(s)))
for t, v in sorted(seq.items(), key=lambda k: int(k[0][1:])):
    rounds = [dict(v[i:i + 2]) for i in range(0, len(v), 2)]
    b = [r['base'] for r in rounds]; g = [r['G'] for r in rounds]
    print(f"lucy16 {t:3} n={len(rounds)} median base {st.median(b):.3f} G {st.median(g):.3f} "
          f"G/base {st.median(g)/st.median(b):.3f} paired {st.median(r['G']/r['base'] for r in rounds):.3f} "
          f"| spread base {min(b):.3f}-{max(b):.3f} G {min(g):.3f}-{max(g):.3f}")
PY
cat $OUT/lucy16-log.txt
