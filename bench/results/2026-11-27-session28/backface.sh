#!/bin/bash
# Session 28, device: F = session 27's release binary (03340c9, the same code as main at cedd6f7), B = F with the
# hardware path dropping the faces a closed solid turns away from a camera outside its box
# (MESH_CLOSED_SOLID, HW_ENTRY_CULL). Two interleaved rounds of the bench scenes (8 frames) and
# stress N = 20 / 100 / 200 (4 frames), vgeo at 1 px; which images differ; the close blade and
# foliage / stress N=20 with every cluster in hardware (`--hw-threshold 0`). One archive (cmp.tgz:
# the log and the bench images that differ). final.sh follows on the same machine.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/log.txt
setup $o F B
T0=$SECONDS
warm B
for r in 1 2; do
  for v in F B; do
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-$v bench --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-$v render .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
  done
done
echo "== images F/B" >> $o
for x in s t; do
  for f in /tmp/su-F-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-B-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
cmp -s /tmp/close-F.png /tmp/close-B.png && echo "  same close" >> $o || echo "  differ close" >> $o
echo "== hardware only (--hw-threshold 0)" >> $o
for v in F B; do
  for s in assets/scenes/foliage.toml .gpu/close.toml; do
    timeout 120 /tmp/vgeo-$v render $s --width 1920 --height 1080 --frames 8 --hw-threshold 0 --time 16 --out /tmp/hw-$v.png 2>&1 | grep -E "timed" | sed "s|^|  $v $s |" >> $o
  done
  timeout 150 /tmp/vgeo-$v bench --suite full --scenes stress --stress-n 20 --frames 2 --modes vgeo --sweep 1 --hw-threshold 0 --quiet --out /tmp/hw-$v-t > /tmp/hw-$v-t.log 2>&1
  echo "  $v stress N=20:" >> $o; python3 bench/results/2026-11-26-session23/passes.py /tmp/hw-$v-t/bench.json >> $o 2>&1 || tail -3 /tmp/hw-$v-t.log >> $o
done
echo "== total $((SECONDS - T0)) s" >> $o
mkdir -p /tmp/cmp/diff && cp $o /tmp/cmp/ && for f in /tmp/su-F-r1-s/images/*.png; do n=$(basename $f); cmp -s $f /tmp/su-B-r1-s/images/$n || { cp $f /tmp/cmp/diff/F-$n; cp /tmp/su-B-r1-s/images/$n /tmp/cmp/diff/B-$n; }; done
cd /tmp/cmp && tar czf $OUT/cmp.tgz . && rm -f $OUT/log.txt
