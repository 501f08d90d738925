#!/usr/bin/python3
"""Converts a LIGGGHTS sphere deck to polyhedra by its particle lines (doc/converting_decks.md).

    tools/convert_deck.py IN OUT --shape rock_40.obj [--shapes-dir examples/shapes] [--orientation random]

Rewrites what makes the particles spheres and keeps everything else as written:

- `atom_style granular|sphere` -> `atom_style polyhedron`;
- `pair_style gran ...` -> `pair_style polyhedral/volumetric`, `fix ... wall/gran ...` -> `fix ... wall/polyhedral`,
  keeping LIGGGHTS' keywords that mean what the volumetric law does (`model hertz`, `tangential history`,
  `cohesion sjkr|off`, `rolling_friction off`, `surface default`);
- `fix ... particletemplate/sphere ... radius constant R` -> `fix ... particletemplate/polyhedron ... file SHAPE
  scale S`, S such that the polyhedron has the sphere's volume (and so its mass);
- `fix ... nve/sphere` -> `nve/polyhedron`, `compute ... erotate/sphere` -> `erotate/polyhedron`,
  `fix ... check/timestep/gran` -> `check/timestep/polyhedral`, `compute ... contact/atom` ->
  `contact/polyhedron`;
- insertion fixes get `orientation random` (LIGGGHTS' default would insert every particle in the template's
  orientation), and an `extrude_length` of insert/stream shorter than three bounding radii of the largest
  polyhedron (insert/stream refuses it) is lengthened to that.

Lines it cannot convert, or converts with a change of meaning, are listed on the standard output with the
reason, one per line ("line N: ..."). Lines that would stop the converted deck (LIGGGHTS' sphere-only commands:
fix adapt of the diameter, cohesion and rolling-friction models, radius distributions, multisphere templates,
per-contact local computes of pair gran, heat conduction by fix heat/gran) are kept in OUT as comments ("#
convert_deck: ..."), together with the lines that only served them (their unfix, their thermo columns, dumps and
`set`s of their per-atom properties), so that OUT runs as it is. Exit status 0, or 1 for a
deck with no particle template or an unknown shape file.
"""
import argparse
import math
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import shape_files  # noqa: E402

# LIGGGHTS keywords of pair gran / wall/gran that mean what the volumetric law does.
ACCEPTED = {("model", "hertz"), ("tangential", "history"), ("cohesion", "off"), ("cohesion", "sjkr"),
            ("rolling_friction", "off"), ("surface", "default")}
MODEL_KEYWORDS = {"model", "tangential", "cohesion", "rolling_friction", "surface"}


# shapes -------------------------------------------------------------------------------------------------

def volume_and_radius(path):
    """The mesh's volume and the largest distance of a vertex from its centroid (file units)."""
    vertices, triangles = shape_files.read_mesh(path)
    volume, centre, _ = shape_files.mass_properties(vertices, triangles)
    return abs(volume), shape_files.bounding_radius(vertices, centre)


# deck lines ---------------------------------------------------------------------------------------------

def logical_lines(text):
    """(first physical line number, [physical lines], joined text without the '&'s) per logical line."""
    out, group, start = [], [], 1
    for number, line in enumerate(text.splitlines(), start=1):
        if not group:
            start = number
        group.append(line)
        if line.split("#")[0].rstrip().endswith("&"):
            continue
        joined = " ".join(g.split("#")[0].rstrip()[:-1] if g.split("#")[0].rstrip().endswith("&") else g
                          for g in group)
        out.append((start, group, joined))
        group = []
    if group:
        out.append((start, group, " ".join(group)))
    return out


def split_comment(line):
    code, _, comment = line.partition("#")
    return code.split(), ("#" + comment if comment else "")


