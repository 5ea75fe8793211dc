#!/bin/bash
# Session 21, device host, second call: more rounds of the small meshes at one and two threads
# (call 1's medians of 7 moved by up to 15 % between two runs of one binary), plus lucy x16 at two
# threads. base = 217d124, H = e441539 (main before this session), N = this session's builder.
# Per run the build's own `seconds`; base, H and N interleaved; pinned as in build.sh.
for b in base H N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
LOG=$OUT/build2-log.txt
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
{ lscpu | head -20; echo "t1: cpu $A; t2: cpus $A,$B"; } > $LOG
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $LOG 2>&1
one() { # mesh threads bin
  case $2 in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; esac
  s=$($pin /tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build $(basename $1 .ply) t$2 $3 $s 0" >> $OUT/build2.txt
}
for r in $(seq ${ROUNDS:-15}); do
  for t in 1 2; do
    for m in bunny lucy turbineblade; do for b in base H N; do one .gpu/assets/scanned/$m.ply $t $b; done; done
  done
  if [ $r -le ${R16:-5} ]; then for b in base H N; do one /tmp/lucy16.ply 2 $b; done; fi
done
python3 - $OUT/build2.txt >> $LOG <<'PY'
import sys, statistics as st, collections
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, m, t, b, s, _ = line.split()
    runs[(m, t, b)].append(float(s))
for (m, t) in sorted({(m, t) for (m, t, _) in runs}):
    b, h, n = (runs[(m, t, x)] for x in ('base', 'H', 'N'))
    med = st.median
    print(f"{m:13} {t:3} n={len(b):2} median base {med(b):.3f} H {med(h):.3f} N {med(n):.3f} | "
          f"H/base {med(h)/med(b):.2f} N/base {med(n)/med(b):.2f} | min N/base {min(n)/min(b):.2f} "
          f"| spread base {min(b):.3f}-{max(b):.3f} N {min(n):.3f}-{max(n):.3f}")
PY
