#!/usr/bin/env bash
# Installs the test-only web tools (tests/web/package.json: a quantized-mesh decoder and the
# Khronos glTF validator) into tests/web/node_modules, from the npm registry, with Debian's
# Node.js when the machine has none. The tests that use them skip, saying so, when they are
# missing; CI installs them first.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v npm >/dev/null 2>&1 || cmake/setup.sh nodejs npm
npm ci --prefix tests/web --no-audit --no-fund --loglevel=error
