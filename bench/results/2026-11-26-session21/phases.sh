#!/bin/bash
# Session 21, device host, call 4: where lucy's two-thread build spends its time, base (217d124)
# against N (this session's builder), both with a progress hook that prints the elapsed time of
# each phase (VGEO_PHASES; throwaway binaries "BP" and "P", not in the repository). Phases:
# prep = up to "clustering level 0" (prepare, attributes, the verify-rule edge table),
# l0 = level 0's clusters, levels = every level to the root chain, asm = assemble, page = paginate.
for b in BP P; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
for r in $(seq ${ROUNDS:-15}); do for t in 1 2; do for b in BP P; do
  case $t in 1) pin="taskset -c $A";; 2) pin="taskset -c $A,$B";; esac
  echo "== $b t$t $r" >> $OUT/phases-raw.txt
  VGEO_PHASES=1 $pin /tmp/vgeo-$b build .gpu/assets/scanned/lucy.ply -o /tmp/x.vgeo --json --threads $t 2>&1 | grep -E '^ +[0-9]+\.[0-9]{4} |"seconds"' >> $OUT/phases-raw.txt
done; done; done
python3 - $OUT/phases-raw.txt > $OUT/phases.txt <<'PY'
import sys, re, statistics as st, collections
runs = collections.defaultdict(list); cur = None
for line in open(sys.argv[1]):
    if line.startswith('=='):
        _, b, t, r = line.split(); cur = (b, t, []); runs[(b, t)].append(cur[2]); continue
    m = re.match(r'\s*"seconds": ([0-9.]+)', line)
    if m: cur[2].append(('end', float(m.group(1)))); continue
    tm, msg = line.strip().split(' ', 1); cur[2].append((msg, float(tm)))
def phases(ev):
    d = dict(); get = lambda pred: next(t for m, t in ev if pred(m))
    last = lambda pred: [t for m, t in ev if pred(m)][-1]
    c0 = get(lambda m: 'clustering level 0' in m); l0 = get(lambda m: 'level 0:' in m)
    lv = last(lambda m: re.search(r'level \d+:', m) is not None); end = get(lambda m: m == 'end')
    pg = [t for m, t in ev if m == 'paging']; pd = [t for m, t in ev if m == 'paged']
    d['prep'] = c0; d['l0'] = l0 - c0; d['levels'] = lv - l0
    d['asm'] = (pg[0] if pg else end) - lv; d['page'] = (pd[0] - pg[0]) if pg else 0.0; d['total'] = end
    return d
keys = ['prep', 'l0', 'levels', 'asm', 'page', 'total']
print('ms (medians of %d runs)' % len(next(iter(runs.values()))))
print(f"{'bin':4} {'thr':3} " + ' '.join(f'{k:>8}' for k in keys))
for (b, t), evs in sorted(runs.items()):
    ps = [phases(e) for e in evs]
    print(f"{b:4} {t:3} " + ' '.join(f'{1000*st.median(p[k] for p in ps):8.1f}' for k in keys))
PY
cat $OUT/phases.txt
