#!/bin/bash
# Session 30, device call 9: lod shares vgeo's HZB test (hzb_rect_occluded), so the finer window
# changed its times too. M = 042b633 (session 29's end), F = dc3099b (this session's code).
# 1. lod's images at session 29's equal-error thresholds (and 1 px), the second frame of the
#    same view (culled with the first one's HZB), M against F byte for byte.
# 2. lod (M and F) and vgeo (F) timed at 0.5-4 px along the scenes' paths as session 29's final
#    run (8 frames; stress N=20 2 frames), without brute: the errors are session 29's where the
#    images are the same.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/lod.txt
setup $o
# The binaries as xz (the carry limit), unpacked by Python's lzma.
for b in M F; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm F
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== lod images (F against M)" >> $o
for se in outdoor:1 indoor:1 foliage:1 foliage:4 drawcalls:0.5 drawcalls:1; do
  s=${se%%:*}; e=${se##*:}
  for b in M F; do
    timeout 60 /tmp/vgeo-$b render assets/scenes/$s.toml --mode lod --error-px $e --frames 2 --width 1920 --height 1080 --out /tmp/lod-$s-$e-$b.png > /tmp/lod-$s-$e-$b.log 2>&1
  done
  if [ -s /tmp/lod-$s-$e-M.png ] && cmp -s /tmp/lod-$s-$e-M.png /tmp/lod-$s-$e-F.png; then r=same; else r="DIFFERENT or missing ($(tail -1 /tmp/lod-$s-$e-F.log))"; fi
  echo "  $s $e px: $r" >> $o
done
echo "== images t=$((SECONDS - T0))" >> $o
pack
timeout 150 /tmp/vgeo-F bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes lod,vgeo --sweep 0.5,1,2,4 --quiet --out $OUT/F-scenes > $OUT/F-scenes.log 2>&1
echo "== F scenes rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 150 /tmp/vgeo-M bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes lod --sweep 0.5,1,2,4 --quiet --out $OUT/M-scenes > $OUT/M-scenes.log 2>&1
echo "== M scenes rc=$? t=$((SECONDS - T0))" >> $o
pack
timeout 100 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 20 --frames 2 --modes lod,vgeo --sweep 1,2 --quiet --out $OUT/F-stress > $OUT/F-stress.log 2>&1
echo "== F stress rc=$? t=$((SECONDS - T0))" >> $o
timeout 100 /tmp/vgeo-M bench --suite full --scenes stress --stress-n 20 --frames 2 --modes lod --sweep 1,2 --quiet --out $OUT/M-stress > $OUT/M-stress.log 2>&1
echo "== M stress rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
