/* How the polyhedral styles get into a prebuilt LIGGGHTS.
 *
 * Debian's libliggghts.so compiles its styles in; it has no plugin loader.
 * Three facts about that library (checked by tests/test_registration.py and,
 * at every start, by polyhedral_verify_hooks()) make registration possible
 * without rebuilding it:
 *
 * 1. Pair, fix, compute and command styles are looked up in std::maps of
 *    creator functions (Force::pair_map, Modify::fix_map, Modify::compute_map,
 *    Input::command_map). Inserting into them works, but `clear` destroys
 *    Force and Modify and builds fresh maps. Both the LAMMPS constructor and
 *    Input::clear() call LAMMPS::post_create() through the PLT, so defining that
 *    method here (our library is searched before libliggghts) runs our
 *    registration after every (re)creation; we then forward to the original.
 *
 * 2. Atom styles and dump styles are if-chains (Atom::new_avec,
 *    Output::add_dump), also called through the PLT. Our definitions catch our
 *    style names and forward everything else to the original via
 *    dlsym(RTLD_NEXT). For a dump, the original still does the bookkeeping
 *    (id check, frequency, list growth) on a cheap stand-in style, which we
 *    then swap for our object.
 *
 * 3. The package ships its own launcher (liggghts_poly_main.cpp), linked
 *    against this library ahead of libliggghts, rather than asking users to
 *    LD_PRELOAD it into the stock `liggghts`: a preload must survive every
 *    launcher in the chain (mpirun, batch systems, remote daemons) and is
 *    inherited by every process they start. It was reported to break OpenMPI
 *    start-up; with Debian 12's OpenMPI 4.1.4 on one node it did work
 *    (doc/building.md), but the launcher does not depend on either.
 */
#include "polyhedral_register.h"

#include <dlfcn.h>
#include <map>
#include <string>
#include <stdio.h>
#include <string.h>

#include "lammps.h"
#include "atom.h"
#include "force.h"
#include "modify.h"
#include "input.h"
#include "output.h"
#include "universe.h"
#include "error.h"

#include "atom_vec_polyhedron.h"
#include "compute_erotate_polyhedron.h"
#include "compute_pair_polyhedral_local.h"
#include "compute_property_polyhedron.h"
#include "create_polyhedron.h"
#include "dump_polyhedron_vtk.h"
#include "fix_contact_history_polyhedral.h"
#include "fix_nve_polyhedron.h"
#include "fix_wall_polyhedral.h"
#include "fix_particletemplate_polyhedron.h"
#include "liggghts_member.h"
#include "pair_polyhedral_volumetric.h"
#include "compute_contact_polyhedron.h"
#include "compute_wall_polyhedral_local.h"
#include "fix_check_timestep_polyhedral.h"
#include "pair_polyhedral_volumetric_gpu.h"
#include "polyhedral_guard.h"

using namespace LAMMPS_NS;

