#!/usr/bin/env bash
# A Vulkan driver for the native wgpu tests and benchmark (`make test-gpu`, `make bench-gpu`;
# cargo feature `wgpu`): where no Vulkan ICD is installed, Debian's mesa-vulkan-drivers (Mesa's
# lavapipe, a software Vulkan device on the CPU: `vulkaninfo` shows llvmpipe) and vulkan-tools.
# A machine with a GPU driver already has an ICD and is left alone. Idempotent.
#
#   scripts/setup-gpu.sh          # installs with apt-get when missing (needs root or sudo)
set -euo pipefail

icd_dirs=(/usr/share/vulkan/icd.d /etc/vulkan/icd.d /usr/local/share/vulkan/icd.d)
has_icd() {
  if [[ -n "${VK_ICD_FILENAMES:-}${VK_DRIVER_FILES:-}" ]]; then return 0; fi
  for d in "${icd_dirs[@]}"; do
    if compgen -G "$d/*.json" >/dev/null; then return 0; fi
  done
  return 1
}

if has_icd && command -v vulkaninfo >/dev/null 2>&1; then
  vulkaninfo --summary 2>/dev/null | grep -m1 deviceName | sed 's/^[[:space:]]*/setup-gpu: /' >&2 || true
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "setup-gpu: installing Mesa's software Vulkan (mesa-vulkan-drivers) and vulkan-tools" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq >&2
$sudo apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers vulkan-tools >&2
vulkaninfo --summary 2>/dev/null | grep -m1 deviceName | sed 's/^[[:space:]]*/setup-gpu: /' >&2 || true
