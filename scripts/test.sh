#!/usr/bin/env bash
# The whole check, as CI runs it: install, lint, types, layering, tests.
# Usage: bash scripts/test.sh [extra pytest arguments]
#
# It installs the project and its test extras into a fresh virtual environment of its own, so
# that a dependency missing from pyproject.toml fails here as it fails on a new machine
# (packages installed by hand elsewhere are not seen). EXCAVKIN_TEST_VENV=DIR reuses (or makes)
# the environment DIR instead, for quicker runs while developing.
set -euo pipefail
cd "$(dirname "$0")/.."

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
venv=${EXCAVKIN_TEST_VENV:-$work/test-venv}
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
export PATH="$venv/bin:$PATH" VIRTUAL_ENV="$venv"
hash -r
echo "== install into $venv"
python -m pip install --quiet --disable-pip-version-check -e ".[test,docs]"

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

echo "== ruff";        ruff check src tests benchmarks && ruff format --check src tests benchmarks scripts
echo "== mypy";        mypy
echo "== import-linter"; lint-imports
echo "== docs";        NO_MKDOCS_2_WARNING=1 mkdocs build --strict --quiet -d "$(mktemp -d)/site"
# A newcomer's plain install: the wheel, non-editable, in a fresh virtual environment, runs the
# demo on the built-in model and reproduces a paper (the examples travel in the wheel).
echo "== wheel"
python -m pip wheel --quiet --disable-pip-version-check --no-deps -w "$work/dist" .
python -m venv "$work/venv"
"$work/venv/bin/pip" install --quiet --disable-pip-version-check "$work"/dist/*.whl
(cd "$work" && "$work/venv/bin/excavkin" demo --out-dir demo >/dev/null \
   && test -s demo/fourbar.csv && test -s demo/fourbar-report.html \
   && "$work/venv/bin/excavkin" reproduce pasika --out-dir pasika >/dev/null \
   && test -s pasika/pasika-fig3.png)
echo "wheel: demo and reproduce ran from a non-editable install"

echo "== pytest";      python -m pytest -q -p no:cacheprovider "$@"
