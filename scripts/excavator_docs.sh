#!/usr/bin/env bash
# Regenerate the example excavator's spec sheet figures in docs/img (docs/excavator.md).
set -euo pipefail
cd "$(dirname "$0")/.."
m=examples/excavator_machine.toml
excavkin excavator ranges "$m" --plot docs/img/excavator-working-range.png --force
excavkin excavator forces "$m" --samples 41 --map docs/img/excavator-force --force
excavkin excavator stability "$m" --samples 31 --map docs/img/excavator-stability --force
excavkin excavator lift "$m" --plot docs/img/excavator-lift-chart.png --force
excavkin excavator pins "$m" --samples 31 --plot docs/img/excavator-pins-maxima.png --map docs/img/excavator-pins --force
excavkin excavator cycle "$m" --plot docs/img/excavator-cycle-power.png --force >/dev/null
excavkin excavator dig "$m" --width 1.2m --soil clay --samples 21 --plot docs/img/excavator-dig.png --force
