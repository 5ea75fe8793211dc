# Sourced by this folder's device scripts (run from the repository root with .gpu/ carried).
D=bench/results/2026-11-26-session17

# setup OUTFILE BINARY...: the Vulkan loader packages, the shared assets, .gpu/vgeo-<B>.gz
# unpacked to /tmp/vgeo-<B>, and the GPU's name and driver as OUTFILE's first lines.
setup() {
  local out=$1; shift
  for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
  if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
  for b in "$@"; do gunzip -c .gpu/vgeo-$b.gz > /tmp/vgeo-$b; chmod +x /tmp/vgeo-$b; done
  nvidia-smi --query-gpu=name,driver_version --format=csv > $out 2>&1
}

# warm BINARY: one untimed bench run, so that the first timed one finds the GPU warm.
warm() {
  timeout 60 /tmp/vgeo-$1 bench --suite full --scenes stress --stress-n 20 --frames 8 --modes vgeo --sweep 1 --quiet --out /tmp/warm > /dev/null 2>&1
}

# summary BENCH_JSON COLUMN...: a line per scene (summary.py).
summary() {
  python3 $D/summary.py "$@"
}

# compare_images OUTFILE TOOL: each scene's lit image and the close blade's (1920x1080, 1 px)
# rendered by /tmp/vgeo-H and /tmp/vgeo-N, and TOOL's line on how N's differs from H's.
compare_images() {
  local out=$1 tool=$2
  for s in assets/scenes/outdoor.toml assets/scenes/indoor.toml assets/scenes/foliage.toml assets/scenes/drawcalls.toml .gpu/close.toml; do
    local n=$(basename $s .toml)
    for b in H N; do
      timeout 60 /tmp/vgeo-$b render $s --width 1920 --height 1080 --out /tmp/img-$n-$b.png > /dev/null 2>&1
    done
    echo "  $n: $(python3 $tool /tmp/img-$n-H.png /tmp/img-$n-N.png 2>&1)" >> $out
  done
}

# setup_xz OUTFILE FILE...: as setup, for binaries carried as .gpu/<FILE>.xz (unpacked to
# /tmp/<FILE>; the device host has no xz, Python's lzma unpacks them).
setup_xz() {
  local out=$1; shift
  for f in .gpu/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
  if [ -d .gpu/assets ]; then mkdir -p ../shared && ln -sfn $PWD/.gpu/assets ../shared/assets; fi
  for b in "$@"; do
    python3 -c "import lzma, sys; open(sys.argv[2], 'wb').write(lzma.open(sys.argv[1]).read())" .gpu/$b.xz /tmp/$b
    chmod +x /tmp/$b
  done
  nvidia-smi --query-gpu=name,driver_version --format=csv > $out 2>&1
}

# pack: everything in $OUT but images into $OUT/h.tgz (call it after each step: what a timeout
# leaves still comes back).
pack() {
  (cd $OUT && tar czf /tmp/h.tgz --exclude='*.png' --exclude='*.svg' --exclude=images --exclude=h.tgz . && cp /tmp/h.tgz $OUT/h.tgz)
}
