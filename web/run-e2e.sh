#!/usr/bin/env bash
# Builds the web app and runs its end-to-end tests headless in Debian's
# chromium against `rigel serve` ($RIGEL_BIN, default ../build/release/apps/cli/rigel).
# Extra arguments go to `playwright test` (e.g. -g "undo").
set -euo pipefail
cd "$(dirname "$0")"
export RIGEL_BIN="$(realpath "${RIGEL_BIN:-../build/release/apps/cli/rigel}")"
if [[ ! -x "$RIGEL_BIN" ]]; then
  echo "run-e2e.sh: no rigel binary at $RIGEL_BIN (build it, or set RIGEL_BIN)" >&2
  exit 2
fi
if [[ ! -x /usr/bin/chromium && -z "${CHROMIUM:-}" ]]; then
  echo "run-e2e.sh: /usr/bin/chromium is missing (apt-get install chromium), or set CHROMIUM" >&2
  exit 2
fi
if [[ ! -d node_modules || package-lock.json -nt node_modules/.package-lock.json ]]; then
  npm ci --no-audit --no-fund
fi
npm run --silent build
# Playwright must not download browsers; it uses /usr/bin/chromium (playwright.config.ts).
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
exec npx playwright test "$@"
