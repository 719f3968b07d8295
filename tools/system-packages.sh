#!/usr/bin/env bash
# The Debian packages aquagait's pictures and tests need, installed if missing:
# EGL and Mesa's software OpenGL (llvmpipe) for 3D videos without a screen or
# a GPU, and Chromium, in which the tests play the HTML export. Without them
# everything else works: a 3D swim skips its video and says why, and the
# browser tests skip.
set -uo pipefail
packages=(libegl1 libgl1-mesa-dri chromium)
missing=()
for package in "${packages[@]}"; do
    dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null; then
    echo "aquagait: no apt-get here; install ${missing[*]} (Debian names) for 3D videos" \
         "and the browser tests" >&2
    exit 0
fi
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -q && $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" \
    || echo "aquagait: could not install ${missing[*]}; 3D videos or browser tests will skip" >&2
exit 0
