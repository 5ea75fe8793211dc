#!/bin/bash
# Session 32, device call 4: call 2's error measurement for the scans built at ratio 0.35
# (outdoor, 2 frames; stress N=20 at 384x216, 2 frames; brute and vgeo at 0.5, 1, 1.5, 2 px),
# binary O = d30e715, the files of call 2 (.gpu/rx, .gpu/sc-0.35).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/err35.txt
setup $o
python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/vgeo-O.xz /tmp/vgeo-O
chmod +x /tmp/vgeo-O
T0=$SECONDS
pack() { (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz); }
r=0.35; d=$OUT/e$r
timeout 100 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes outdoor --frames 2 --modes brute,vgeo --sweep 0.5,1,1.5,2 --quiet --out $d-outdoor > $d-outdoor.log 2>&1
echo "== e$r outdoor rc=$? t=$((SECONDS - T0))" >> $o
timeout 100 /tmp/vgeo-O bench --suite full --scenes-dir .gpu/sc-$r --scenes stress --stress-n 20 --width 384 --height 216 --frames 2 --modes brute,vgeo --sweep 0.5,1,1.5,2 --quiet --out $d-tiny216 > $d-tiny216.log 2>&1
echo "== e$r tiny216 rc=$? t=$((SECONDS - T0))" >> $o
echo "== total $((SECONDS - T0)) s" >> $o
pack; cd $OUT && find $OUT -mindepth 1 ! -name h.tgz -delete
