#!/bin/bash
# Session 13, call 2 (H100 host): build throughput, base 217d124 against N = 958e434 (call 1's
# builder with the crease normals made parallel), interleaved: bunny, lucy, turbineblade 5 runs
# at 1 and 16 threads; lucy subdivided to 1.6 M triangles 5 runs at 1, 2 and 16 threads.
for b in base N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdiv.gz > /tmp/subdiv; chmod +x /tmp/subdiv
nproc > $OUT/log.txt
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 >> $OUT/log.txt 2>&1
one() { # mesh threads bin
  s=$(/tmp/vgeo-$3 build $1 -o /tmp/x.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build $(basename $1 .ply) t$2 $3 $s" >> $OUT/build.txt
}
for t in 1 16; do
  for r in 1 2 3 4 5; do
    for m in bunny lucy turbineblade; do for b in base N; do one .gpu/assets/scanned/$m.ply $t $b; done; done
  done
done
for t in 1 2 16; do for r in 1 2 3 4 5; do for b in base N; do one /tmp/lucy16.ply $t $b; done; done; done
echo "== builds done $SECONDS s" >> $OUT/log.txt