class Converter:
    def __init__(self, shape_path, orientation):
        self.shape = shape_path
        self.shape_volume, self.shape_radius = volume_and_radius(shape_path)
        self.orientation = orientation
        self.notes = []            # (line, message)
        self.dropped_ids = set()   # fixes and computes kept as comments
        self.templates = 0
        self.largest_bounding = 0.0

    def note(self, line, message):
        self.notes.append((line, message))

    def scale_for_radius(self, radius):
        """Scale of the shape whose volume is the sphere's."""
        return 2.0 * radius * (math.pi / 6.0 / self.shape_volume) ** (1.0 / 3.0)

    def model_keywords(self, line, words, start, caller):
        """The words from `start` on, LIGGGHTS' model keywords filtered: (kept words, the rest from the first
        word that is not a model keyword)."""
        kept, k = [], start
        while k + 1 < len(words) and words[k] in MODEL_KEYWORDS:
            key, value = words[k], words[k + 1]
            if (key, value) in ACCEPTED:
                kept += [key, value]
            elif key == "model":
                kept += ["model", "hertz"]
                self.note(line, f"{caller}: model {value} -> model hertz: the volumetric law generalises "
                                "Hertz-Mindlin and has no other model (stiffness from E and nu, not the deck's "
                                "Hooke parameters)")
            elif key == "tangential":
                kept += ["tangential", "history"]
                self.note(line, f"{caller}: tangential {value} -> tangential history (Mindlin-Deresiewicz with its "
                                "history; there is no viscous-only tangential force)")
            elif key == "rolling_friction":
                self.note(line, f"{caller}: rolling_friction {value} dropped: polyhedra resist rolling by their "
                                "shape (they roll over edges and vertices)")
            elif key == "cohesion":
                self.note(line, f"{caller}: cohesion {value} dropped, NOT CONVERTED: of LIGGGHTS' cohesion models "
                                "only sjkr has a polyhedral counterpart; the converted deck has no cohesion")
            else:
                self.note(line, f"{caller}: surface {value} dropped (no counterpart)")
            k += 2
        return kept, words[k:]

    def convert(self, number, words):
        """The converted words of a logical line, None to keep the line, or a reason to comment it out."""
        if not words:
            return None
        command = words[0]
        style = words[3] if command in ("fix", "compute") and len(words) > 3 else None
        if command == "atom_style" and words[1:2] in (["granular"], ["sphere"]):
            return ["atom_style", "polyhedron"] + words[2:]
        if command == "pair_style" and words[1:2] == ["gran"]:
            kept, rest = self.model_keywords(number, words, 2, "pair_style")
            if rest:
                self.note(number, f"pair_style: '{' '.join(rest)}' dropped (pair gran options with no counterpart)")
            return ["pair_style", "polyhedral/volumetric"] + kept
        if style == "wall/gran":
            kept, rest = self.model_keywords(number, words, 4, f"fix {words[1]}")
            return words[:3] + ["wall/polyhedral"] + kept + rest
        if style == "particletemplate/sphere":
            return self.template(number, words)
        if style in ("particletemplate/multisphere", "multisphere", "particletemplate/multiplespheres"):
            return f"{style}: multisphere clumps have no polyhedral conversion here (use a polyhedral shape of the clump)"
        if style == "nve/sphere":
            return words[:3] + ["nve/polyhedron"] + words[4:]
        if style == "erotate/sphere":
            return words[:3] + ["erotate/polyhedron"] + words[4:]
        if style == "check/timestep/gran":
            return words[:3] + ["check/timestep/polyhedral"] + words[4:]
        if style and style.startswith("insert/"):
            return self.insertion(number, words)
        if style == "adapt" and "diameter" in words:
            return "fix adapt ... diameter: polyhedra do not grow (to pack denser, insert at the target fraction)"
        if style == "heat/gran":
            # heat/gran keeps its temperatures and fluxes in per-atom properties of these names (LIGGGHTS'
            # fix_heat_gran.cpp): what reads them goes with it.
            self.dropped_ids.update(("Temp", "heatFlux", "heatSource", "directionalHeatFlux"))
            return "fix heat/gran conducts heat through pair gran's contacts; polyhedral contacts conduct none"
        if style in ("ave/euler", "ave/euler/stress"):
            return f"fix {style} takes volumes from bounding spheres; use compute property/polyhedron volume"
        if command == "compute" and style == "contact/atom":
            if len(words) > 4:
                self.note(number, f"compute {words[1]}: contact/atom -> contact/polyhedron, '{' '.join(words[4:])}' "
                                  "dropped (it counts the polyhedra that overlap, no skin)")
            return words[:3] + ["contact/polyhedron"]
        if command == "compute" and style in ("wall/gran/local", "pair/gran/local"):
            return f"compute {style} works on pair gran contacts; compute pair/polyhedral/local lists polyhedral " \
                   "contacts"
        if command == "set" and "diameter" in words:
            return "set ... diameter: the shape sets a polyhedron's size (scale of its template)"
        if command == "unfix" and len(words) > 1 and words[1] in self.dropped_ids:
            return f"unfix of the commented-out fix {words[1]}"
        if command == "set" and "property/atom" in words and self.dropped_ids:
            k = words.index("property/atom")
            if words[k + 1:k + 2] and words[k + 1] in self.dropped_ids:
                return f"set ... property/atom {words[k + 1]}: the property of a commented-out fix"
        if command in ("thermo_style", "fix", "compute", "variable", "dump") and self.dropped_ids:
            return self.without_dropped_references(number, words)
        return None

    def template(self, number, words):
        if "radius" not in words:
            return "particletemplate/sphere without 'radius': cannot size the polyhedron"
        k = words.index("radius")
        if words[k + 1:k + 2] != ["constant"] or k + 2 >= len(words):
            return (f"particletemplate/sphere radius {words[k + 1] if k + 1 < len(words) else ''}: only "
                    "'radius constant R' converts (one template per size, several templates in the distribution)")
        radius = float(words[k + 2])
        scale = self.scale_for_radius(radius)
        self.templates += 1
        self.largest_bounding = max(self.largest_bounding, self.shape_radius * scale)
        return (words[:3] + ["particletemplate/polyhedron"] + words[4:k] + words[k + 3:] +
                ["file", str(self.shape), "scale", f"{scale:.10g}"])

    def insertion(self, number, words):
        out = list(words)
        if "orientation" not in out and self.orientation:
            at = out.index("distributiontemplate") if "distributiontemplate" in out else len(out)
            out[at:at] = ["orientation", self.orientation]
        if "extrude_length" in out and self.largest_bounding > 0:
            k = out.index("extrude_length")
            needed = 3.0 * self.largest_bounding * 1.001
            if float(out[k + 1]) < needed:
                self.note(number, f"fix {words[1]}: extrude_length {out[k + 1]} -> {needed:.4g} (insert/stream needs "
                                  "three bounding radii of the largest polyhedron)")
                out[k + 1] = f"{needed:.4g}"
        return out if out != words else None

    def without_dropped_references(self, number, words):
        pattern = re.compile(r"^[cf]_(%s)(\[\d+\])?$" % "|".join(map(re.escape, sorted(self.dropped_ids))))
        kept = [w for w in words if not pattern.match(w)]
        if kept == words:
            return None
        dropped = " ".join(w for w in words if pattern.match(w))
        if words[0] == "thermo_style":
            self.note(number, "thermo_style: the columns of commented-out fixes and computes dropped: " + dropped)
            return kept
        if words[0] == "dump" and len(kept) > 6:  # dump ID group style N file, then its columns: some are left
            self.note(number, f"dump {words[1]}: the columns of commented-out fixes and computes dropped: {dropped}")
            return kept
        return f"{words[0]} reads a commented-out fix or compute"


