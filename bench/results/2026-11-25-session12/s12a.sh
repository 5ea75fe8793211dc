#!/bin/bash
# Session 12, call 1 (H100): N = this session's code (crease normals by smooth fans, streaming
# without waits) against F = session 11's last commit (fa4fcad) and the issue's base 217d124.
#  1. builder throughput, 1 thread, on a quiet 16-core host: base, F, N (5 runs each, interleaved)
#  2. N: the scene suite in brute, lod and vgeo at 1 px with the error against the 4x4-spp
#     reference, and stress N=20 (issue 11 acceptance 3 on the new images)
# (call 2, s12b.sh: F's scenes and N streamed.)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base F N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
nproc >> $OUT/log.txt
for r in 1 2 3 4 5; do
  for m in bunny lucy turbineblade; do
    for b in base F N; do
      s=$(/tmp/vgeo-$b build .gpu/assets/scanned/$m.ply -o /tmp/x.vgeo --json --threads 1 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
      echo "build $m $b $s" >> $OUT/build.txt
    done
  done
done
echo "== builds done" >> $OUT/log.txt
timeout 300 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,lod,vgeo --sweep 1 --frames 8 --quiet --out /tmp/N > /tmp/N.log 2>&1
echo "== N scenes rc=$?" >> $OUT/log.txt
timeout 200 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1 --frames 2 --quiet --out /tmp/Ns > /tmp/Ns.log 2>&1
echo "== N stress rc=$?" >> $OUT/log.txt
for d in N Ns; do cp /tmp/$d/bench.md $OUT/$d-bench.md 2>/dev/null; tail -3 /tmp/$d.log >> $OUT/log.txt; done
cp /tmp/N/bench.json $OUT/N-bench.json 2>/dev/null
