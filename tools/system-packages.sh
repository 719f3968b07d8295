#!/usr/bin/env bash
# What aquagait's pictures and tests need from outside PyPI, installed if missing:
# - Debian packages: EGL and Mesa's software OpenGL (llvmpipe) for 3D videos
#   without a screen or a GPU, and Chromium, in which the tests play the HTML
#   export;
# - from npm, into tools/node: Khronos's glTF validator, which the tests run
#   on the glTF export (tools/gltf-validate.mjs).
# Without them everything else works: a 3D swim skips its video and says why,
# and the browser and validator tests skip.
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"

install_debian() {
    local packages=(libegl1 libgl1-mesa-dri chromium) missing=()
    command -v npm >/dev/null || packages+=(nodejs npm)  # any Node with npm will do
    for package in "${packages[@]}"; do
        dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if ! command -v apt-get >/dev/null; then
        echo "aquagait: no apt-get here; install ${missing[*]} (Debian names) for 3D videos" \
             "and the browser and validator tests" >&2
        return 0
    fi
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -q && $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" \
        || echo "aquagait: could not install ${missing[*]}; 3D videos or some tests will skip" >&2
}

install_npm() {
    if ! command -v npm >/dev/null; then
        echo "aquagait: no npm; the glTF validator test will skip" >&2
        return 0
    fi
    [ -d "$here/node/node_modules/gltf-validator" ] && return 0
    npm ci --prefix "$here/node" --no-audit --no-fund --loglevel=error \
        || echo "aquagait: could not install the glTF validator from npm; its test will skip" >&2
}

install_debian
install_npm
exit 0
