// Exact reference for the overlap of two closed triangle meshes: volume and centroid of A n B
// in exact rational arithmetic (CGAL's Exact_predicates_exact_constructions_kernel), sharing no
// code with the package. Test-only (tests/test_exact_reference.py builds and runs it).
//
// Input on stdin, whitespace-separated tokens, any number of each record, in any order
// (a mesh must come before the cases that name it; meshes are numbered 0, 1, ... as read):
//
//   mesh NV NT  x0 y0 z0 ... (3 NV doubles)  i0 j0 k0 ... (3 NT vertex indices, 0-based)
//   case IA  r00 r01 r02 r10 r11 r12 r20 r21 r22  t0 t1 t2   IB  (the same 12 numbers for B)
//
// A case places mesh IA at x -> R x + t and mesh IB at its own R, t (row-major R; the numbers
// are read as doubles and the placement is applied exactly: the placed vertices are the exact
// values of R x + t, not their rounding). Meshes must be closed, outward oriented and free of
// self-intersections; the two placed meshes may touch, share faces, edges and vertices, or
// coincide: the corefinement is exact.
//
// Output: one line per case, "volume cx cy cz method" with %.17g (the doubles nearest the exact
// values, within one unit in the last place); "0 nan nan nan 0" for an empty intersection.
// method 0: PMP::corefine_and_compute_intersection. Where A n B is not a manifold surface (two
// pieces sharing an edge, say) that returns false; then from one corefinement the union and the
// differences: method 1: V(A n B) = V(A) + V(B) - V(A u B); 2: V(A) - V(A - B); 3: V(B) - V(B - A)
// (the first of them that is manifold; the same for the first moment; the others that are manifold
// must agree exactly). Exit status 2 and a message on stderr if none is, or on bad input.
//
// Volume: PMP::volume; centroid: first moment of the signed tetrahedra (origin, face) over the
// volume, both exact (the two volumes are checked to be equal).

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <array>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_exact_constructions_kernel K;
typedef K::FT FT;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
namespace PMP = CGAL::Polygon_mesh_processing;

struct Input {
  std::vector<double> vertices;
  std::vector<int> triangles;
};

static void fail(const std::string &message)
{
  std::cerr << "exact_overlap_cgal: " << message << std::endl;
  std::exit(2);
}

static double read_double(std::istream &in)
{
  std::string token;
  if (!(in >> token)) fail("unexpected end of input");
  char *end = 0;
  double value = std::strtod(token.c_str(), &end);  // correctly rounded (glibc)
  if (*end) fail("not a number: " + token);
  return value;
}

static long read_int(std::istream &in)
{
  long value;
  if (!(in >> value)) fail("expected an integer");
  return value;
}

// The mesh placed exactly at x -> R x + t.
static Mesh place(const Input &input, const double placement[12])
{
  FT r[9], t[3];
  for (int k = 0; k < 9; k++) r[k] = FT(placement[k]);
  for (int k = 0; k < 3; k++) t[k] = FT(placement[9 + k]);
  Mesh mesh;
  std::vector<Mesh::Vertex_index> index;
  for (size_t i = 0; i < input.vertices.size() / 3; i++) {
    FT x(input.vertices[3 * i]), y(input.vertices[3 * i + 1]), z(input.vertices[3 * i + 2]);
    FT c[3];
    for (int k = 0; k < 3; k++) {
      c[k] = r[3 * k] * x + r[3 * k + 1] * y + r[3 * k + 2] * z + t[k];
      c[k].exact();  // keep the lazy expression trees shallow
    }
    index.push_back(mesh.add_vertex(Point(c[0], c[1], c[2])));
  }
  for (size_t f = 0; f < input.triangles.size() / 3; f++)
    if (mesh.add_face(index[input.triangles[3 * f]], index[input.triangles[3 * f + 1]],
                      index[input.triangles[3 * f + 2]]) == Mesh::null_face())
      fail("mesh is not an oriented 2-manifold");
  if (!CGAL::is_closed(mesh)) fail("mesh is not closed");
  return mesh;
}

