#!/bin/bash
# Session 22, device host: build throughput of base = 217d124 (issue 11's base), H = 3b27061
# (main before this session) and F = this session's builder, plain release binaries (stripped),
# interleaved; per run the build's own `seconds`. t1/t2 pinned to one/two physical cores as in
# session 21; t16 unpinned.
for b in base H F; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
LOG=$OUT/build-log.txt
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
{ date; lscpu | head -20; echo "t1: cpu $A; t2: cpus $A,$B"; } > $LOG
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $LOG 2>&1
one() { # mesh threads bin
  case $2 in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; *) pin="";; esac
  s=$($pin /tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build $(basename $1 .ply) t$2 $3 $s" >> $OUT/build.txt
}
for r in $(seq ${ROUNDS:-15}); do
  for t in 1 2; do
    for m in bunny lucy turbineblade; do for b in base H F; do one .gpu/assets/scanned/$m.ply $t $b; done; done
  done
  if [ $r -le ${R16:-5} ]; then for t in 1 2; do for b in base H F; do one /tmp/lucy16.ply $t $b; done; done; fi
  if [ $r -le 3 ]; then for b in base H F; do one /tmp/lucy16.ply 16 $b; done; fi
done
python3 - $OUT/build.txt >> $LOG <<'PY'
import sys, statistics as st, collections
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, m, t, b, s = line.split()
    runs[(m, t, b)].append(float(s))
for (m, t) in sorted({(m, t) for (m, t, _) in runs}, key=lambda k: (k[0], int(k[1][1:]))):
    b, h, f = (runs[(m, t, x)] for x in ('base', 'H', 'F'))
    med = st.median
    print(f"{m:13} {t:3} n={len(b):2} median base {med(b):.3f} H {med(h):.3f} F {med(f):.3f} | "
          f"H/base {med(h)/med(b):.3f} F/base {med(f)/med(b):.3f} | "
          f"spread base {min(b):.3f}-{max(b):.3f} F {min(f):.3f}-{max(f):.3f}")
PY
cat $LOG | tail -12
