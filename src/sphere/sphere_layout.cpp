#include <algorithm>
#include <cmath>
#include <vector>

#include "sphere/detail/sphere_support.hpp"

namespace ricci::sphere_support {

/// The disk laid out in the plane in arithmetic T, smallest faces first. Each face gets a rigid
/// frame (rotation R, translation t: corner k at R s_k + t, s_k its corner in the face's own
/// shape). In increasing order of size, a face that touches no face laid out yet starts a region
/// of its own; otherwise it joins the region of the first laid-out face across one of its edges,
/// its frame turning its side of the edge onto that face's, and every other region it touches
/// across an edge is moved rigidly (the smaller region onto the larger) so that their copies of
/// the shared edge coincide. A vertex ends where the first face laid out with it puts it.
///
/// Why not one tree from one root: the flow leaves each vertex's angle sum 2 pi to about 1e-14,
/// and a tree layout closes every loop with the rotation of the vertices it encloses times
/// their distance. Two faces at a fingertip reached down the two sides of the finger close a
/// loop around vertices at the finger's base, e^25 times larger than they at the tip of a
/// finger four times as long as it is round: a relative error of 1e-3 there. Grown from the
/// smallest faces up, every loop closes around faces no larger than the ones it meets at, and
/// the error stays relative to the local size. Everything runs in T, the rotations included
/// (their rounding adds up along a chain the same way); the sides and turns come from the
/// faces' own shapes, exact at any scale. No least-squares fit either: it spreads errors of the
/// size of the whole disk over every face.
template <class T>
std::vector<Point2<T>> develop_disk(const DiskMap& in) {
  const Topology& t = in.disk;
  const int nf = t.num_faces;
  // Side from corner `from` to corner `to` of face f in its own frame, exactly in T.
  auto side = [&](int f, int from, int to) {
    return Point2<T>{
        static_cast<T>(in.shapes[f][to].real()) - static_cast<T>(in.shapes[f][from].real()),
        static_cast<T>(in.shapes[f][to].imag()) - static_cast<T>(in.shapes[f][from].imag())};
  };
  auto unit = [](const Point2<T>& z) {
    const T norm = square_root(z[0] * z[0] + z[1] * z[1]);
    return Point2<T>{z[0] / norm, z[1] / norm};
  };
  auto conjugate = [](const Point2<T>& z) { return Point2<T>{z[0], -z[1]}; };
  auto plus = [](const Point2<T>& z, const Point2<T>& w) {
    return Point2<T>{z[0] + w[0], z[1] + w[1]};
  };
  auto minus = [](const Point2<T>& z, const Point2<T>& w) {
    return Point2<T>{z[0] - w[0], z[1] - w[1]};
  };
  std::vector<Point2<T>> rotation(nf), translation(nf);
  // Corner k of face f in its region's frame.
  auto corner = [&](int f, int k) {
    const Point2<T> s{static_cast<T>(in.shapes[f][k].real()),
                      static_cast<T>(in.shapes[f][k].imag())};
    return plus(times(rotation[f], s), translation[f]);
  };
  // The faces by size (longest side), ties by index.
  std::vector<double> size(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& s = in.shapes[f];
    size[f] = std::max({std::abs(s[1] - s[0]), std::abs(s[2] - s[1]), std::abs(s[0] - s[2])});
  }
  std::vector<int> order(nf);
  for (int f = 0; f < nf; ++f) order[f] = f;
  std::sort(order.begin(), order.end(),
            [&](int f, int g) { return size[f] < size[g] || (size[f] == size[g] && f < g); });
  std::vector<int> region(nf, -1);            // region of each laid-out face
  std::vector<std::vector<int>> members(nf);  // faces of each region (indexed by its first face)
  for (int f : order) {
    int joined = -1;
    for (int k = 0; k < 3; ++k) {
      const int twin = t.halfedge_twin[3 * f + k];
      if (twin < 0) continue;
      const int g = Topology::face_of(twin), c = twin % 3;
      if (region[g] < 0 || region[g] == joined) continue;
      // The shared edge: f's corners k + 1 -> k + 2 are g's corners c + 2 -> c + 1.
      const int fa = (k + 1) % 3, fb = (k + 2) % 3, ga = (c + 2) % 3;
      if (joined < 0) {
        // f joins g's region, its side turned onto g's.
        const Point2<T> in_g = times(rotation[g], side(g, ga, (c + 1) % 3));
        rotation[f] = unit(times(in_g, conjugate(side(f, fa, fb))));
        translation[f] = {T{0}, T{0}};
        translation[f] = minus(corner(g, ga), corner(f, fa));
        joined = region[g];
        region[f] = joined;
        members[joined].push_back(f);
        continue;
      }
      // Another region across this edge: the smaller moves, turning its copy of the edge onto
      // the other's.
      int from = region[g], onto = joined;
      int moving_face = g, moving_a = ga, moving_b = (c + 1) % 3;
      int fixed_face = f, fixed_a = fa, fixed_b = fb;
      if (members[from].size() > members[onto].size()) {
        std::swap(from, onto);
        std::swap(moving_face, fixed_face);
        std::swap(moving_a, fixed_a);
        std::swap(moving_b, fixed_b);
      }
      const Point2<T> moving_a_at = corner(moving_face, moving_a);
      const Point2<T> fixed_a_at = corner(fixed_face, fixed_a);
      const Point2<T> turn =
          unit(times(minus(corner(fixed_face, fixed_b), fixed_a_at),
                     conjugate(minus(corner(moving_face, moving_b), moving_a_at))));
      for (int h : members[from]) {
        // z -> turn (z - moving_a_at) + fixed_a_at, applied to the frame of h.
        rotation[h] = times(turn, rotation[h]);
        translation[h] = plus(times(turn, minus(translation[h], moving_a_at)), fixed_a_at);
        region[h] = onto;
      }
      members[onto].insert(members[onto].end(), members[from].begin(), members[from].end());
      members[from].clear();
      members[from].shrink_to_fit();
      joined = onto;
    }
    if (joined < 0) {  // a region of its own
      rotation[f] = {T{1}, T{0}};
      translation[f] = {T{0}, T{0}};
      region[f] = f;
      members[f].push_back(f);
    }
  }
  std::vector<Point2<T>> p(t.num_vertices, Point2<T>{T{0}, T{0}});
  std::vector<char> placed(t.num_vertices, 0);
  for (int f : order) {
    for (int k = 0; k < 3; ++k) {
      const int v = t.triangles(f, k);
      if (placed[v]) continue;
      p[v] = corner(f, k);
      placed[v] = 1;
    }
  }
  return p;
}

template std::vector<Point2<double>> develop_disk<double>(const DiskMap&);
template std::vector<Point2<long double>> develop_disk<long double>(const DiskMap&);
#ifdef RICCI_HAVE_QUAD
template std::vector<Point2<Quad>> develop_disk<Quad>(const DiskMap&);
#endif

}  // namespace ricci::sphere_support
