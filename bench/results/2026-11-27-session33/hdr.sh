#!/bin/bash
# Session 33, device call 1: a cluster's box as grid coordinates in its cull words (format 8, 16
# bytes less per cluster) against a0434d5 (format 7, bounds as six floats).
# O = a0434d5's binary, N = the same tree with the box on the grid (each binary builds its own
# pages from the same meshes at load, or from .vgeo files it builds here).
# 1. Images: each scene's lit image and the close blade's at 1920x1080, 1 px (one frame), N
#    against O byte for byte.
# 2. Times at the default ratio (0.5): stress N=100 and 200 along the full suite's 16-frame path,
#    the five scenes (4 frames), O N N O O N; each bench's summary holds geometry bytes per stored
#    triangle.
# 3. Times at --ratio 0.35 (scans built here by each binary, named by copies of the stress and
#    outdoor scene files; outdoor's box built at load): big and stress N=20 + outdoor, O N N O.
# 4. The close blade and the empty frame, `render --time 64`.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/hdr.txt
setup $o
for b in O N; do
  python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-$b.xz /tmp/vgeo-$b
  chmod +x /tmp/vgeo-$b
done
ls -la /tmp/vgeo-O /tmp/vgeo-N >> $o
warm N
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
echo "== images (N against O)" >> $o
mkdir -p $OUT/diff
for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
  n=$(basename $s .toml)
  for b in O N; do
    timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --stats --out /tmp/img-$n-$b.png > $OUT/img-$n-$b.log 2>&1
  done
  if cmp -s /tmp/img-$n-O.png /tmp/img-$n-N.png; then r=same; else r=DIFFERENT; cp /tmp/img-$n-O.png /tmp/img-$n-N.png $OUT/diff/; fi
  echo "  $n: $r" >> $o
done
echo "== images t=$((SECONDS - T0))" >> $o
pack
run() {
  local b=$1 rep=$2
  local d=$OUT/$b$rep
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== $b$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes stress,foliage,outdoor,indoor,drawcalls --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== $b$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run O a; run N a; run N b; run O b; run O c; run N c
# Ratio 0.35: each binary builds the scans; scene copies name the files.
S=../shared/assets/scanned
for b in O N; do
  mkdir -p /tmp/sc35-$b
  for m in turbineblade bunny lucy; do
    /tmp/vgeo-$b build $S/$m.ply --ratio 0.35 -o /tmp/sc35-$b/$m.vgeo > $OUT/build35-$b-$m.log 2>&1
  done
  for s in stress outdoor; do
    sed -e "s#../../../shared/assets/scanned/\([a-z]*\).ply#/tmp/sc35-$b/\1.vgeo#" assets/scenes/$s.toml > /tmp/sc35-$b/$s.toml
  done
done
grep -h "path" /tmp/sc35-N/*.toml >> $o
run35() {
  local b=$1 rep=$2
  local d=$OUT/r35$b$rep
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes-dir /tmp/sc35-$b --scenes stress --stress-n 100,200 --modes vgeo --sweep 1 --quiet --out $d-big > $d-big.log 2>&1
  echo "== r35$b$rep big rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-$b bench --suite full --scenes-dir /tmp/sc35-$b --scenes stress,outdoor --stress-n 20 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-scenes > $d-scenes.log 2>&1
  echo "== r35$b$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run35 O a; run35 N a; run35 N b; run35 O b
for b in O N; do
  timeout 60 /tmp/vgeo-$b render .gpu/close.toml --width 1920 --height 1080 --time 64 > $OUT/close-$b.log 2>&1
  timeout 60 /tmp/vgeo-$b render .gpu/empty.toml --width 1920 --height 1080 --time 64 > $OUT/empty-$b.log 2>&1
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
