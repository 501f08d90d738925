#!/usr/bin/env bash
# dump polyhedron/vtk: bytes and seconds per snapshot, per file format (doc/benchmarks.md, "Particle output").
#
#   bash tools/bench_dump_vtk.sh ["SHAPE:N ..."] [ranks] ["FORMAT ..."]
#
#   scenes   default "rock_40:300 rock_40:5000 schoenhardt:1011500": the hopper's rocks at its two sizes and the
#            packed bed's count, N particles on the lattice of examples/gravity_packing/make_packing.py (rock_40
#            scaled to the Schönhardt polyhedron's bounding radius, so no two touch)
#   ranks    MPI ranks (default 2)
#   formats  of: ascii (dump_modify binary no), raw (compressor none), zlib (the default, level 1), zlib1..zlib9
#            (compression_level), lz4, pvtp (zlib, a piece per rank); default "ascii raw zlib lz4 pvtp". FORMATS=legacy for a launcher from before
#            dump_modify binary/compressor (ASCII .vtp by hand, commit cb9c721 and older).
#   LAUNCHER liggghts-poly to time (default build/bin/liggghts-poly)
#
# Each run reads the lattice, sets up once (run 0), then writes SNAPSHOTS (default 3) snapshots in a `run` of as
# many steps with the dump every step; seconds per snapshot = LIGGGHTS' "Outpt time" of that run / SNAPSHOTS,
# bytes = the files of the last snapshot (index and pieces for pvtp). Work files in $WORK (default a temporary
# directory, removed at the end).
set -euo pipefail
shopt -s nullglob
root="$(cd "$(dirname "$0")/.." && pwd)"
scenes=${1:-"rock_40:300 rock_40:5000 schoenhardt:1011500"}
ranks=${2:-2}
formats=${3:-${FORMATS:-"ascii raw zlib lz4 pvtp"}}
launcher=${LAUNCHER:-$root/build/bin/liggghts-poly}
snapshots=${SNAPSHOTS:-3}
work=${WORK:-$(mktemp -d)}
[ -z "${WORK:-}" ] && trap 'rm -rf "$work"' EXIT
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
python=/usr/bin/python3

echo "# $(date -u +%FT%TZ) $(hostname), nproc $(nproc), $(lscpu | sed -n 's/^Model name: *//p'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# commit $(git -C "$root" rev-parse --short HEAD) (package sources last changed in $(git -C "$root" log -1 --format=%h -- src gpu Makefile Makefile.package)$(git -C "$root" diff --quiet HEAD -- src gpu || echo ', modified')); launcher $launcher; $ranks ranks"
printf "| scene | particles | triangles | format | files | bytes per snapshot | bytes per particle | seconds per snapshot |\n|---|---:|---:|---|---:|---:|---:|---:|\n"

for scene in $scenes; do
  shape=${scene%%:*}; count=${scene##*:}
  mkdir -p "$work/data"
  [ -f "$work/data/packing_N${count}_nofloor.data" ] ||
    (cd "$work" && $python "$root/examples/gravity_packing/make_packing.py" "$count" --floor none --outdir data >/dev/null)
  # The template's scale: the Schönhardt polyhedron's as in.packing; other shapes at its bounding radius.
  read -r scale triangles < <($python - "$root" "$shape" <<'EOF'
import math, sys
sys.path.insert(0, sys.argv[1] + "/tools")
from shape_files import bounding_radius, mass_properties, read_mesh
schoenhardt_scale = 0.0243908205380617
files = {"schoenhardt": "schoenhardt.stl", "rock_40": "rock_40.obj"}
vertices, triangles = read_mesh(sys.argv[1] + "/examples/shapes/" + files.get(sys.argv[2], sys.argv[2]))
reference, tris = read_mesh(sys.argv[1] + "/examples/shapes/schoenhardt.stl")
radius = bounding_radius(vertices, mass_properties(vertices, triangles)[1])
reference_radius = bounding_radius(reference, mass_properties(reference, tris)[1])
print(repr(schoenhardt_scale * reference_radius / radius), len(triangles))
EOF
)
  file=$shape; [ "$shape" = schoenhardt ] && file=schoenhardt.stl; [ "$shape" = rock_40 ] && file=rock_40.obj
  for format in $formats; do
    extension=vtp; modify=""
    case $format in
      ascii) modify="dump_modify d binary no" ;;
      raw) modify="dump_modify d compressor none" ;;
      zlib|legacy) ;;
      zlib[1-9]) modify="dump_modify d compression_level ${format#zlib}" ;;
      lz4) modify="dump_modify d compressor lz4" ;;
      pvtp) extension=pvtp ;;
      *) echo "unknown format $format" >&2; exit 2 ;;
    esac
    run="$work/$shape-$count-$format"
    rm -rf "$run" && mkdir -p "$run/post"
    cat > "$run/in.dump" <<EOF
atom_style polyhedron
atom_modify map array sort 0 0
boundary p p f
newton off
communicate single vel yes
units si
processors * * 1
read_data $work/data/packing_N${count}_nofloor.data
neighbor 0.002 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 2e9 1e9
fix m2 all property/global poissonsRatio peratomtype 0.25 0.25
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.30 0.35 0.35 0.35
fix m4 all property/global coefficientFriction peratomtypepair 2 0.39 0.35 0.35 0.35
fix shape all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 file $root/examples/shapes/$file scale $scale
pair_style polyhedral/volumetric
pair_coeff * *
fix integrate all nve/polyhedron
timestep 1e-9
run 0
dump d all polyhedron/vtk 1 post/particles_*.$extension
$modify
run $snapshots
EOF
    (cd "$run" && mpirun -np "$ranks" "$launcher" -in in.dump -log log.dump -screen none)
    output=$(awk '/^Outpt  *time/ {print $5}' "$run/log.dump" | tail -1)
    last=$(ls "$run/post" | sed -n 's/^particles_\([0-9]*\)\..*/\1/p' | sort -n | tail -1)
    snapshot=("$run"/post/particles_"${last}".* "$run"/post/particles_"${last}"_*)
    files=${#snapshot[@]}
    bytes=$(cat "${snapshot[@]}" | wc -c)
    awk -v s="$shape" -v n="$count" -v t="$triangles" -v f="$format" -v k="$files" -v b="$bytes" -v o="$output" \
        -v m="$snapshots" 'BEGIN {printf "| %s | %d | %d | %s | %d | %d | %.0f | %.4f |\n", s, n, t * n, f, k, b, b / n, o / m}'
    rm -rf "$run"
  done
done
