#!/bin/bash
# Session 41, call 3: session 40 call 1 again on F = b8908f4 (main), an
# H200 (the same Hopper chip as the H100, more memory); issue 13's acceptances 2 and 3 on the
# final code (the pages are 6-8 % smaller than in session
# 32's run, so 24 meshes are now 4.05 GiB: 26 are used), as session 32's stream.sh:
# stream_sizes (unique meshes: bunny subdivided 3 levels, 4 copies, a seed each; 17.8 M
# triangles, 181 MB of .vgeo each at the default 0.35) at 4, 12 and 26 meshes under 256 MiB,
# 1920x1080, 60 frames along the path, 64 MiB per frame at most, then the cold cut; the frame time
# streamed (256 MiB) against all resident on the 4-mesh scene (`vgeo render --time 64`, the
# close-up after 40 frames and the path's end after 120); then outdoor and indoor once more,
# A = f0ec5ef against F = main (b8908f4), runs A Z Z A A Z at the suite's 16 frames.
# Binaries: .gpu/vgeo-A.xz, .gpu/vgeo-F.xz (main, release, stripped), .gpu/stream_sizes.xz
# (main's example, release, stripped).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stream.txt
setup_xz $o vgeo-A vgeo-F stream_sizes
nproc >> $o
T0=$SECONDS
timeout 330 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT/sizes --sizes 4,12,26 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 60 --size 1920x1080 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? t=$((SECONDS - T0))" >> $o
ls -la /tmp/big >> $o; du -sb /tmp/big/*.vgeo | awk '{s+=$1} END {print "vgeo bytes", s}' >> $o
pack
for mode in streamed resident; do
  B=""; [ $mode = streamed ] && B="--geometry-budget 256 --stream-mib-per-frame 64"
  timeout 40 /tmp/vgeo-F render /tmp/big/s4.toml $B --frames 40 --time 64 --width 1920 --height 1080 --stats -o /tmp/close-$mode.png > $OUT/close-$mode.txt 2>&1
  echo "== close $mode rc=$? t=$((SECONDS - T0))" >> $o
  timeout 30 /tmp/vgeo-F render /tmp/big/s4.toml $B --path --frames 120 --time 64 --width 1920 --height 1080 --stats -o /tmp/path-$mode.png > $OUT/path-$mode.txt 2>&1
  echo "== path $mode rc=$? t=$((SECONDS - T0))" >> $o
done
cmp /tmp/close-streamed.png /tmp/close-resident.png >> $o 2>&1 && echo "close images: same" >> $o
pack
warm A
for r in Aa Fa Fb Ab Ac Fc; do
  [ $((SECONDS - T0)) -gt 520 ] && break
  timeout 40 /tmp/vgeo-${r:0:1} bench --suite full --scenes outdoor,indoor --modes vgeo --sweep 1 --quiet --out $OUT/$r-od > $OUT/$r-od.log 2>&1
  echo "== $r od rc=$? t=$((SECONDS - T0))" >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
