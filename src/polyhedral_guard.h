/* Stops LIGGGHTS fixes that treat every particle as a sphere from running on
 * atom_style polyhedron (issue 13): fix wall/gran, fix adapt ... atom diameter,
 * fix ave/euler and the non-polyhedral particle templates would run silently
 * with wrong results (bounding-sphere contacts, bounding-sphere volume fractions,
 * shapeless particles), and so would compute contact/atom (bounding-sphere
 * contacts). Each gets an ERROR: naming the polyhedral replacement
 * at the line that defines it. */
#ifndef POLYHEDRAL_GUARD_H
#define POLYHEDRAL_GUARD_H

#include <map>
#include <string>

namespace LAMMPS_NS {
class LAMMPS;
class Fix;
class Compute;
}

typedef LAMMPS_NS::Fix *(*PolyhedralFixCreator)(LAMMPS_NS::LAMMPS *, int, char **);
typedef LAMMPS_NS::Compute *(*PolyhedralComputeCreator)(LAMMPS_NS::LAMMPS *, int, int, char **);

// Replaces, in a fresh Modify::fix_map, the creators of the guarded LIGGGHTS
// styles by wrappers that call error->all under atom_style polyhedron and
// forward to LIGGGHTS' creator otherwise. Called after every (re)creation of
// the map (LAMMPS::post_create in polyhedral_register.cpp).
void polyhedral_guard_sphere_fixes(std::map<std::string, PolyhedralFixCreator> &fix_map);

// The same for LIGGGHTS' computes that assume spheres: compute contact/atom.
void polyhedral_guard_sphere_computes(std::map<std::string, PolyhedralComputeCreator> &compute_map);

typedef void (*PolyhedralCommandCreator)(LAMMPS_NS::LAMMPS *, int, char **);

// And the `set` command: under atom_style polyhedron `set ... diameter` and `set ... mass` stop with an ERROR:
// (a polyhedron's size is its template's scale, its mass its template's volume times its density; the next
// run's set-up overwrote both without a word).
void polyhedral_guard_commands(std::map<std::string, PolyhedralCommandCreator> &command_map);

#endif
