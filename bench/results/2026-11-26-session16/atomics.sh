#!/bin/bash
# Session 16 (device, 1920x1080, 1 px): what the cull's same-address statistics atomics cost.
# One binary (.gpu/vgeo-N.gz, main's shaders) and shader folders given by --shader-dir:
#   base   = the built-in shaders
#   nostat = .gpu/nostat: the 14 atomicAdds of counters that are statistics only (instances
#            tested / visible, clusters tested, nodes visited, triangles, local walks, occluded)
#            removed from instance_cull.comp.glsl and common/cull.glsl (timing only: the stats
#            it reports are then zero)
#   agg    = .gpu/agg: the cull's counters and list slots taken once per subgroup (subgroupAdd,
#            subgroupBallot)
# Call 5 (VARIANTS="base notri tagg noinst nocl") splits nostat's gain:
#   notri  = only the `triangles` statistic removed (a varying increment per cluster)
#   tagg   = `triangles` added once per subgroup (subgroupAdd + subgroupElect), the rest as base
#   noinst = only instances tested / visible removed
#   nocl   = only clusters tested, nodes visited, local walks and the occluded counts removed
# (call 4 ran base, nostat, agg)
# Per variant and round: vgeo bench on stress N=20, 100 (4 frames) and foliage, outdoor (8 frames).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-N.gz > /tmp/vgeo; chmod +x /tmp/vgeo; V=/tmp/vgeo
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/atomics.txt 2>&1
T0=$SECONDS
timeout 60 $V bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
vs=${VARIANTS:-base nostat agg}
for r in 1 2; do
  for v in $vs; do
    if [ $v = base ]; then unset VGEO_SHADER_DIR; else export VGEO_SHADER_DIR=$PWD/.gpu/$v; fi
    d=/tmp/a-$v-r$r
    timeout 90 $V bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    timeout 90 $V bench --suite full --scenes foliage,outdoor --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    echo "== $v r$r t=$((SECONDS - T0))" >> $OUT/atomics.txt
    for x in t s; do
      tail -2 $d-$x.log | grep -i error >> $OUT/atomics.txt
      python3 - $d-$x/bench.json >> $OUT/atomics.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    cull = sum(v for k, v in p.items() if "cull" in k)
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  cull {cull:6.3f}  raster_sw {sw:6.3f}  tris {s['triangles_mean']:.0f}")
PY
    done
  done
done
echo "== total $((SECONDS - T0)) s" >> $OUT/atomics.txt
