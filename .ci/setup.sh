#!/usr/bin/env bash
# Installs the system packages vgeo needs on Debian 12 (bookworm): Mesa 25 lavapipe (software Vulkan)
# from bookworm-backports, the Vulkan loader, the Khronos validation layer, and shaderc/glslang/SPIRV-Tools
# for building shaders. Idempotent; quick when everything is already there. Needs root (or sudo).
set -euo pipefail

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

# The Debian archive mirror this machine's active apt sources already use for bookworm (one-line
# `.list` or deb822 `.sources` files; commented lines, `Enabled: no` stanzas and files with other
# extensions are not active), reused for bookworm-backports: this script names no mirror host of its
# own. Only the suite `bookworm` itself with the `main` component counts (not bookworm-security, not
# bookworm-updates), and not a third-party repository: one signed by another key than Debian's
# archive keyring is skipped. APT_ETC (default /etc/apt) is for tests.
APT_ETC=${APT_ETC:-/etc/apt}
apt_files() {
  local f
  for f in "$APT_ETC/sources.list" "$APT_ETC"/sources.list.d/*.list "$APT_ETC"/sources.list.d/*.sources; do
    [ -f "$f" ] && echo "$f"
  done
  return 0
}
# Active entries, one per line: "URI SUITE COMPONENTS... | SIGNED-BY".
apt_entries() {
  local f
  apt_files | while read -r f; do
    case "$f" in
      *.sources)
        awk 'BEGIN { RS = ""; FS = "\n" } {
               uris = ""; suites = ""; comps = ""; signed = ""; enabled = 1; types = ""
               for (i = 1; i <= NF; i++) {
                 line = $i; sub(/^[ \t]+/, "", line)
                 if (line ~ /^#/) continue
                 key = tolower(line); sub(/:.*/, "", key); val = line; sub(/^[^:]*:[ \t]*/, "", val)
                 if (key == "types") types = val
                 else if (key == "uris") uris = val
                 else if (key == "suites") suites = val
                 else if (key == "components") comps = val
                 else if (key == "signed-by") signed = val
                 else if (key == "enabled" && tolower(val) ~ /^(no|false|0)/) enabled = 0
               }
               if (!enabled || types !~ /(^| )deb( |$)/) next
               n = split(uris, u, " "); m = split(suites, s, " ")
               for (a = 1; a <= n; a++) for (b = 1; b <= m; b++) print u[a], s[b], comps, "|", signed
             }' "$f"
        ;;
      *)
        awk '$1 == "deb" {
               signed = ""; i = 2
               if ($2 ~ /^\[/) {
                 while (i <= NF) { if ($i ~ /^signed-by=/) { signed = $i; sub(/^signed-by=/, "", signed); sub(/\]$/, "", signed) }
                                   if ($i ~ /\]$/) { i++; break }; i++ }
               }
               uri = $i; suite = $(i + 1); comps = ""
               for (j = i + 2; j <= NF && $j !~ /^#/; j++) comps = comps " " $j
               print uri, suite, comps, "|", signed
             }' "$f"
        ;;
    esac
  done
}
debian_mirror() {
  apt_entries | awk -F'|' '{
      split($1, a, " "); uri = a[1]; suite = a[2]; main = 0
      for (k = 3; k in a; k++) if (a[k] == "main") main = 1
      signed = $2; gsub(/^[ \t]+|[ \t]+$/, "", signed)
      if (suite != "bookworm" || !main || uri !~ /^[a-z]+:\/\//) next
      if (signed != "" && signed !~ /debian-archive-keyring/) next
      print uri; exit
    }'
}
has_backports() {
  apt_entries | awk '{ if ($2 == "bookworm-backports") found = 1 } END { exit !found }'
}
if [ "${1:-}" = "--print-mirror" ]; then
  mirror=$(debian_mirror)
  if [ -z "$mirror" ]; then
    echo "setup: no active apt source for Debian bookworm (main) found in $APT_ETC" >&2
    exit 1
  fi
  echo "$mirror"
  has_backports && echo "backports: enabled" || echo "backports: not enabled"
  exit 0
fi

# g++ and ca-certificates: the C/C++ parts of dependencies (meshoptimizer, METIS) and crates.io over TLS.
# renderdoc: the capture test (tests/capture.rs) and `vgeo render --capture`.
need=(mesa-vulkan-drivers libvulkan1 vulkan-validationlayers libshaderc-dev glslang-dev spirv-tools pkg-config g++ ca-certificates renderdoc)
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

if ! has_backports; then
  mirror=$(debian_mirror)
  if [ -z "$mirror" ]; then
    echo "setup: no active apt source for Debian bookworm (main) found in $APT_ETC; add bookworm-backports to the apt sources by hand" >&2
    exit 1
  fi
  echo "deb $mirror bookworm-backports main" | $SUDO tee "$APT_ETC/sources.list.d/bookworm-backports.list" >/dev/null
  echo "setup: added bookworm-backports from $mirror"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${need[@]}"
echo "setup: installed ${missing[*]}"
