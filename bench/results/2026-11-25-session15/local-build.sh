#!/bin/bash
# local build timing: base vs F, interleaved
out=$1; : > $out
one() { # mesh threads bin
  case $2 in 1) pin="taskset -c 0";; 2) pin="taskset -c 0,1";; esac
  t0=$(date +%s%N)
  s=$($pin $3 build $1 -o /tmp/lx.vgeo --json --threads $2 2>/dev/null | grep '"seconds"' | tr -dc '0-9.')
  t1=$(date +%s%N)
  echo "build $(basename $1 .ply) t$2 $4 $s $(( (t1 - t0) / 1000000 ))e-3" >> $out
}
for r in 1 2 3 4 5; do for t in 1 2; do for m in bunny lucy turbineblade; do
  one /work/shared/assets/scanned/$m.ply $t /work/base/target/release/vgeo base; one /work/shared/assets/scanned/$m.ply $t /tmp/vgeo-F F; done; done; done
for r in 1 2 3; do for t in 1 2; do one /tmp/lucy16.ply $t /work/base/target/release/vgeo base; one /tmp/lucy16.ply $t /tmp/vgeo-F F; done; done
