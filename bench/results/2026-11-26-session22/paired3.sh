#!/bin/bash
# Session 22, device host: rounds of base = 217d124, F = cb18b72 and a third binary (call 8: S, F
# with the cheap passes over small inputs run serially, not kept; call 9: G = e6e8494), run back to
# back in each round, with the host's steal time before and after. THIRD names it (default S).
T=${THIRD:-S}
for b in base F $T; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
LOG=$OUT/paired3-log.txt
steal() { awk '/^cpu /{print "steal jiffies", $9}' /proc/stat; }
{ date; echo "t1: cpu $A; t2: cpus $A,$B"; steal; } >> $LOG
for r in $(seq ${ROUNDS:-21}); do for t in 1 2; do for m in bunny lucy turbineblade; do
  case $t in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; esac
  for b in base F $T; do
    s=$($pin /tmp/vgeo-$b build .gpu/assets/scanned/$m.ply -o /tmp/x.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
    echo "build $m t$t $b $s" >> $OUT/paired3.txt
  done
done; done; done
steal >> $LOG
python3 - $OUT/paired3.txt $T >> $LOG <<'PY'
import sys, statistics as st, collections
T = sys.argv[2]
seq = collections.defaultdict(list)
for l in open(sys.argv[1]):
    _, m, t, b, s = l.split(); seq[(m, t)].append((b, float(s)))
for (m, t), v in sorted(seq.items()):
    rounds = [dict(v[i:i + 3]) for i in range(0, len(v), 3)]
    med = lambda b: st.median(r[b] for r in rounds)
    pr = lambda b: st.median(r[b] / r['base'] for r in rounds)
    print(f"{m:13} {t} n={len(rounds)} median base {med('base'):.4f} F {med('F'):.4f} {T} {med(T):.4f} | "
          f"F/base {med('F')/med('base'):.3f} {T}/base {med(T)/med('base'):.3f} | paired F {pr('F'):.3f} {T} {pr(T):.3f} "
          f"| base spread {min(r['base'] for r in rounds):.4f}-{max(r['base'] for r in rounds):.4f}")
PY
tail -8 $LOG
