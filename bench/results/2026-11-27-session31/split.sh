#!/bin/bash
# Session 31, device call 5: issue 14's acceptance 3 at this session's final binary F (e71d988):
# the default SW/HW split (`auto`, chosen by measured frame time) against software only
# (`--hw-threshold 100000`) on every scene (the four scenes and stress N=20 along 8 frames, stress
# N=100 along the full suite's 16), twice, interleaved; hardware only (`--hw-threshold 0`) on
# stress N=100 and foliage (4 frames) with the vertex path (the default) and the mesh path.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/split.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-F.xz /tmp/vgeo-F
chmod +x /tmp/vgeo-F
warm F
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
run() {
  local name=$1 rep=$2 hw=$3
  local d=$OUT/$name$rep
  timeout 200 /tmp/vgeo-F bench --suite full --scenes outdoor,indoor,foliage,drawcalls,stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet $hw --out $d-scenes > $d-scenes.log 2>&1
  echo "== $name$rep scenes rc=$? t=$((SECONDS - T0))" >> $o
  timeout 200 /tmp/vgeo-F bench --suite full --scenes stress --stress-n 100 --modes vgeo --sweep 1 --quiet $hw --out $d-n100 > $d-n100.log 2>&1
  echo "== $name$rep n100 rc=$? t=$((SECONDS - T0))" >> $o
  pack
}
run auto a ""; run sw a "--hw-threshold 100000"; run sw b "--hw-threshold 100000"; run auto b ""
for p in vertex mesh; do
  timeout 200 /tmp/vgeo-F bench --suite full --scenes foliage,stress --stress-n 100 --frames 4 --modes vgeo --sweep 1 --quiet --hw-threshold 0 --hw-path $p --out $OUT/hw-$p > $OUT/hw-$p.log 2>&1
  echo "== hw $p rc=$? t=$((SECONDS - T0))" >> $o
  pack
done
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
