#!/bin/bash
# Session 15, call 1 (H100): early depth rejection in vis_write (a plain read of the depth word
# before the atomicMax). One binary (.gpu/vgeo-H.gz, session 14's), run with and without
# VGEO_SHADER_DIR=.gpu/ez (holding only the new common/visbuffer.glsl), interleaved, 8 frames,
# 1920x1080, 1 px: foliage and stress N=100 hybrid / HW only / SW only, indoor and outdoor hybrid.
# Images: `vgeo render` of foliage, indoor and stress N=20 with and without, compared with cmp.
for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
gunzip -c .gpu/vgeo-H.gz > /tmp/vgeo; chmod +x /tmp/vgeo; V=/tmp/vgeo
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > $OUT/log.txt 2>&1
T0=$(date +%s)
# warm-up
timeout 60 $V bench --suite full --scenes outdoor --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
run() { # tag scene thr extra...
  tag=$1; scene=$2; thr=$3; shift 3
  for ez in base ez; do
    if [ $ez = ez ]; then export VGEO_SHADER_DIR=$PWD/.gpu/ez; else unset VGEO_SHADER_DIR; fi
    d=/tmp/r-$tag-$ez
    timeout 120 $V bench --suite full --scenes $scene --modes vgeo --sweep 1 --hw-threshold $thr "$@" --quiet --out $d > $d.log 2>&1
    echo "== $tag $ez rc=$? t=$(( $(date +%s) - T0 ))" >> $OUT/log.txt
    grep -E "^\| vgeo" $d/bench.md >> $OUT/log.txt 2>/dev/null || tail -3 $d.log >> $OUT/log.txt
    grep -o '"raster_[a-z_]*[^]]*' $d/bench.json | head -4 >> $OUT/log.txt 2>/dev/null
  done
  unset VGEO_SHADER_DIR
}
run foliage-hybrid foliage 32 --frames 8
run foliage-sw foliage 100000 --frames 8
run indoor indoor 32 --frames 8
run outdoor outdoor 32 --frames 8
run stress100 stress 32 --stress-n 100 --frames 4
run foliage-hw foliage 0 --frames 4
run stress100-hw stress 0 --stress-n 100 --frames 2
for s in foliage indoor; do
  for ez in base ez; do
    if [ $ez = ez ]; then export VGEO_SHADER_DIR=$PWD/.gpu/ez; else unset VGEO_SHADER_DIR; fi
    timeout 60 $V render assets/scenes/$s.toml --width 1920 --height 1080 --out /tmp/img-$s-$ez.png > /tmp/img-$s-$ez.log 2>&1
    echo "render $s $ez rc=$?" >> $OUT/log.txt
  done
  unset VGEO_SHADER_DIR
  cmp /tmp/img-$s-base.png /tmp/img-$s-ez.png && echo "IMAGES EQUAL $s" >> $OUT/log.txt || echo "IMAGES DIFFER $s" >> $OUT/log.txt
done
echo "== total $(( $(date +%s) - T0 )) s" >> $OUT/log.txt