def convert_text(text, converter):
    out = []
    for number, physical, joined in logical_lines(text):
        words, comment = split_comment(joined)
        result = converter.convert(number, words)
        if result is None:
            out += physical
        elif isinstance(result, str):
            converter.note(number, "NOT CONVERTED, commented out: " + result)
            if words[0] in ("fix", "compute") and len(words) > 1:
                converter.dropped_ids.add(words[1])
            out += [f"# convert_deck: {result}"] + ["# " + line for line in physical]
        else:
            out.append(" ".join(result) + (" " + comment if comment else ""))
    return "\n".join(out) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("input")
    p.add_argument("output")
    p.add_argument("--shape", required=True, help="the particle mesh (OBJ, OFF or STL), e.g. rock_40.obj")
    p.add_argument("--shapes-dir", default=str(ROOT / "examples" / "shapes"),
                   help="where --shape is looked for when it is not a path to a file (examples/shapes)")
    p.add_argument("--orientation", default="random", help="orientation keyword for the insertion fixes (random)")
    a = p.parse_args()
    shape = pathlib.Path(a.shape)
    if not shape.is_file():
        shape = pathlib.Path(a.shapes_dir) / a.shape
    if not shape.is_file():
        print(f"ERROR: shape file {a.shape} not found (nor in {a.shapes_dir})")
        return 1
    source = pathlib.Path(a.input)
    if not source.is_file():
        print(f"ERROR: deck {source} not found")
        return 1
    converter = Converter(shape.resolve(), a.orientation)
    text = convert_text(source.read_text(errors="replace"), converter)
    if converter.templates == 0:
        print(f"ERROR: {source} has no 'particletemplate/sphere ... radius constant R' to convert")
        return 1
    pathlib.Path(a.output).write_text(text)
    print(f"{source} -> {a.output}: shape {shape.name} (volume {converter.shape_volume:.6g}, bounding radius "
          f"{converter.shape_radius:.6g} in file units), {converter.templates} template(s)")
    for line, message in converter.notes:
        print(f"line {line}: {message}")
    if not converter.notes:
        print("every line converted")
    return 0


if __name__ == "__main__":
    sys.exit(main())
