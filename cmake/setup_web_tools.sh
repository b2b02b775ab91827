#!/usr/bin/env bash
# Installs the test-only web tools: the npm packages of tests/web/package.json (a quantized-mesh
# decoder, the Khronos glTF validator, CesiumJS and playwright-core) into tests/web/node_modules,
# from the npm registry, and Debian's Chromium (/usr/bin/chromium), which playwright-core drives:
# it never downloads a browser of its own. Node.js and npm come from Debian when the machine has
# none; the Debian packages go through cmake/setup.sh (which checks its own list too). The tests
# that use these tools skip, saying so, when they are missing; CI installs them first.
# Idempotent and quick once done: npm runs only when package-lock.json differs from the one last
# installed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
extra=(chromium)
command -v npm >/dev/null 2>&1 || extra+=(nodejs npm)
cmake/setup.sh "${extra[@]}"

stamp=tests/web/node_modules/.installed-package-lock.json
if cmp -s tests/web/package-lock.json "$stamp"; then
  echo "setup_web_tools.sh: tests/web/node_modules is up to date"
  exit 0
fi
npm ci --prefix tests/web --no-audit --no-fund --loglevel=error
cp tests/web/package-lock.json "$stamp"
