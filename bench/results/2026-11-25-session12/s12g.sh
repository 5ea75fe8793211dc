#!/bin/bash
# Session 12, call 7 (H100, 16-core host): builder scaling (issue 14 item 6). L = 6357a38.
# lucy (100 K triangles) subdivided 3 times, 2 copies: 12.8 M input triangles; `vgeo build
# --threads T` for T = 1, 2, 4, 8, 16 (builder seconds from --json), and the byte-identical check.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
gunzip -c .gpu/vgeo-L.gz > /tmp/vgeo; gunzip -c .gpu/subdiv.gz > /tmp/subdiv; chmod +x /tmp/vgeo /tmp/subdiv
nproc > $OUT/log.txt
/tmp/subdiv .gpu/assets/scanned/lucy.ply /tmp/big.ply --levels 3 --copies 2 >> $OUT/log.txt 2>&1
for t in 16 8 4 2 1; do
  /tmp/vgeo build /tmp/big.ply -o /tmp/big-$t.vgeo --threads $t --json > /tmp/b$t.json 2>/dev/null
  echo "threads $t seconds $(grep '"seconds"' /tmp/b$t.json | tr -dc '0-9.') tris/s $(grep '"triangles_per_second"' /tmp/b$t.json | tr -dc '0-9.')" >> $OUT/log.txt
  cmp /tmp/big-16.vgeo /tmp/big-$t.vgeo && echo "  same bytes as 16 threads" >> $OUT/log.txt
done