// 6 V and 24 V c of a closed oriented triangle mesh, from the tetrahedra (origin, face).
static void moments(const Mesh &mesh, FT &volume6, FT moment24[3])
{
  volume6 = 0;
  moment24[0] = moment24[1] = moment24[2] = 0;
  for (Mesh::Face_index f : mesh.faces()) {
    Point p[3];
    int n = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (n == 3) fail("intersection face is not a triangle");
      p[n++] = mesh.point(v);
    }
    FT det = p[0].x() * (p[1].y() * p[2].z() - p[1].z() * p[2].y()) -
             p[0].y() * (p[1].x() * p[2].z() - p[1].z() * p[2].x()) +
             p[0].z() * (p[1].x() * p[2].y() - p[1].y() * p[2].x());
    volume6 += det;
    moment24[0] += det * (p[0].x() + p[1].x() + p[2].x());
    moment24[1] += det * (p[0].y() + p[1].y() + p[2].y());
    moment24[2] += det * (p[0].z() + p[1].z() + p[2].z());
    volume6.exact();
    for (int k = 0; k < 3; k++) moment24[k].exact();
  }
}

static double nearest(const FT &x)
{
  x.exact();  // refines the interval to the two doubles around the exact value
  return CGAL::to_double(x);
}

int main()
{
  std::ios::sync_with_stdio(false);
  std::vector<Input> meshes;
  std::string word;
  while (std::cin >> word) {
    if (word == "mesh") {
      long nv = read_int(std::cin), nt = read_int(std::cin);
      if (nv < 4 || nt < 4) fail("mesh too small");
      Input input;
      for (long i = 0; i < 3 * nv; i++) input.vertices.push_back(read_double(std::cin));
      for (long i = 0; i < 3 * nt; i++) {
        long v = read_int(std::cin);
        if (v < 0 || v >= nv) fail("vertex index out of range");
        input.triangles.push_back((int)v);
      }
      meshes.push_back(input);
    } else if (word == "case") {
      Mesh placed[2];
      for (int m = 0; m < 2; m++) {
        long id = read_int(std::cin);
        if (id < 0 || id >= (long)meshes.size()) fail("no such mesh");
        double placement[12];
        for (int k = 0; k < 12; k++) placement[k] = read_double(std::cin);
        placed[m] = place(meshes[id], placement);
      }
      int method = 0;
      FT volume6, moment24[3];
      Mesh a = placed[0], b = placed[1], out;  // corefinement modifies its inputs
      if (PMP::corefine_and_compute_intersection(a, b, out)) {
        moments(out, volume6, moment24);
        if (!CGAL::is_empty(out) && PMP::volume(out) * 6 != volume6)
          fail("PMP::volume and the tetrahedron sum disagree");
      } else {
        // A n B is not a manifold surface: from the union or a difference, which may be.
        Mesh c = placed[0], d = placed[1], results[4];
        std::array<boost::optional<Mesh *>, 4> wanted;
        for (int k = 0; k < 4; k++) wanted[k] = &results[k];
        std::array<bool, 4> manifold = PMP::corefine_and_compute_boolean_operations(c, d, wanted);
        FT whole6[2], whole24[2][3];
        for (int m = 0; m < 2; m++) moments(placed[m], whole6[m], whole24[m]);
        static const int order[3] = {PMP::Corefinement::UNION, PMP::Corefinement::TM1_MINUS_TM2,
                                     PMP::Corefinement::TM2_MINUS_TM1};
        method = 0;
        for (int candidate = 1; candidate <= 3; candidate++) {
          if (!manifold[order[candidate - 1]]) continue;
          FT part6, part24[3], value6, value24[3];
          moments(results[order[candidate - 1]], part6, part24);
          // 1: A + B - (A u B); 2: A - (A - B); 3: B - (B - A)
          value6 = (candidate == 3 ? 0 : whole6[0]) + (candidate == 2 ? 0 : whole6[1]) - part6;
          for (int k = 0; k < 3; k++)
            value24[k] = (candidate == 3 ? 0 : whole24[0][k]) + (candidate == 2 ? 0 : whole24[1][k]) - part24[k];
          if (!method) {
            method = candidate;
            volume6 = value6;
            for (int k = 0; k < 3; k++) moment24[k] = value24[k];
          } else if (value6 != volume6 || value24[0] != moment24[0] || value24[1] != moment24[1] ||
                     value24[2] != moment24[2]) {
            fail("the union and the differences disagree");
          }
        }
        if (!method) fail("A n B, A u B, A - B and B - A are all non-manifold");
      }
      if (CGAL::is_zero(volume6)) {
        std::printf("0 nan nan nan %d\n", method);
      } else {
        if (CGAL::is_negative(volume6)) fail("negative intersection volume: is a mesh inside out?");
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = nearest(moment24[k] / (volume6 * 4));
        std::printf("%.17g %.17g %.17g %.17g %d\n", nearest(volume6 / 6), c[0], c[1], c[2], method);
      }
      std::fflush(stdout);
    } else {
      fail("unknown record: " + word);
    }
  }
  return 0;
}
