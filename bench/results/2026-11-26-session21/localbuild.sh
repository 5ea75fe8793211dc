#!/bin/bash
# Local (2-core VM) build timing: base H N interleaved, one and two threads.
OUTF=$1; R=${ROUNDS:-15}
one() { s=$(/tmp/lb-$3 build $1 -o /tmp/lbx.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.'); echo "build $(basename $1 .ply) t$2 $3 $s 0" >> $OUTF; }
cp /tmp/gpubin/vgeo-base /tmp/lb-base; cp /tmp/vgeo-m0 /tmp/lb-H; cp /tmp/vgeo-N2 /tmp/lb-N
for r in $(seq $R); do for t in 1 2; do
  for m in bunny lucy turbineblade; do for b in base H N; do one /work/shared/assets/scanned/$m.ply $t $b; done; done
  if [ $r -le ${R16:-5} ]; then for b in base H N; do one /tmp/lucy16.ply $t $b; done; fi
done; done
echo done >> $OUTF.done
