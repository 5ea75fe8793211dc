#!/bin/bash
# vgeo's stress scene in Bevy 0.19.1's virtual geometry (meshlets) on the device machine, beside
# `vgeo bench --scenes stress` in the same call. Run from the repository root:
#
#   bash bench/peers/bevy/run.sh [BIN_GZ] [MESH] [OUT_DIR]
#
#   BIN_GZ   the harness, built, stripped and gzipped here (default .gpu/vgeo-peer-bevy.gz; see
#            README.md: `cargo build --release` in bench/peers/bevy, then gzip -9)
#   MESH     the stress scene's mesh (default .gpu/assets/scanned/turbineblade.ply, else
#            shared/assets/scanned/turbineblade.ply, else ../shared/assets/scanned/turbineblade.ply)
#   OUT_DIR  results (default $OUT/bevy, or /tmp/bevy-peer without $OUT)
#
# Environment: BEVY_NS (default "8 20 50 100"); BEVY_TIMEOUTS (seconds per N, same order, default
# "60 75 120 240": 495 s at most, under the device tool's 600 s a command; with vgeo's own run in
# the same call, lower them or the Ns); BEVY_FRAMES (default 16, vgeo's full suite); BEVY_PNG=0 to
# skip the images; BEVY_ARGS (more arguments for every run, e.g. "--warmup-passes 2").
#
# Per N: bevy-nN.json (GPU ms per frame of the path and their statistics), bevy-nN.log (stderr),
# bevy-nN.png (the path's middle frame, as vgeo bench's image); summary.md gathers one line per N
# and the exit codes. A run that fails (exit code != 0: missing GPU features, out of memory,
# panic, timeout 124) is listed as such and the next N still runs.
set -u
BIN_GZ=${1:-.gpu/vgeo-peer-bevy.gz}
MESH=${2:-}
if [ -z "$MESH" ]; then
  for m in .gpu/assets/scanned/turbineblade.ply shared/assets/scanned/turbineblade.ply \
           ../shared/assets/scanned/turbineblade.ply; do
    [ -f "$m" ] && { MESH=$m; break; }
  done
fi
OUT_DIR=${3:-${OUT:+$OUT/bevy}}
OUT_DIR=${OUT_DIR:-/tmp/bevy-peer}
NS=(${BEVY_NS:-8 20 50 100})
TIMEOUTS=(${BEVY_TIMEOUTS:-60 75 120 240})
FRAMES=${BEVY_FRAMES:-16}
mkdir -p "$OUT_DIR"
if [ ! -f "$BIN_GZ" ] || [ -z "$MESH" ] || [ ! -f "$MESH" ]; then
  echo "run.sh: need the gzipped harness ($BIN_GZ) and the mesh (${MESH:-not found})" | tee "$OUT_DIR/summary.md"
  exit 2
fi
BIN=/tmp/vgeo-peer-bevy
gunzip -c "$BIN_GZ" > $BIN && chmod +x $BIN
{
  echo "# Bevy peer: vgeo's stress scene, Bevy 0.19.1 meshlets"
  echo
  echo "host: $(nproc) cores; GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
  echo "mesh: $MESH; frames: $FRAMES; 1920x1080"
  echo
  echo "| run | N | instances | scene triangles | GPU ms | wall ms |"
  echo "|---|---|---|---|---|---|"
} > "$OUT_DIR/summary.md"
codes=""
for i in "${!NS[@]}"; do
  n=${NS[$i]}
  t=${TIMEOUTS[$i]:-300}
  png=()
  [ "${BEVY_PNG:-1}" = 1 ] && png=(--png "$OUT_DIR/bevy-n$n.png")
  t0=$SECONDS
  # The harness's own watchdog exits 124 a little before timeout(1) would kill it.
  timeout -k 10 "$t" $BIN --n "$n" --mesh "$MESH" --frames "$FRAMES" --timeout $((t - 5)) \
    --out "$OUT_DIR/bevy-n$n.json" "${png[@]}" ${BEVY_ARGS:-} \
    > /dev/null 2> "$OUT_DIR/bevy-n$n.log"
  rc=$?
  codes="$codes n$n=$rc($((SECONDS - t0))s)"
  line=$(grep '^| bevy' "$OUT_DIR/bevy-n$n.log" | tail -1)
  if [ $rc = 0 ] && [ -n "$line" ]; then
    echo "$line" >> "$OUT_DIR/summary.md"
  else
    err=$(grep -m1 'error' "$OUT_DIR/bevy-n$n.log" | cut -c1-300)
    echo "| bevy FAILED rc=$rc | N=$n | | | ${err:-see bevy-n$n.log} | |" >> "$OUT_DIR/summary.md"
  fi
done
echo >> "$OUT_DIR/summary.md"
echo "exit codes (seconds):$codes" >> "$OUT_DIR/summary.md"
cat "$OUT_DIR/summary.md"
