#!/bin/bash
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
gunzip -c .gpu/vgeo-xp.gz > /tmp/vgeo-xp; chmod +x /tmp/vgeo-xp
for r in 1 2 3; do
for v in "X=1" "XP_NO_LABELS=1" "XP_NO_TS=1" "XP_NO_LABELS=1 XP_NO_TS=1" "XP_SPIN=1"; do
  env $v timeout 60 /tmp/vgeo-xp bench --suite full --record-cpu 8000,1000000 --record-changed 0 --frames 100 --out /tmp/x > /tmp/x.txt 2>&1
  echo "== $v run $r rc=$?"; grep -E "^\| [0-9]" /tmp/x/record_cpu.md | cut -d'|' -f2,6,8
done; done
