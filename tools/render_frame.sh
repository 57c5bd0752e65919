#!/usr/bin/env bash
# Renders one frame of an XDMF time series to a PNG with ParaView, headless.
# Usage: tools/render_frame.sh OUT/case.xdmf [--field density] [--time last|N]
#                              [--out frame.png] [--size 1200x900]
# (all options: tools/render_frame.sh --help)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

for tool in pvbatch xvfb-run; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "render_frame: $tool not found; run tools/install-deps.sh (as root)" >&2
    exit 1
  fi
done

exec xvfb-run -a pvbatch "$here/render_frame.py" "$@"