namespace {

const char *const kPostCreateSymbol = "_ZN9LAMMPS_NS6LAMMPS11post_createEv";
const char *const kNewAvecSymbol = "_ZN9LAMMPS_NS4Atom8new_avecEPKcPcRi";
const char *const kAddDumpSymbol = "_ZN9LAMMPS_NS6Output8add_dumpEiPPc";

// Itanium C++ ABI: a non-virtual member function is a function taking `this` first.
typedef void (*PostCreateFn)(LAMMPS *);
typedef AtomVec *(*NewAvecFn)(Atom *, const char *, char *, int &);
typedef void (*AddDumpFn)(Output *, int, char **);

void *original(const char *symbol)
{
  void *fn = dlsym(RTLD_NEXT, symbol);
  if (!fn) {
    fprintf(stderr, "ERROR: polyhedral: LIGGGHTS library has no symbol %s\n", symbol);
    fflush(stderr);
    abort();
  }
  return fn;
}

template <typename T> Pair *create_pair(LAMMPS *lmp) { return new T(lmp); }
template <typename T> Fix *create_fix(LAMMPS *lmp, int narg, char **arg) { return new T(lmp, narg, arg); }
template <typename T> Compute *create_compute(LAMMPS *lmp, int iarg, int narg, char **arg) { return new T(lmp, iarg, narg, arg); }
template <typename T> void run_command(LAMMPS *lmp, int narg, char **arg) { T command(lmp); command.command(narg, arg); }

// The creator maps are public in Force but private in Modify and protected in
// Input; liggghts_member.h reads them.
typedef Fix *(*FixCreator)(LAMMPS *, int, char **);
typedef Compute *(*ComputeCreator)(LAMMPS *, int, int, char **);
typedef void (*CommandCreator)(LAMMPS *, int, char **);
typedef std::map<std::string, FixCreator> *Modify::*FixMapMember;
typedef std::map<std::string, ComputeCreator> *Modify::*ComputeMapMember;
typedef std::map<std::string, CommandCreator> *Input::*CommandMapMember;

struct FixMapTag { typedef FixMapMember Member; friend Member exposed(FixMapTag); };
struct ComputeMapTag { typedef ComputeMapMember Member; friend Member exposed(ComputeMapTag); };
struct CommandMapTag { typedef CommandMapMember Member; friend Member exposed(CommandMapTag); };
template struct ExposeMember<FixMapTag, &Modify::fix_map>;
template struct ExposeMember<ComputeMapTag, &Modify::compute_map>;
template struct ExposeMember<CommandMapTag, &Input::command_map>;

// The styles users write, by kind, for polyhedral_print_styles (the atom style and the dump style come through
// the interposed Atom::new_avec and Output::add_dump below; the contact-history fix is internal).
const char *const kListedStyles[][2] = {
    {"Atom styles", "polyhedron"},
    {"Pair styles", "polyhedral/volumetric"},
    {"Pair styles", "polyhedral/volumetric/gpu"},
    {"Fix styles", "particletemplate/polyhedron"},
    {"Fix styles", "nve/polyhedron"},
    {"Fix styles", "wall/polyhedral"},
    {"Fix styles", "check/timestep/polyhedral"},
    {"Compute styles", "erotate/polyhedron"},
    {"Compute styles", "property/polyhedron"},
    {"Compute styles", "pair/polyhedral/local"},
    {"Compute styles", "contact/polyhedron"},
    {"Compute styles", "wall/polyhedral/local"},
    {"Dump styles", "polyhedron/vtk"},
    {"Commands", "create_polyhedron"},
};

void register_styles(LAMMPS *lmp)
{
  std::map<std::string, FixCreator> &fixes = *(lmp->modify->*exposed(FixMapTag()));
  std::map<std::string, ComputeCreator> &computes = *(lmp->modify->*exposed(ComputeMapTag()));
  std::map<std::string, CommandCreator> &commands = *(lmp->input->*exposed(CommandMapTag()));

  (*lmp->force->pair_map)["polyhedral/volumetric"] = &create_pair<PairPolyhedralVolumetric>;
  (*lmp->force->pair_map)["polyhedral/volumetric/gpu"] = &create_pair<PairPolyhedralVolumetricGPU>;
  fixes["particletemplate/polyhedron"] = &create_fix<FixParticletemplatePolyhedron>;
  fixes[FixContactHistoryPolyhedral::creation_style()] = &create_fix<FixContactHistoryPolyhedral>;
  fixes["nve/polyhedron"] = &create_fix<FixNVEPolyhedron>;
  fixes["wall/polyhedral"] = &create_fix<FixWallPolyhedral>;
  fixes["check/timestep/polyhedral"] = &create_fix<FixCheckTimestepPolyhedral>;
  computes["erotate/polyhedron"] = &create_compute<ComputeERotatePolyhedron>;
  computes["property/polyhedron"] = &create_compute<ComputePropertyPolyhedron>;
  computes["pair/polyhedral/local"] = &create_compute<ComputePairPolyhedralLocal>;
  computes["contact/polyhedron"] = &create_compute<ComputeContactPolyhedron>;
  computes["wall/polyhedral/local"] = &create_compute<ComputeWallPolyhedralLocal>;
  commands["create_polyhedron"] = &run_command<CreatePolyhedron>;
  // LIGGGHTS fixes and computes that assume spheres stop with an ERROR: under atom_style polyhedron.
  polyhedral_guard_sphere_fixes(fixes);
  polyhedral_guard_sphere_computes(computes);
  polyhedral_guard_commands(commands);
}

}  // namespace

// ---- the three interposed LIGGGHTS methods -------------------------------

