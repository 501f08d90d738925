#!/usr/bin/env bash
# Bundles the Debian runtime that liggghts-poly needs (LIGGGHTS, VTK, OpenMPI and
# their libraries, not the C library) into one folder, for a GPU host that has
# no Debian package archive:
#
#   bash tools/bundle_runtime.sh [OUT] [--with-tests]   # default OUT: runtime/ ; needs apt-get here
#   (--with-tests adds Debian's pytest and LIGGGHTS' tutorials (liggghts-doc), to run tests/test_gpu.py and
#    tools/bench_gpu_decks.py there)
#   (copy OUT and build/ to the GPU host)
#   source OUT/env.sh && liggghts-poly -in in.script
#   source OUT/env.sh && mpirun -np 4 liggghts-poly -in in.script
#
# The folder holds the .deb files (compressed, to travel light); the first
# `source env.sh` unpacks them with dpkg -x, then env.sh points PATH,
# LD_LIBRARY_PATH and OPAL_PREFIX into them (OpenMPI finds its plugins there).
set -euo pipefail
root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$(realpath -m "${1:-$root_dir/runtime}")"
with_tests="${2:-}"
launcher="$root_dir/build/bin/liggghts-poly"
[ -x "$launcher" ] || { echo "ERROR: build first (make)" >&2; exit 1; }

# Libraries the launcher, our library and OpenMPI's programs load, and the packages that own them.
objects=("$launcher" "$root_dir/build/lib/libpolyhedral.so" "$(command -v mpirun)" "$(command -v orted)")
mapfile -t libraries < <(for object in "${objects[@]}"; do
  LD_LIBRARY_PATH="$root_dir/build/lib" ldd "$object" | awk '/=> \// {print $3}'
done | sort -u)
packages=(liggghts libliggghts3 openmpi-bin openmpi-common libopenmpi3)
for library in "${libraries[@]}"; do
  owner="$(dpkg -S "$(realpath "$library")" 2>/dev/null || dpkg -S "$library" 2>/dev/null || true)"
  [ -n "$owner" ] && packages+=("${owner%%:*}")
done
# The C library and its loader come from the host.
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | sort -u | grep -v -x -e libc6 -e libc6-dev)
if [ "$with_tests" = "--with-tests" ]; then
  # liggghts-doc: LIGGGHTS' tutorials, for tests/test_tutorial_decks.py and tools/bench_gpu_decks.py
  packages+=(python3-pytest python3-pluggy python3-iniconfig python3-packaging liggghts-doc)
fi

rm -rf "$out"
mkdir -p "$out/debs"
(cd "$out/debs" && apt-get download "${packages[@]}" 2>/dev/null >/dev/null)
cat > "$out/env.sh" <<ENV
# source this file: the bundled Debian runtime of liggghts-poly
here="\$(cd "\$(dirname "\${BASH_SOURCE[0]}")" && pwd)"
bundle="\${POLY_RUNTIME_DIR:-/tmp/liggghts-poly-runtime}"
if [ ! -x "\$bundle/usr/bin/liggghts" ]; then
  mkdir -p "\$bundle"
  for deb in "\$here"/debs/*.deb; do dpkg -x "\$deb" "\$bundle"; done
fi
export PATH="\$bundle/usr/bin:\$PATH"
export LD_LIBRARY_PATH="\$bundle/usr/lib/x86_64-linux-gnu:\$bundle/usr/lib/x86_64-linux-gnu/openmpi/lib:\$bundle/lib/x86_64-linux-gnu\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
export OPAL_PREFIX="\$bundle/usr"
export PYTHONPATH="\$bundle/usr/lib/python3/dist-packages\${PYTHONPATH:+:\$PYTHONPATH}"
ENV
echo "bundled ${#packages[@]} packages, $(du -sh "$out" | cut -f1) in $out"
