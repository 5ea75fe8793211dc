#!/bin/bash
# Session 16, call 1 (H100, 1920x1080, 1 px): raster_sw as two variants over the SW list, the
# lean one for clusters whose triangles project small and the `shared` one (large triangles by
# the whole workgroup) for those the cull flags (SW_LIST_SHARED_FLAG). V = .gpu/vgeo-V.gz (branch
# swlists, a047090); base = .gpu/vgeo-M.gz (main at 6b555f9: one raster_sw with the shared pass
# for every cluster). Two rounds each, interleaved. outdoor, indoor, foliage, drawcalls (8 frames), stress
# N=20 and 100 (4 frames), the close blade; then images (view triangles) compared with pngdiff.py.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
for b in M V; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/swlists.txt 2>&1
T0=$SECONDS
timeout 60 /tmp/vgeo-V bench --suite full --scenes outdoor --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
run() { # tag binary shaderdir
  if [ -n "$3" ]; then export VGEO_SHADER_DIR=$3; else unset VGEO_SHADER_DIR; fi
  d=/tmp/l-$1
  timeout 60 /tmp/vgeo-$2 bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
  timeout 60 /tmp/vgeo-$2 bench --suite full --scenes stress --stress-n 20,100 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
  echo "== $1 t=$((SECONDS - T0))" >> $OUT/swlists.txt
  for x in s t; do
    python3 - $d-$x/bench.json >> $OUT/swlists.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for s in r["summary"]:
    p = dict(s.get("passes_mean", []))
    sw = sum(v for k, v in p.items() if k.startswith("raster_sw"))
    print(f"  {s['scene']:12} {s['gpu_ms_mean']:8.3f} ms  raster_sw {sw:6.3f}  tris {s['triangles_mean']:.0f}")
PY
  done
  timeout 60 /tmp/vgeo-$2 render .gpu/close.toml --width 1920 --height 1080 --stats --frames 8 --out /tmp/close-$1.png 2>&1 | grep -E "GPU time|  raster_sw  " | sed 's/^/  close /' >> $OUT/swlists.txt
  for s in foliage indoor; do timeout 60 /tmp/vgeo-$2 render assets/scenes/$s.toml --width 1920 --height 1080 --view triangles --out /tmp/img-$s-$1.png > /dev/null 2>&1; done
  timeout 60 /tmp/vgeo-$2 render .gpu/close.toml --width 1920 --height 1080 --view triangles --out /tmp/img-close-$1.png > /dev/null 2>&1
  unset VGEO_SHADER_DIR
}
run base M ""
run V1 V ""
run base2 M ""
run V2 V ""
for s in foliage indoor close; do python3 bench/results/2026-11-25-session15/pngdiff.py /tmp/img-$s-base.png /tmp/img-$s-V1.png >> $OUT/swlists.txt 2>&1; done
echo "== total $((SECONDS - T0)) s" >> $OUT/swlists.txt
