#!/bin/sh
# Renders every SVG of a `wogan report` output directory to PNG beside it, to look at the
# pictures without a browser. Needs rsvg-convert (Debian/Ubuntu: apt-get install librsvg2-bin).
# Usage: scripts/tools/render_report_pngs.sh DIR
set -eu
dir=${1:?usage: $0 DIR}
command -v rsvg-convert >/dev/null || { echo "rsvg-convert not found (apt-get install librsvg2-bin)" >&2; exit 2; }
for svg in "$dir"/*.svg; do
    [ -e "$svg" ] || continue
    rsvg-convert "$svg" -o "${svg%.svg}.png"
    echo "${svg%.svg}.png"
done
