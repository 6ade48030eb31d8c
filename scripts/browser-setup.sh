#!/usr/bin/env bash
# Installs what the live view's browser test needs, only what is missing (idempotent):
# Debian's chromium (headless), and from npm (tests/web, pinned in package-lock.json)
# playwright-core (drives the installed chromium, downloads no browser) and Foxglove's MCAP,
# WebSocket and ROS 2 message libraries (tests/web/foxglove_decode.mjs).
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
if [ ! -x /usr/bin/chromium ]; then
  echo "browser-setup: installing Debian's chromium"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null
fi
command -v npm >/dev/null || { echo "browser-setup: npm (Node.js) is required" >&2; exit 1; }
# node_modules/.installed-from: the lock file it was installed from (reinstall when it changes).
if ! cmp -s tests/web/package-lock.json tests/web/node_modules/.installed-from 2>/dev/null; then
  echo "browser-setup: installing tests/web's npm packages (npm ci)"
  (cd tests/web && npm ci --no-audit --no-fund --silent && cp package-lock.json node_modules/.installed-from)
fi