// LIGGGHTS' Error appends, to about one error in five of a build whose version
// string says "PUBLIC", a "tip of the day" returned as the c_str() of a
// destroyed std::string (error_special.h), i.e. random bytes after the ERROR
// line. The check is a case-sensitive strstr, so changing the case of that one
// word (in place, same length) switches the joke off and keeps ERROR lines clean.
static void silence_error_jokes(LAMMPS *lmp)
{
  char *marker = strstr(lmp->universe->version, "PUBLIC");
  if (marker) memcpy(marker, "Public", 6);
}

void LAMMPS::post_create()
{
  static PostCreateFn original_post_create = (PostCreateFn) original(kPostCreateSymbol);
  silence_error_jokes(this);
  register_styles(this);
  // With `-suffix gpu` the original issues `package gpu ...`, a package this
  // LIGGGHTS lacks; our /gpu styles need no package command.
  if (suffix && suffix_enable && strcmp(suffix, "gpu") == 0) return;
  original_post_create(this);
}

AtomVec *Atom::new_avec(const char *style, char *suffix, int &sflag)
{
  static NewAvecFn original_new_avec = (NewAvecFn) original(kNewAvecSymbol);
  if (strcmp(style, "polyhedron") == 0) {
    sflag = 0;
    return new AtomVecPolyhedron(lmp);
  }
  return original_new_avec(this, style, suffix, sflag);
}

void Output::add_dump(int narg, char **arg)
{
  static AddDumpFn original_add_dump = (AddDumpFn) original(kAddDumpSymbol);
  if (narg < 3 || strcmp(arg[2], "polyhedron/vtk") != 0) {
    original_add_dump(this, narg, arg);
    return;
  }
  // The original does the bookkeeping and its checks (dump ID, group,
  // frequency) on a cheap stand-in style; then our object takes its slot.
  if (narg < 5) error->all(FLERR, "Illegal dump polyhedron/vtk command: expected ID group polyhedron/vtk N file");
  char stand_in_style[] = "xyz";
  char stand_in_file[] = "/dev/null";
  char *stand_in_args[5] = {arg[0], arg[1], stand_in_style, arg[3], stand_in_file};
  original_add_dump(this, 5, stand_in_args);
  Dump *ours = new DumpPolyhedronVTK(lmp, narg, arg);
  delete dump[ndump - 1];
  dump[ndump - 1] = ours;
}

void polyhedral_print_styles(FILE *out)
{
  fprintf(out, "\n* Polyhedral styles (package polyhedral, registered at start-up; doc/Manual.md):\n");
  const char *kind = "";
  int column = 0;
  for (size_t k = 0; k < sizeof kListedStyles / sizeof kListedStyles[0]; k++) {
    if (strcmp(kind, kListedStyles[k][0]) != 0) {
      kind = kListedStyles[k][0];
      fprintf(out, "\n%s:\n", kind);
      column = 0;
    }
    fprintf(out, "%-32s", kListedStyles[k][1]);
    if (++column == 5 || k + 1 == sizeof kListedStyles / sizeof kListedStyles[0] ||
        strcmp(kind, kListedStyles[k + 1][0]) != 0) {
      fprintf(out, "\n");
      column = 0;
    }
  }
  fprintf(out, "\n");
}

// ---- start-up check -------------------------------------------------------

static bool defined_in_this_library(const char *symbol)
{
  Dl_info ours, used;
  void *resolved = dlsym(RTLD_DEFAULT, symbol);
  if (!resolved || !dladdr((void *) &register_styles, &ours) || !dladdr(resolved, &used)) return false;
  return ours.dli_fbase == used.dli_fbase;
}

int polyhedral_verify_hooks(void)
{
  const char *symbols[3] = {kPostCreateSymbol, kNewAvecSymbol, kAddDumpSymbol};
  int ok = 1;
  for (int i = 0; i < 3; i++) {
    if (!defined_in_this_library(symbols[i])) {
      fprintf(stderr,
              "ERROR: polyhedral: the dynamic linker does not resolve %s to libpolyhedral; "
              "this LIGGGHTS build cannot host the polyhedral styles (link libpolyhedral before libliggghts)\n",
              symbols[i]);
      ok = 0;
    }
  }
  return ok;
}
