#!/usr/bin/env bash
# Installs the system packages vgeo needs on Debian 12 (bookworm): Mesa 25 lavapipe (software Vulkan)
# from bookworm-backports, the Vulkan loader, the Khronos validation layer, and shaderc/glslang/SPIRV-Tools
# for building shaders. Idempotent; quick when everything is already there. Needs root (or sudo).
set -euo pipefail

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

# g++ and ca-certificates: the C/C++ parts of dependencies (meshoptimizer, METIS) and crates.io over TLS.
need=(mesa-vulkan-drivers libvulkan1 vulkan-validationlayers libshaderc-dev glslang-dev spirv-tools pkg-config g++ ca-certificates)
missing=()
for p in "${need[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# lavapipe must be Mesa 25 (Vulkan 1.4, 64-bit buffer atomics), i.e. from bookworm-backports.
mesa=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
case "$mesa" in 2[5-9].*|[3-9][0-9].*) ;; *) missing+=(mesa-vulkan-drivers) ;; esac

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: system packages present (mesa-vulkan-drivers $mesa)"
  exit 0
fi

# The mirror that serves bookworm on this machine (one-line .list or deb822 .sources), reused for
# bookworm-backports: this script names no mirror host of its own.
debian_mirror() {
  local f
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    awk '$1 == "deb" && $0 ~ / bookworm( |$)/ { for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) { print $i; exit } }' "$f"
  done
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk 'BEGIN { RS = ""; FS = "\n" } {
           uri = ""; ok = 0
           for (i = 1; i <= NF; i++) {
             if ($i ~ /^URIs:/) { split($i, a, " "); uri = a[2] }
             if ($i ~ /^Suites:/ && $i ~ / bookworm( |$)/) ok = 1
           }
           if (ok && uri != "") print uri
         }' "$f"
  done
}
if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  mirror=$(debian_mirror | head -n 1)
  if [ -z "$mirror" ]; then
    echo "setup: no apt source for bookworm found; add bookworm-backports to the apt sources by hand" >&2
    exit 1
  fi
  echo "deb $mirror bookworm-backports main" | $SUDO tee /etc/apt/sources.list.d/bookworm-backports.list >/dev/null
  echo "setup: added bookworm-backports from $mirror"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${need[@]}"
echo "setup: installed ${missing[*]}"
