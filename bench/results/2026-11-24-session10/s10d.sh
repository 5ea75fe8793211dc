#!/bin/bash
# Session 10, call 8 (generation as in s10c.sh, 4 meshes only): the streamed frame time, settled,
# against all resident, both timed back to back (`--time 64`) on the close-up and the path's end.
# streaming a scene of unique geometry larger than the budget (issue 13,
# acceptance 2-3). 16 meshes (call 6: 14), each 4 bunnies subdivided 3 times with their own seed (17.8 M
# triangles, a .vgeo of ~300 MB each), built here; scenes of 4, 8 and 14 of them rendered along a
# camera path under a 256 MiB budget; a close-up from a cold start (frames to settle) against
# the same view all resident (the 4-mesh scene, which fits).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-S.gz > /tmp/vgeo; gunzip -c .gpu/subdiv.gz > /tmp/subdiv; chmod +x /tmp/vgeo /tmp/subdiv
A=$PWD/.gpu/assets
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
mkdir -p /tmp/big && cd /tmp/big
T0=$(date +%s)
gen() { i=$1; /tmp/subdiv $2/scanned/bunny.ply m$i.ply --levels 3 --copies 4 --seed $i > g$i.log 2>&1 && /tmp/vgeo build m$i.ply -o m$i.vgeo --threads 4 > b$i.log 2>&1; echo "m$i rc=$?" >> b$i.log; rm -f m$i.ply; }
export -f gen
seq 0 3 | xargs -P 4 -I{} bash -c "gen {} $A"
echo "generated in $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
ls -l /tmp/big/*.vgeo >> $OUT/log.txt; du -cb /tmp/big/*.vgeo | tail -1 >> $OUT/log.txt
tail -n 3 /tmp/big/b0.log >> $OUT/log.txt
scene() { n=$1; f=/tmp/big/s$n.toml; : > $f
  for i in $(seq 0 $((n-1))); do printf '[[mesh]]\nname = "m%d"\npath = "/tmp/big/m%d.vgeo"\n\n' $i $i >> $f; done
  for i in $(seq 0 $((n-1))); do printf '[[instance]]\nmesh = "m%d"\ntranslation = [%s, 0, %s]\n\n' $i $(( (i % 4) * 8 ))e-1 $(( (i / 4) * 4 ))e-1 >> $f; done
  cat >> $f <<'T'
[camera]
eye = [0.0, 0.13, 0.22]
target = [0.0, 0.1, 0.0]

[[path]]
eye = [1.2, 0.8, 3.0]
target = [1.2, 0.1, 0.6]

[[path]]
eye = [0.0, 0.15, 0.3]
target = [0.0, 0.1, 0.0]

[[path]]
eye = [0.5, 0.15, 0.3]
target = [0.5, 0.1, 0.0]

[[path]]
eye = [1.3, 0.15, 0.7]
target = [1.3, 0.1, 0.4]

[[path]]
eye = [2.4, 0.2, 1.5]
target = [2.4, 0.1, 1.2]
T
}
scene 4
for mode in stream all; do
  B=""; [ $mode = stream ] && B="--geometry-budget 256 --stream-mib-per-frame 64"
  timeout 100 /tmp/vgeo render /tmp/big/s4.toml $B --frames 40 --time 64 --width 1920 --height 1080 --stats -o /tmp/big/close-$mode.png > $OUT/close-$mode.txt 2>&1
  echo "close-up $mode rc=$?" >> $OUT/log.txt
  timeout 100 /tmp/vgeo render /tmp/big/s4.toml $B --path --frames 120 --time 64 --width 1920 --height 1080 --stats -o /tmp/big/path-$mode.png > $OUT/path-$mode.txt 2>&1
  echo "path end $mode rc=$?" >> $OUT/log.txt
done
cmp /tmp/big/close-stream.png /tmp/big/close-all.png && echo "close-up: streamed == all resident" >> $OUT/log.txt
cmp /tmp/big/path-stream.png /tmp/big/path-all.png && echo "path end: streamed == all resident" >> $OUT/log.txt
grep -H -E "^timed|^GPU time|^triangles|geometry" $OUT/close-*.txt $OUT/path-*.txt >> $OUT/log.txt
echo "total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
