#!/bin/bash
# local (2-core dev VM): base vs F, paired rounds
out=/tmp/local22.txt; : > $out
for r in $(seq 11); do for t in 1 2; do for m in bunny lucy turbineblade; do for b in base0 F; do
  s=$(/tmp/vgeo-$b build /work/shared/assets/scanned/$m.ply -o /tmp/l22.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build $m t$t $b $s" >> $out
done; done; done
if [ $r -le 5 ]; then for t in 2; do for b in base0 F; do
  s=$(/tmp/vgeo-$b build /tmp/lucy16.ply -o /tmp/l22.vgeo --json --threads $t 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  echo "build lucy16 t$t $b $s" >> $out; done; done; fi
done
