#!/bin/bash
# Session 11, call 3: session 10's scenes of unique geometry (s10c.sh: 16 meshes of 4 bunnies
# subdivided 3 times with their own seed, 4.12 GiB of .vgeo) rendered along the path under a 256 MiB
# budget with 4, 8 and 16 of them, now that pages carry their clusters: what the scene's geometry
# buffers hold per buffer (`--stats`: "scene buffers used") against the scene size (issue 13,
# acceptance 3).
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets
gunzip -c .gpu/vgeo-N.gz > /tmp/vgeo; gunzip -c .gpu/subdiv.gz > /tmp/subdiv; chmod +x /tmp/vgeo /tmp/subdiv
A=$PWD/.gpu/assets
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/log.txt
mkdir -p /tmp/big && cd /tmp/big
T0=$(date +%s)
gen() { i=$1; /tmp/subdiv $2/scanned/bunny.ply m$i.ply --levels 3 --copies 4 --seed $i > g$i.log 2>&1 && /tmp/vgeo build m$i.ply -o m$i.vgeo --threads 4 > b$i.log 2>&1; echo "m$i rc=$?" >> b$i.log; rm -f m$i.ply; }
export -f gen
seq 0 15 | xargs -P 4 -I{} bash -c "gen {} $A"
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
for n in 4 8 16; do scene $n; done
for n in 4 8 16; do
  T1=$(date +%s)
  timeout 90 /tmp/vgeo render /tmp/big/s$n.toml --geometry-budget 256 --stream-mib-per-frame 64 --path --frames 120 --width 1920 --height 1080 --stats -o /tmp/big/p$n.png > $OUT/path$n.txt 2>&1
  echo "path s$n rc=$? in $(( $(date +%s) - T1 )) s" >> $OUT/log.txt
done
for n in 4 8 16; do echo "== s$n" >> $OUT/log.txt; grep -E "scene buffers used|geometry [0-9.]* MiB" $OUT/path$n.txt | tail -2 >> $OUT/log.txt; grep "^  frame 120" $OUT/path$n.txt >> $OUT/log.txt; done
echo "total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
