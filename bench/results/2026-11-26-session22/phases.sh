#!/bin/bash
# Session 22, device host: per-phase build times (throwaway VGEO_T hooks, see phases.py) of
# baseT = 217d124 (issue 11's base), curT = 3b27061 (session 21's builder) and newT (this
# session's), interleaved, pinned to one physical core (t1) or two (t2) as in session 21.
R=${R:-15}; R16=${R16:-5}
for b in baseT curT newT; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
gunzip -c .gpu/subdivide_mesh.gz > /tmp/subdiv; chmod +x /tmp/subdiv
mapfile -t FIRST < <(lscpu -p=CPU,CORE | grep -v '^#' | sort -t, -k2,2n -k1,1n | awk -F, '!seen[$2]++ {print $1}')
A=${FIRST[1]:-${FIRST[0]}}; B=${FIRST[2]:-${FIRST[0]}}
LOG=$OUT/phases.txt
{ lscpu | head -20; echo "t1: cpu $A; t2: cpus $A,$B"; } > $LOG
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/lucy16.ply --levels 2 > /dev/null 2>&1
P="python3 bench/results/2026-11-26-session22/phases.py"
BINS="/tmp/vgeo-baseT /tmp/vgeo-curT /tmp/vgeo-newT"
for m in lucy bunny; do
  $P .gpu/assets/scanned/$m.ply $R 1 $A -- $BINS >> $LOG
  $P .gpu/assets/scanned/$m.ply $R 2 $A,$B -- $BINS >> $LOG
done
$P .gpu/assets/scanned/turbineblade.ply $R16 1 $A -- $BINS >> $LOG
$P .gpu/assets/scanned/turbineblade.ply $R16 2 $A,$B -- $BINS >> $LOG
$P /tmp/lucy16.ply $R16 2 $A,$B -- $BINS >> $LOG
cat $LOG
