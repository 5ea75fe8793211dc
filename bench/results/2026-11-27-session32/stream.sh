#!/bin/bash
# Session 32, device call 3: issue 13 acceptances 2 and 3 with the scans built at a simplification
# ratio of 0.35 (`vgeo build --ratio 0.35`; call 2 and the lavapipe runs in README.md). As
# session 18 (../2026-11-26-session18/stream.sh): stream_sizes (this commit's
# examples/stream_sizes.rs, now with --ratio) makes unique meshes (bunny subdivided 3 levels, 4
# copies, its own seed each: 17.8 M triangles), scenes of 4, 12 and 24 of them under 256 MiB,
# 1920x1080, 60 frames along the path, 64 MiB per frame at most, then the cold cut. Then the
# frame time streamed (256 MiB) against all resident on the 4-mesh scene (it fits both ways),
# `vgeo render --time 64` on the close-up (40 frames) and at the path's end (120 frames).
# Binaries: .gpu/vgeo-O.xz (d30e715), .gpu/stream_sizes.xz.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/stream.txt
setup $o
for b in vgeo-O stream_sizes; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/$b.xz /tmp/$b
  chmod +x /tmp/$b
done
nproc >> $o
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
timeout 470 /tmp/stream_sizes --mesh .gpu/assets/scanned/bunny.ply --work /tmp/big --out $OUT/sizes --sizes 4,12,24 --budget-mib 256 --mib-per-frame 64 --levels 3 --copies 4 --frames 60 --size 1920x1080 --ratio 0.35 > $OUT/sizes-log.txt 2>&1
echo "== sizes rc=$? t=$((SECONDS - T0))" >> $o
ls -la /tmp/big >> $o
pack
for mode in streamed resident; do
  [ $((SECONDS - T0)) -gt 530 ] && break
  B=""; [ $mode = streamed ] && B="--geometry-budget 256 --stream-mib-per-frame 64"
  timeout 40 /tmp/vgeo-O render /tmp/big/s4.toml $B --frames 40 --time 64 --width 1920 --height 1080 --stats -o /tmp/close-$mode.png > $OUT/close-$mode.txt 2>&1
  echo "== close $mode rc=$? t=$((SECONDS - T0))" >> $o
done
for mode in streamed resident; do
  [ $((SECONDS - T0)) -gt 545 ] && break
  B=""; [ $mode = streamed ] && B="--geometry-budget 256 --stream-mib-per-frame 64"
  timeout 30 /tmp/vgeo-O render /tmp/big/s4.toml $B --path --frames 120 --time 64 --width 1920 --height 1080 --stats -o /tmp/path-$mode.png > $OUT/path-$mode.txt 2>&1
  echo "== path $mode rc=$? t=$((SECONDS - T0))" >> $o
done
cmp /tmp/close-streamed.png /tmp/close-resident.png >> $o 2>&1 && echo "close images: same" >> $o
cmp /tmp/path-streamed.png /tmp/path-resident.png >> $o 2>&1 && echo "path images: same" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
