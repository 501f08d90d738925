#!/usr/bin/env bash
# Installs the Debian packages the package needs to build, run its examples and test.
# Skips apt-get entirely when everything is already installed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
packages=(liggghts libliggghts-dev libopenmpi-dev openmpi-bin make g++ gcc binutils
          python3 python3-numpy python3-scipy python3-matplotlib python3-pytest
          python3-pytest-xdist                  # make test: the suite's files on two processes
          python3-paraview xvfb xauth    # ParaView's Python under Xvfb: tools/render_scene.py
          libcgal-dev libgmp-dev libmpfr-dev    # test only: the exact overlap reference (tests/test_exact_reference.py)
          liggghts-doc)                         # test only: LIGGGHTS' tutorial meshes (tests/test_tutorial_decks.py)
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# VTK's headers, for dump polyhedron/vtk (it writes through the VTK 9 libraries LIGGGHTS already links).
# libvtk9-dev cannot be installed beside python3-paraview (it depends on python3-vtk9, which conflicts),
# so its package, of the same version as the installed libraries, is unpacked under build-deps/.
vtk_unpacked="$root/build-deps/libvtk9-dev"
if [ ! -f /usr/include/vtk-9.1/vtkXMLPPolyDataWriter.h ] &&
   [ ! -f "$vtk_unpacked/usr/include/vtk-9.1/vtkXMLPPolyDataWriter.h" ]; then
  version="$(dpkg-query -W -f='${Version}' libvtk9.1 2>/dev/null)" ||
    { echo "tools/debian_deps.sh: libvtk9.1 (VTK 9.1, which liggghts depends on) is not installed" >&2; exit 1; }
  download="$(mktemp -d)"
  chmod 777 "$download"    # apt-get download writes as the _apt user where it can
  echo "unpacking the headers of libvtk9-dev $version under build-deps/"
  # The installed libraries' own version; else (the mirror has moved on to another Debian revision of VTK 9.1,
  # whose headers are the same) the one apt offers.
  fetch() { (cd "$download" && apt-get download -qq "$@" 2>/dev/null); }
  fetch "libvtk9-dev=$version" || { $sudo apt-get update -qq && fetch "libvtk9-dev=$version"; } || fetch libvtk9-dev ||
    { echo "tools/debian_deps.sh: could not download libvtk9-dev (VTK's headers for dump polyhedron/vtk)" >&2; exit 1; }
  rm -rf "$vtk_unpacked" && mkdir -p "$vtk_unpacked"
  dpkg-deb -x "$download"/libvtk9-dev_*.deb "$vtk_unpacked"
  rm -rf "$download"
fi
