#!/usr/bin/env bash
# Installs the Debian packages the package needs to build, run its examples and test.
# Skips apt-get entirely when everything is already installed.
set -euo pipefail
packages=(liggghts libliggghts-dev libopenmpi-dev openmpi-bin make g++ gcc binutils
          python3 python3-numpy python3-scipy python3-matplotlib python3-pytest
          python3-paraview xvfb xauth    # ParaView's Python under Xvfb: tools/render_scene.py
          libcgal-dev libgmp-dev libmpfr-dev    # test only: the exact overlap reference (tests/test_exact_reference.py)
          liggghts-doc)                         # test only: LIGGGHTS' tutorial meshes (tests/test_tutorial_decks.py)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
