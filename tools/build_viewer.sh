#!/usr/bin/env bash
# Build the HTML export's viewer (src/aquagait/io/export/viewer/), package data
# that is committed: run this after changing tools/viewer/viewer.js or its pins.
#
# Installs the pinned three.js and esbuild (tools/viewer/package-lock.json) with
# `npm ci`, bundles viewer.js and the parts of three.js it uses into one minified
# IIFE (no module imports: Chromium refuses them from file://), and puts three.js's
# licence and the versions used beside it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
viewer="$root/tools/viewer"
out="$root/src/aquagait/io/export/viewer"

(cd "$viewer" && npm ci --no-audit --no-fund)
mkdir -p "$out"
"$viewer/node_modules/.bin/esbuild" "$viewer/viewer.js" \
    --bundle --format=iife --minify --target=es2020 \
    --legal-comments=none --log-level=warning \
    --outfile="$out/viewer.js"
cp "$viewer/node_modules/three/LICENSE" "$out/THREE-LICENSE"
version() { node -p "require('$viewer/node_modules/$1/package.json').version"; }
printf 'three %s\nesbuild %s\n' "$(version three)" "$(version esbuild)" > "$out/VERSIONS"
echo "built $out/viewer.js ($(wc -c < "$out/viewer.js") bytes): $(tr '\n' ' ' < "$out/VERSIONS")"
