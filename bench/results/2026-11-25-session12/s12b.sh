#!/bin/bash
# Session 12, call 2 (H100): F = session 11's last commit (fa4fcad): the scene suite in vgeo at
# 1 px (frame time and triangles before this session's crease normals); N = this session's code:
# outdoor streamed under 64 MiB (settled frame time against call 1's all-resident).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
for b in base F N; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
timeout 200 /tmp/vgeo-F bench --suite full --scenes outdoor,indoor,foliage,drawcalls --modes vgeo --sweep 1 --frames 8 --quiet --out /tmp/F > /tmp/F.log 2>&1
echo "== F scenes rc=$?" >> $OUT/log.txt
timeout 150 /tmp/vgeo-N bench --suite full --scenes outdoor --modes vgeo --sweep 1 --frames 4 --geometry-budget 64 --quiet --out /tmp/Nb > /tmp/Nb.log 2>&1
echo "== N streamed rc=$?" >> $OUT/log.txt
for d in F Nb; do cp /tmp/$d/bench.md $OUT/$d-bench.md 2>/dev/null; tail -3 /tmp/$d.log >> $OUT/log.txt; done
