#!/bin/bash
# Session 13, call 1 (H100 host): N = this session's builder (group clusters split at full-cluster
# multiples, level-0 chunks of 4096, one-piece coverage error, crease normals by one edge sort)
# against the base 217d124.
#  1. build throughput (the build's own "seconds": import + build), base and N interleaved:
#     bunny, lucy, turbineblade 5 runs at 1 thread and 5 at 16; lucy subdivided to 1.6 M
#     triangles 3 runs at 1 thread and 3 at 16
#  2. N: the scene suite in brute, lod and vgeo at 1 px with the error against the 4x4-spp
#     reference, and stress N=20 (issue 11 acceptance 3 with the new clusters)
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdiv.gz > /tmp/subdiv; chmod +x /tmp/subdiv
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
nproc >> $OUT/log.txt
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $OUT/log.txt 2>&1
one() { # mesh threads bin
  s=$(/tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build $(basename $1 .ply) t$2 $3 $s" >> $OUT/build.txt
}
for t in 1 16; do
  for r in 1 2 3 4 5; do
    for m in bunny lucy turbineblade; do for b in base N; do one .gpu/assets/scanned/$m.ply $t $b; done; done
  done
  for r in 1 2 3; do for b in base N; do one /tmp/lucy16.ply $t $b; done; done
done
echo "== builds done $SECONDS s" >> $OUT/log.txt
timeout 270 /tmp/vgeo-N bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes brute,lod,vgeo --sweep 1 --frames 8 --quiet --out /tmp/N > /tmp/N.log 2>&1
echo "== N scenes rc=$? $SECONDS s" >> $OUT/log.txt
timeout 150 /tmp/vgeo-N bench --suite full --scenes stress --stress-n 20 --modes brute,vgeo --sweep 1 --frames 2 --quiet --out /tmp/Ns > /tmp/Ns.log 2>&1
echo "== N stress rc=$? $SECONDS s" >> $OUT/log.txt
for d in N Ns; do cp /tmp/$d/bench.md $OUT/$d-bench.md 2>/dev/null; tail -3 /tmp/$d.log >> $OUT/log.txt; done
