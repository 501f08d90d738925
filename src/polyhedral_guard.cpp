/* See polyhedral_guard.h.
 *
 * Why wrap the creators rather than check in a fix's init(): Modify::add_fix
 * looks the style up in fix_map and calls its creator, so the wrapper runs at
 * the very `fix` line (a fix needs a box, hence atom_style is known by then),
 * also for fixes that other fixes create, and no extra fix has to be kept at a
 * particular place in the fix list. The ERROR: line then follows the deck's
 * offending line in the log. */
#include "polyhedral_guard.h"

#include <string.h>

#include "lammps.h"
#include "atom.h"
#include "error.h"

using namespace LAMMPS_NS;

namespace {

struct Guard {
  const char *style;
  const char *message;  // NULL: built from kTemplate, or (fix adapt) only some arguments are refused
};

const char *const kAdaptDiameter =
    "Fix adapt with 'atom diameter' changes the bounding radius and the mass of polyhedra, not their shape; "
    "with atom_style polyhedron set particle sizes with the 'scale' keyword of fix particletemplate/polyhedron";

const char *const kTemplate =
    "makes particles without a polyhedral shape (no template, zero inertia), which fix wall/polyhedral and "
    "pair polyhedral/volumetric cannot handle; with atom_style polyhedron use fix particletemplate/polyhedron";

#define POLY_EULER_MESSAGE(style)                                                                    \
  "Fix " style " takes particle volumes from the bounding spheres (a cube counts as 2.72 times its " \
  "volume); with atom_style polyhedron use compute property/polyhedron volume (per particle, e.g. "   \
  "summed over a region with compute reduce/region)"

const Guard kGuards[] = {
    {"wall/gran",
     "Fix wall/gran treats polyhedra as their bounding spheres; with atom_style polyhedron use fix "
     "wall/polyhedral (same 'primitive type T wallstyle args' or 'mesh n_meshes K meshes ...' arguments)"},
    {"check/timestep/gran",
     "Fix check/timestep/gran needs pair gran and spheres; with atom_style polyhedron use fix "
     "check/timestep/polyhedral (same 'nevery fraction_rayleigh fraction_hertz' arguments and output vector)"},
    {"adapt", NULL},
    {"ave/euler", POLY_EULER_MESSAGE("ave/euler")},
    {"ave/euler/stress", POLY_EULER_MESSAGE("ave/euler/stress")},
    {"particletemplate/sphere", NULL},
    {"particletemplate/multisphere", NULL},
    {"particletemplate/multiplespheres", NULL},
    {"particletemplate/superquadric", NULL},  // absent from Debian's build (no superquadric support)
};
const int kNumGuards = sizeof kGuards / sizeof kGuards[0];

// LIGGGHTS' own creators, taken from the map before wrapping. They are the
// same functions after every `clear` (template instances in libliggghts).
PolyhedralFixCreator original_creator[kNumGuards];

// Fix adapt's arguments: N, then `pair pstyle param I J v_name`, `kspace v_name`
// or `atom attribute v_name` entries, as LIGGGHTS' FixAdapt parses them.
bool adapts_diameter(int narg, char **arg)
{
  int iarg = 4;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "pair") == 0) iarg += 6;
    else if (strcmp(arg[iarg], "kspace") == 0) iarg += 2;
    else if (strcmp(arg[iarg], "atom") == 0) {
      if (iarg + 1 < narg && strcmp(arg[iarg + 1], "diameter") == 0) return true;
      iarg += 3;
    } else break;
  }
  return false;
}

bool polyhedral_atoms(LAMMPS *lmp)
{
  return lmp->atom->atom_style && strcmp(lmp->atom->atom_style, "polyhedron") == 0;
}

template <int K> Fix *guarded_creator(LAMMPS *lmp, int narg, char **arg)
{
  const Guard &guard = kGuards[K];
  if (polyhedral_atoms(lmp)) {
    if (strcmp(guard.style, "adapt") == 0) {
      if (adapts_diameter(narg, arg)) lmp->error->all(FLERR, kAdaptDiameter);
    } else if (guard.message) {
      lmp->error->all(FLERR, guard.message);
    } else {
      std::string message = std::string("Fix ") + guard.style + " " + kTemplate;
      lmp->error->all(FLERR, message.c_str());
    }
  }
  return original_creator[K](lmp, narg, arg);
}

// Wraps kGuards[0 .. K-1].
template <int K> void wrap(std::map<std::string, PolyhedralFixCreator> &fix_map)
{
  wrap<K - 1>(fix_map);
  std::map<std::string, PolyhedralFixCreator>::iterator it = fix_map.find(kGuards[K - 1].style);
  if (it == fix_map.end() || it->second == &guarded_creator<K - 1>) return;
  original_creator[K - 1] = it->second;
  it->second = &guarded_creator<K - 1>;
}
template <> void wrap<0>(std::map<std::string, PolyhedralFixCreator> &) {}

// LIGGGHTS' compute contact/atom counts the spheres within the skin of each other: with polyhedra it would
// count bounding spheres. The one guarded compute; its creator is kept and called for every other atom style.
PolyhedralComputeCreator original_contact_atom = NULL;

Compute *guarded_contact_atom(LAMMPS *lmp, int iarg, int narg, char **arg)
{
  if (polyhedral_atoms(lmp))
    lmp->error->all(FLERR, "Compute contact/atom counts bounding spheres within the skin of each other; with "
                           "atom_style polyhedron use compute contact/polyhedron (the polyhedra that overlap)");
  return original_contact_atom(lmp, iarg, narg, arg);
}

PolyhedralCommandCreator original_set = NULL;

// LIGGGHTS' set: style ID, then keyword value... pairs; a keyword of ours is never a value (the name after
// property/atom is skipped, being the user's).
void guarded_set(LAMMPS *lmp, int narg, char **arg)
{
  for (int i = 2; polyhedral_atoms(lmp) && i < narg; i++) {
    if (strcmp(arg[i], "property/atom") == 0) {
      i++;
      continue;
    }
    if (strcmp(arg[i], "diameter") == 0)
      lmp->error->all(FLERR, "Set diameter: a polyhedron's size is its template's (the 'scale' keyword of fix "
                             "particletemplate/polyhedron); with atom_style polyhedron it cannot be set per particle");
    if (strcmp(arg[i], "mass") == 0)
      lmp->error->all(FLERR, "Set mass: a polyhedron's mass is its template's volume times its density; with "
                             "atom_style polyhedron use set ... density");
  }
  original_set(lmp, narg, arg);
}

}  // namespace

void polyhedral_guard_commands(std::map<std::string, PolyhedralCommandCreator> &command_map)
{
  std::map<std::string, PolyhedralCommandCreator>::iterator it = command_map.find("set");
  if (it == command_map.end() || it->second == &guarded_set) return;
  original_set = it->second;
  it->second = &guarded_set;
}

void polyhedral_guard_sphere_fixes(std::map<std::string, PolyhedralFixCreator> &fix_map)
{
  wrap<kNumGuards>(fix_map);
}

void polyhedral_guard_sphere_computes(std::map<std::string, PolyhedralComputeCreator> &compute_map)
{
  std::map<std::string, PolyhedralComputeCreator>::iterator it = compute_map.find("contact/atom");
  if (it == compute_map.end() || it->second == &guarded_contact_atom) return;
  original_contact_atom = it->second;
  it->second = &guarded_contact_atom;
}
