#!/bin/bash
# Session 21, device host: build throughput of issue 11's base 217d124 ("base"), main before this
# session (e441539, "H") and this session's builder ("N": meshoptimizer compiled with NDEBUG, a
# cheaper median edge, the canonical order by packed keys), for issue 11 acceptance 6. Session 20's
# build.sh with a third binary and more rounds; the pinned CPUs are chosen by physical core.
#   t1  : one thread on one CPU of core A
#   t2  : two threads on one CPU each of cores A and B (two physical cores, as a 2-core CI machine)
#   t2s : two threads on the two hardware threads of core A (only when the host has SMT)
#   t16 : sixteen threads, unpinned
# Per run: the build's own `seconds` and the whole command's wall time; base and N interleaved.
for b in base H N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
LOG=$OUT/build-log.txt
{ nproc; lscpu; echo "== lscpu -p"; lscpu -p=CPU,CORE,SOCKET,NODE | grep -v '^#'; } > $LOG
# CPU lists: one CPU per core, in core order; core A is the second core (the first takes interrupts).
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
CORE_A=$(lscpu -p=CPU,CORE | grep -v '^#' | awk -F, -v c=$A '$1==c {print $2}')
SIB=$(lscpu -p=CPU,CORE | grep -v '^#' | awk -F, -v k=$CORE_A -v c=$A '$2==k && $1!=c {print $1; exit}')
echo "t1: cpu $A; t2: cpus $A,$B (cores $CORE_A and another); t2s: cpus $A,${SIB:-none}" >> $LOG
MODES="1 2 16"; [ -n "$SIB" ] && MODES="1 2 2s 16"
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $LOG 2>&1
one() { # mesh mode bin
  case $2 in 1) pin="taskset -c $A"; t=1;; 2) pin="taskset -c $A,$B"; t=2;; 2s) pin="taskset -c $A,$SIB"; t=2;; *) pin=""; t=$2;; esac
  t0=$(date +%s%N)
  s=$($pin /tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  t1=$(date +%s%N)
  echo "build $(basename $1 .ply) t$2 $3 $s $(( (t1 - t0) / 1000000 ))e-3" >> $OUT/build.txt
}
T0=$SECONDS
for r in $(seq ${ROUNDS:-9}); do
  for t in $MODES; do
    for m in bunny lucy turbineblade; do for b in base H N; do one .gpu/assets/scanned/$m.ply $t $b; done; done
    for b in base H N; do one /tmp/lucy16.ply $t $b; done
  done
done
echo "== builds done $((SECONDS - T0)) s" >> $LOG
python3 - $OUT/build.txt >> $LOG <<'PY'
import sys, statistics as st, collections
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, m, t, b, s, w = line.split()
    runs[(m, t, b)].append((float(s), float(w)))
print(f"{'mesh':14} {'thr':4} {'binary':8} {'build s (median)':>17} {'min':>7} {'max':>7} {'wall s (median)':>16} {'x base build':>13} {'x base wall':>12}")
for (m, t, b), v in sorted(runs.items()):
    s = st.median(x[0] for x in v); w = st.median(x[1] for x in v)
    base = runs.get((m, t, 'base'))
    bs = st.median(x[0] for x in base) if base else float('nan'); bw = st.median(x[1] for x in base) if base else float('nan')
    print(f"{m:14} {t:4} {b:8} {s:17.3f} {min(x[0] for x in v):7.3f} {max(x[0] for x in v):7.3f} {w:16.3f} {s/bs:13.2f} {w/bw:12.2f}")
PY
