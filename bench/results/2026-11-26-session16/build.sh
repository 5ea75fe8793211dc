#!/bin/bash
# Session 16, device host: build throughput, issue 11's base 217d124 against N (main at ec95e91:
# groups compacted once into local ids, speculation bounded by threads), for issue 11
# acceptance 6. Binaries in .gpu/: vgeo-base.gz, vgeo-N.gz; subdivide_mesh.gz makes lucy x16
# (1.6 M triangles). Per run: the build's own `seconds` (the builder, as both binaries report it)
# and the whole command's wall time (import, build, file). One thread pinned to one core, two
# threads to two cores (taskset), 16 unpinned; base and N interleaved. Seven rounds (ROUNDS=n for
# another count: session 17 ran five).
for b in base N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
nproc > $OUT/build-log.txt; lscpu | grep -E "Model name|MHz" >> $OUT/build-log.txt
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $OUT/build-log.txt 2>&1
one() { # mesh threads bin
  case $2 in 1) pin="taskset -c 2";; 2) pin="taskset -c 2,3";; *) pin="";; esac
  t0=$(date +%s%N)
  s=$($pin /tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  t1=$(date +%s%N)
  echo "build $(basename $1 .ply) t$2 $3 $s $(( (t1 - t0) / 1000000 ))e-3" >> $OUT/build.txt
}
T0=$SECONDS
for r in $(seq ${ROUNDS:-7}); do
  for t in 1 2 16; do
    for m in bunny lucy turbineblade; do for b in base N; do one .gpu/assets/scanned/$m.ply $t $b; done; done
  done
done
echo "== small meshes done $((SECONDS - T0)) s" >> $OUT/build-log.txt
for r in $(seq ${ROUNDS:-7}); do
  for t in 1 2 16; do
    for b in base N; do one /tmp/lucy16.ply $t $b; done
  done
done
echo "== builds done $((SECONDS - T0)) s" >> $OUT/build-log.txt
python3 - $OUT/build.txt >> $OUT/build-log.txt <<'PY'
import sys, statistics as st, collections
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, m, t, b, s, w = line.split()
    runs[(m, t, b)].append((float(s), float(w)))
print(f"{'mesh':14} {'thr':4} {'binary':8} {'build s (median)':>17} {'wall s (median)':>16} {'x base build':>13} {'x base wall':>12}")
for (m, t, b), v in sorted(runs.items()):
    s = st.median(x[0] for x in v); w = st.median(x[1] for x in v)
    base = runs.get((m, t, 'base'))
    bs = st.median(x[0] for x in base) if base else float('nan'); bw = st.median(x[1] for x in base) if base else float('nan')
    print(f"{m:14} {t:4} {b:8} {s:17.3f} {w:16.3f} {s/bs:13.2f} {w/bw:12.2f}")
PY
