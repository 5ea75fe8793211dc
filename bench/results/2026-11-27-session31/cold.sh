#!/bin/bash
# Session 31, device call 2 (H's binary left out: the carry limit; its figures are call 1's):
# N = the session's starting binary (dc2138c) with a frame
# without a previous HZB selecting its occluders (pass occluder_select; the main phase draws the
# nearest distance bins whose bounding-sphere discs cover COLD_OCCLUDER_COVER = 4 screens).
# Shader-directory variants of N: KX = no selection (a cold frame draws everything first, as H,
# but after occluder_select); K1 / K2 / K8 = cover 1 / 2 / 8 screens; S = a small instance's
# one-cluster table cut emitted without testing the cluster again (call 1's S1); S2 = S only for
# instances under 2 px; K2S = K2 and S.
# Stress N=100 and 200 along the full suite's 16-frame path (its default), the five scenes
# (4 frames), vgeo at 1 px.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/cold.txt
setup $o
for b in N; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
warm N
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 scenes=$2 rep=$3
  local d=$OUT/$name$rep
  local bin=N sd=""
  [ $name != N ] && sd="--shader-dir .gpu/sd/$name"
  timeout 200 /tmp/vgeo-$bin bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet $sd --out $d-big > $d-big.log 2>&1
  echo "== $name$rep big rc=$? t=$((SECONDS - T0))" >> $o
  if [ $scenes = 1 ]; then
    timeout 200 /tmp/vgeo-$bin bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet $sd --out $d-scenes > $d-scenes.log 2>&1
    echo "== $name$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  fi
  pack
}
run KX 1 a; run N 1 a; run K2 1 a; run K1 0 a; run K8 0 a; run S 1 a; run S2 1 a; run K2S 1 a
run N 1 b; run KX 1 b; run K2S 1 b; run S2 0 b
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
