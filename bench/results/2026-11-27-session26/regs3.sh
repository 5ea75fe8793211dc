#!/bin/bash
# Session 26, device: R3 = R1 (00dafd2's raster_sw) whose row and box walks step their edge
# functions from the triangle's dx / dy instead of holding the steps (and count the row in int),
# against R1 (both through `--shader-dir` on the binary of 17bbf70). Bench scenes (8 frames),
# stress N = 20 / 100 / 200 (4 frames), the close blade, meadow.toml. Two interleaved rounds;
# images R3 against R1.
. bench/results/2026-11-26-session17/common.sh
o=$OUT/regs3.txt
setup $o F
T0=$SECONDS
warm F
for r in 1 2; do
  for v in R1 R3; do
    sd=""; [ -d .gpu/sd/$v ] && sd="--shader-dir .gpu/sd/$v"
    d=/tmp/su-$v-r$r
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes outdoor,indoor,foliage,drawcalls --frames 8 --modes vgeo --sweep 1 --quiet --out $d-s > $d-s.log 2>&1
    timeout 150 /tmp/vgeo-F bench $sd --suite full --scenes stress --stress-n 20,100,200 --frames 4 --modes vgeo --sweep 1 --quiet --out $d-t > $d-t.log 2>&1
    echo "== r$r $v t=$((SECONDS - T0))" >> $o
    for x in s t; do python3 bench/results/2026-11-26-session23/passes.py $d-$x/bench.json >> $o 2>&1 || tail -3 $d-$x.log >> $o; done
    timeout 60 /tmp/vgeo-F render $sd .gpu/close.toml --width 1920 --height 1080 --frames 8 --time 64 --out /tmp/close-$v.png 2>&1 | grep -E "timed" | sed "s/^/  close /" >> $o
    timeout 100 /tmp/vgeo-F render $sd .gpu/meadow.toml --width 1920 --height 1080 --frames 8 --time 64 --stats --out /tmp/meadow-$v.png > /tmp/meadow-$v.log 2>&1
    grep -E "timed|raster_sw|main:" /tmp/meadow-$v.log | sed "s/^/  meadow /" >> $o
  done
done
echo "== images R1/R3" >> $o
for x in s t; do
  for f in /tmp/su-R1-r1-$x/images/*.png; do
    n=$(basename $f); cmp -s $f /tmp/su-R3-r1-$x/images/$n && echo "  same $n" >> $o || echo "  differ $n" >> $o
  done
done
for s in close meadow; do cmp -s /tmp/$s-R1.png /tmp/$s-R3.png && echo "  same $s" >> $o || echo "  differ $s" >> $o; done
echo "== total $((SECONDS - T0)) s" >> $o
cd $OUT && tar czf /tmp/c.tgz regs3.txt && rm -rf $OUT/* && mv /tmp/c.tgz $OUT/
