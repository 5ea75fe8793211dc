#!/bin/bash
# Session 31, device call 4: the final binary F (e71d988), measured as session 29's call 4
# (bench/results/2026-11-27-session29/final2.sh) measured its own, but for the stress scaling
# along the full suite's 16-frame path (its default) instead of 4 frames: the four bench scenes
# in all three modes, lod and vgeo swept over 0.25-4 px, errors against brute at 4x4 spp, 8
# frames; the stress scaling N = 20, 50, 100, 200 (vgeo at 1 px); the "tiny" check (stress N=20
# at 384x216 and 192x108, all three modes at 1 px, against its 4x4 reference); the close blade
# and the empty frame (`render --time 64`); stress N=20 (2 frames, 0.5-2 px, with its reference).
# The archive is rewritten after each step, so a cut call still brings back what ran.
. bench/results/2026-11-26-session17/common.sh
d=/tmp/final
mkdir -p $d
o=$d/log.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-F.xz /tmp/vgeo-F
chmod +x /tmp/vgeo-F
B=F
T0=$SECONDS
pack() { rm -rf $d/*/images; (cd $d && tar czf $OUT/final.tgz .); }
warm $B
timeout 300 /tmp/vgeo-$B bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --sweep 0.25,0.5,1,2,4 --quiet --out $d/scenes > $d/scenes.log 2>&1
echo "== scenes rc=$? t=$((SECONDS - T0))" >> $o; pack
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20,50,100,200 --modes vgeo --sweep 1 --quiet --out $d/scaling > $d/scaling.log 2>&1
echo "== scaling rc=$? t=$((SECONDS - T0))" >> $o; pack
for res in "384 216" "192 108"; do
  set -- $res
  timeout 200 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --width $1 --height $2 --frames 2 --sweep 1 --quiet --out $d/tiny$2 > $d/tiny$2.log 2>&1
  echo "== tiny$2 rc=$? t=$((SECONDS - T0))" >> $o; pack
done
for s in close empty; do
  timeout 60 /tmp/vgeo-$B render .gpu/$s.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/$s-$B.png 2>&1 | grep -E "timed" | sed "s/^/  $s /" >> $o
done
pack
timeout 150 /tmp/vgeo-$B bench --suite full --scenes stress --stress-n 20 --frames 2 --sweep 0.5,1,2 --quiet --out $d/stress > $d/stress.log 2>&1
echo "== stress rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack
