#!/usr/bin/env bash
# Headless Chromium for the browser demo's end-to-end tests (`make test-www`): Debian's `chromium`
# package (playwright's own browser downloads are not used). Idempotent; prints the binary's path.
#
#   scripts/setup-browser.sh          # installs with apt-get when missing (needs root or sudo)
#   CHROMIUM=/path/to/chrome ...      # use another Chromium/Chrome binary instead
set -euo pipefail

if [[ -n "${CHROMIUM:-}" ]]; then
  command -v "$CHROMIUM"
  exit 0
fi
for name in chromium chromium-browser google-chrome; do
  if command -v "$name" >/dev/null 2>&1; then
    command -v "$name"
    exit 0
  fi
done

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "setup-browser: installing Debian's chromium" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq >&2
$sudo apt-get install -y -qq --no-install-recommends chromium >&2
command -v chromium
