#!/bin/bash
# Session 22, device host: paired rounds (base = 217d124, F = this session's builder, run back to
# back each round) of the small scans at one and two threads, with the host's steal time (from
# /proc/stat) before and after, to tell a calm host from a busy one.
for b in base F; do [ -x /tmp/vgeo-$b ] || { gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; }; done
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[${CPU_A:-1}]:-${FIRST[0]}}; B=${FIRST[${CPU_B:-2}]:-${FIRST[0]}}
LOG=$OUT/paired-log.txt
steal() { awk '/^cpu /{print "steal jiffies", $9}' /proc/stat; }
{ date; echo "t1: cpu $A; t2: cpus $A,$B"; steal; } >> $LOG
for r in $(seq ${ROUNDS:-21}); do for t in 1 2; do for m in bunny lucy turbineblade; do
  case $t in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; esac
  for b in base F; do
    s=$($pin /tmp/vgeo-$b build .gpu/assets/scanned/$m.ply -o /tmp/x.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
    echo "build $m t$t $b $s" >> $OUT/paired.txt
  done
done; done; done
steal >> $LOG
python3 - $OUT/paired.txt >> $LOG <<'PY'
import sys, statistics as st, collections
seq = collections.defaultdict(list)
for l in open(sys.argv[1]):
    _, m, t, b, s = l.split(); seq[(m, t)].append((b, float(s)))
for (m, t), v in sorted(seq.items()):
    pairs = [dict(v[i:i + 2]) for i in range(0, len(v), 2)]
    r = sorted(p['F'] / p['base'] for p in pairs)
    b = [p['base'] for p in pairs]; f = [p['F'] for p in pairs]
    print(f"{m:13} {t} n={len(r)} median base {st.median(b):.4f} F {st.median(f):.4f} "
          f"F/base (medians) {st.median(f)/st.median(b):.3f} paired median {st.median(r):.3f} "
          f"quartiles {r[len(r)//4]:.2f}-{r[3*len(r)//4]:.2f} | base spread {min(b):.4f}-{max(b):.4f}")
PY
tail -8 $LOG
