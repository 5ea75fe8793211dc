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

if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee /etc/apt/sources.list.d/bookworm-backports.list >/dev/null
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${need[@]}"
echo "setup: installed ${missing[*]}"
