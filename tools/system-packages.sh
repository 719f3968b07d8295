#!/usr/bin/env bash
# The Debian packages aquagait's pictures need, installed if missing: EGL and
# Mesa's software OpenGL (llvmpipe) for 3D videos without a screen or a GPU.
# Without them everything else works; a 3D swim skips its video and says why.
set -uo pipefail
packages=(libegl1 libgl1-mesa-dri)
missing=()
for package in "${packages[@]}"; do
    dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null; then
    echo "aquagait: no apt-get here; install EGL and Mesa's OpenGL (${missing[*]} on Debian)" \
         "for 3D videos" >&2
    exit 0
fi
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -q && $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" \
    || echo "aquagait: could not install ${missing[*]}; 3D videos will be skipped" >&2
exit 0
