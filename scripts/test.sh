#!/usr/bin/env bash
# The whole check, as CI runs it: install, lint, types, layering, tests.
# Usage: bash scripts/test.sh [extra pytest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."

python -m pip install --quiet --disable-pip-version-check -e ".[test]"

# The report's browser test drives Debian's Chromium (no browser download is possible here).
if ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq >/dev/null && apt-get install -y -qq chromium >/dev/null
  else
    echo "scripts/test.sh: Debian's chromium is needed for the report's browser test:" >&2
    echo "  sudo apt-get install -y chromium" >&2
    exit 1
  fi
fi

echo "== ruff";        ruff check src tests benchmarks
echo "== mypy";        mypy
echo "== import-linter"; lint-imports
echo "== pytest";      python -m pytest -q -p no:cacheprovider "$@"
