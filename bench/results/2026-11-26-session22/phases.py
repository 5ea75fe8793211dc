#!/usr/bin/env python3
"""Session 22: interleaved builds of one mesh by several vgeo binaries built with a throwaway
VGEO_T hook (each phase's end printed as `T <ms since the build began> <name>`); per binary, the
median of each phase's length and of the build's own `seconds`.
usage: phases.py MESH ROUNDS THREADS [CPU-LIST] -- BIN...   (CPU-LIST: taskset's, optional)"""
import sys, subprocess, statistics as st, collections, os, json
args = sys.argv[1:]
mesh, rounds, threads = args[0], int(args[1]), args[2]
i = args.index('--'); pin = args[3:i]; bins = args[i + 1:]
res = {b: collections.OrderedDict() for b in bins}
for r in range(rounds):
    for b in bins:
        cmd = (['taskset', '-c', pin[0]] if pin else []) + \
            [b, 'build', mesh, '-o', '/tmp/ph.vgeo', '--threads', threads, '--json']
        p = subprocess.run(cmd, env=dict(os.environ, VGEO_T='1'), capture_output=True, text=True)
        prev = 0.0
        for l in p.stderr.splitlines():
            if l.startswith('T '):
                _, ms, name = l.split(None, 2); ms = float(ms)
                res[b].setdefault(name, []).append(ms - prev); prev = ms
        res[b].setdefault('seconds', []).append(1000 * json.loads(p.stdout)[0]['seconds'])
base = None
for b in bins:
    sec = st.median(res[b]['seconds']); base = base or sec
    print(f"== {os.path.basename(b)} {os.path.basename(mesh)} t{threads}: median {sec:.1f} ms "
          f"(x{sec / base:.3f} of the first), min {min(res[b]['seconds']):.1f}, {rounds} rounds")
    print('   ' + '  '.join(f"{k}={st.median(v):.2f}" for k, v in res[b].items()
                            if k not in ('seconds', 'start')))
