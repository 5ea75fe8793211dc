#!/bin/bash
# Session 17, device (1920x1080, 1 px): does the order of a fan's triangles (the triangles that
# share their largest index m, whose relative order the code leaves free) change raster_sw's cost?
# H = 233b13b; T = the max-delta code with a temporary switch VGEO_ZZ_TIE (not in the repo):
# unset = stable (as committed), a / b = sorted by (m, second / third corner), ra = (m, second
# corner descending). The same bytes in every variant. Two interleaved rounds of vgeo bench on
# stress N=20, 100 (4 frames) and foliage.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in H T; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
o=$OUT/tie.txt
nvidia-smi --query-gpu=name,driver_version --format=csv > $o 2>&1
T0=$SECONDS
timeout 60 /tmp/vgeo-H bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
for r in 1 2; do
  for v in H T T-a T-b T-ra; do
    b=${v%%-*}; tie=${v#T-}; [ "$v" = T ] && tie=""; [ $b = H ] && tie=""
    d=/tmp/s-$v-r$r
    VGEO_ZZ_TIE=$tie timeout 90 /tmp/vgeo-$b bench --suite full --scenes stress,foliage --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d > $d.log 2>&1
    echo "== $v r$r t=$((SECONDS - T0))" >> $o
    python3 - $d/bench.json >> $o 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  raster_sw {sw:6.3f}  B/stored tri {s['bytes_per_stored_triangle']:.2f}")
PY
  done
done
echo "== total $((SECONDS - T0)) s" >> $o
