// Definitions of RS<S>: growth, merge, Tribox corners, support, volume, overlap and distance bounds.
#ifndef FCL_RS_RS_INL_H
#define FCL_RS_RS_INL_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "fcl_rs/bv/lanes.h"
#include "fcl_rs/bv/pca.h"
#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

namespace detail {

template <typename S>
constexpr S eps() { return std::numeric_limits<S>::epsilon(); }

/// The unit of storage rounding: eps of RS::Stored when it is narrower than S, else 0 (nothing is rounded).
template <typename S>
constexpr S storageEps()
{
  if constexpr (std::is_same_v<S, typename RS<S>::Stored>)
    return 0;
  else
    return S(eps<typename RS<S>::Stored>());
}

/// What storing a volume in RS::Stored costs anything computed from two volumes (pairRoundingBound carries it,
/// contain() and merges too), for reach = the volumes' reaches (Box::reach) summed. With v = storageEps<S>():
///  - slabs: each is rounded outward on its own, so the 18 values stop being one support function by up to an
///    ulp each, <= sqrt(2) v reach (a flat leaf's chamfers, rounded at the leaf's size, pass its thin box by
///    that much). Corners and SupportCorner's values are piecewise linear in the slab values, with coefficient
///    magnitudes summing below 30: they move by < 43 v reach. Faces and principal boxes need none of it (each
///    stored slab contains the points on its own).
///  - frames: a frame rounded to nearest, A = fl(Q) for an orthonormal Q, has |A^T A - I| <= v per entry, so
///    its inverse transpose (which maps frame coordinates to model ones: x = o + A^-T y, as the fit measured
///    y = A^T (x - o)) differs from A by <= sqrt(3) v per column (2-norm). The pair kernel uses A for both, so M =
///    A1^T (R A2) is off by <= sqrt(3) v <= 2v per entry against the exact maps b2 -> b1 (A1^T R A2^-T) and b1
///    -> b2 (A1^-1 R A2), as are the moved box centres (the comment above pairRoundingBound follows M's error
///    through the comparisons: a point y2 moves by m |y2|_1 for a per-entry error m, the worst comparison (a
///    diagonal of b2, sqrt(2) scale) by <= 34 m reaches), i.e. <= 48 v reaches on the unit scale.
/// First-order total <= 91 v reaches; the bound is 128 v reaches (about 1.5e-5 of the volumes' size for
/// RS<double>, 0 for RS<float>).
template <typename S>
S storageBound(S reach)
{
  return 128 * storageEps<S>() * reach;
}

/// Unit direction of slab k in frame coordinates.
template <typename S>
fcl::Vector3<S> slabDirection(int k)
{
  const SlabDirection& d = kSlabDirections[k];
  fcl::Vector3<S> v = fcl::Vector3<S>::Zero();
  if (d.sign == 0) { v[d.i] = 1; return v; }
  v[d.i] = S(M_SQRT1_2);
  v[d.j] = S(d.sign) * S(M_SQRT1_2);
  return v;
}

/// Rows of M combined as slab k's direction: M^T d_k for a unit slab direction d_k.
template <typename S>
fcl::Vector3<S> slabOfRows(const fcl::Matrix3<S>& M, int k)
{
  const SlabDirection& d = kSlabDirections[k];
  if (d.sign == 0) return M.row(d.i).transpose();
  return (M.row(d.i) + S(d.sign) * M.row(d.j)).transpose() * S(M_SQRT1_2);
}

/// Columns of M combined as slab k's direction: M d_k.
template <typename S>
fcl::Vector3<S> slabOfColumns(const fcl::Matrix3<S>& M, int k)
{
  const SlabDirection& d = kSlabDirections[k];
  if (d.sign == 0) return M.col(d.i);
  return (M.col(d.i) + S(d.sign) * M.col(d.j)) * S(M_SQRT1_2);
}

template <typename S>
int octantOf(const fcl::Vector3<S>& dir)
{
  return (dir[0] < 0 ? 1 : 0) | (dir[1] < 0 ? 2 : 0) | (dir[2] < 0 ? 4 : 0);
}

}  // namespace detail

// The stored identity directly, not the identity in S rounded to storage: FCL builds a default volume for every
// node it allocates, as many as the fit builds.
template <typename S>
RS<S>::RS() : axis(Axes::Identity()), origin(fcl::Vector3<S>::Zero())
{
}

template <typename S>
RS<S>::RS(const fcl::Matrix3<S>& axis_, const fcl::Vector3<S>& origin_)
  : axis(axis_.template cast<Stored>()), origin(origin_)
{
}

template <typename S>
template <int n>
Eigen::Array<typename RS<S>::Stored, n, 1> RS<S>::slabsBelow(const Eigen::Array<S, n, 1>& v)
{
  if constexpr (std::is_same_v<S, Stored>)
    return v;
  else
  {
    // Rounding to nearest moves a value by at most half an ulp: 2^-24 of it, or half the smallest subnormal.
    // Stepping down by eps(float) = 2^-23 of it and the smallest subnormal first leaves the rounded value <= v,
    // at most two ulps below the largest such float, without branches (the fit rounds 18 values per node).
    // Past float's range, rounding to nearest gives infinity, which a lower end may only be on the low side.
    const Eigen::Array<S, n, 1> stepped = (v - v.abs() * S(std::numeric_limits<Stored>::epsilon()) -
                                           S(std::numeric_limits<Stored>::denorm_min()))
                                              .min(S(std::numeric_limits<Stored>::max()));
    Eigen::Array<Stored, n, 1> rounded;  // not stepped.cast<Stored>(): gcc 12 calls Eigen's constructor for it
    for (int k = 0; k < n; ++k) rounded[k] = static_cast<Stored>(stepped[k]);
    return rounded;
  }
}

template <typename S>
template <int n>
Eigen::Array<typename RS<S>::Stored, n, 1> RS<S>::slabsAbove(const Eigen::Array<S, n, 1>& v)
{
  return -slabsBelow<n>(-v);
}

template <typename S>
typename RS<S>::Stored RS<S>::slabBelow(S v)
{
  return slabsBelow<1>(Eigen::Array<S, 1, 1>(v))[0];
}

template <typename S>
typename RS<S>::Stored RS<S>::slabAbove(S v)
{
  return slabsAbove<1>(Eigen::Array<S, 1, 1>(v))[0];
}

template <typename S>
bool RS<S>::empty() const
{
  return !(lo[0] <= hi[0]);
}

template <typename S>
void RS<S>::expandFrame(const fcl::Vector3<S>& y, S abs_err)
{
  // Projection rounding is a few ulps of |y|; the caller adds what it knows of y's own error.
  const S err = abs_err + 4 * detail::eps<S>() * y.template lpNorm<1>();
  for (int k = 0; k < kNumSlabs; ++k)
  {
    const S v = projectOnSlab(y, k);
    lo[k] = std::min(lo[k], slabBelow(v - err));
    hi[k] = std::max(hi[k], slabAbove(v + err));
  }
}

template <typename S>
template <typename PointAt>
void RS<S>::expandPoints(int n, PointAt point_at)
{
  using Array = Eigen::Array<S, kNumSlabs, 1>;
  Array low = Array::Constant(std::numeric_limits<S>::max());
  Array high = Array::Constant(std::numeric_limits<S>::lowest());
  S largest_norm1 = 0;
  // Diagonal projections are (y_i +- y_j) / sqrt(2): the extremes of the sums are scaled once, after the loop.
  // Rounded multiplication by a positive constant is monotone, so this gives projectOnSlab's extremes exactly.
  Array unit;
  for (int k = 0; k < kNumSlabs; ++k) unit[k] = kSlabDirections[std::size_t(k)].sign == 0 ? S(1) : S(M_SQRT1_2);
  const fcl::Matrix3<S> A = axes();  // toFrame's, converted once
  for (int i = 0; i < n; ++i)
  {
    const fcl::Vector3<S> y = A.transpose() * (point_at(i) - origin);
    Array v;
    for (int k = 0; k < kNumSlabs; ++k)
    {
      const SlabDirection& d = kSlabDirections[std::size_t(k)];
      v[k] = d.sign == 0 ? y[d.i] : y[d.i] + S(d.sign) * y[d.j];
    }
    low = low.min(v);
    high = high.max(v);
    largest_norm1 = std::max(largest_norm1, y.template lpNorm<1>());
  }
  if (n > 0)
  {
    const S err = 4 * detail::eps<S>() * largest_norm1;  // as expandFrame's, for the largest point
    lo = lo.cwiseMin(slabsBelow<kNumSlabs>(low * unit - err).matrix());
    hi = hi.cwiseMax(slabsAbove<kNumSlabs>(high * unit + err).matrix());
  }
  updateBoxExcess();
}

template <typename S>
RS<S>& RS<S>::operator+=(const fcl::Vector3<S>& p)
{
  if (empty()) origin = p;
  expandFrame(toFrame(p), 0);
  updateBoxExcess();
  return *this;
}

template <typename S>
void RS<S>::updateBoxExcess()
{
  box_excess = 0;
  if (empty()) return;
  // cornerVertices' four cases in closed form: with a, b, c the depths of the chamfers xy, xz, yz below the
  // box corner, its vertices on the principal planes are at squared distances a²+b², a²+c², b²+c², the
  // chamfers' triple point at ex²+ey²+ez²; where the triple point passes a principal plane (e > 0), two
  // vertices on that plane replace it. Rounding only moves the bound by ulps, which costs pruning at most.
  // All eight corners at once (one lane per octant, bit i set = negative along u_i, as cornerPlanes), every case
  // computed and the right one selected: a build fits one volume per node and branches cost more than the lanes.
  using Octants = Eigen::Array<double, 8, 1>;
  const auto end = [this](int k, int pattern) {  // lane o: -lo[k] where bit o of pattern is set, else hi[k]
    Octants v;
    for (int o = 0; o < 8; ++o) v[o] = (pattern >> o) & 1 ? -double(lo[k]) : double(hi[k]);
    return v;
  };
  // cornerPlanes' unnormalised chamfer over axes i, j: the minus slab where the two signs differ.
  const auto chamfer = [this](int i, int j) {
    Octants v;
    for (int o = 0; o < 8; ++o)
    {
      const bool ni = (o >> i) & 1, nj = (o >> j) & 1;
      const int k = diagonalIndex(i, j, ni == nj ? +1 : -1);
      v[o] = M_SQRT2 * (ni ? -double(lo[k]) : double(hi[k]));
    }
    return v;
  };
  const Octants X = end(0, 0b10101010), Y = end(1, 0b11001100), Z = end(2, 0b11110000);
  const Octants a = X + Y - chamfer(0, 1), b = X + Z - chamfer(0, 2), c = Y + Z - chamfer(1, 2);
  const Octants ex = (c - a - b) / 2, ey = (b - a - c) / 2, ez = (a - b - c) / 2;
  const Octants ab = a * a + b * b, ac = a * a + c * c, bc = b * b + c * c;
  const Octants inside = (ex * ex + ey * ey + ez * ez).min(ab).min(ac).min(bc);
  const Octants past_x = (a * a + (c - a) * (c - a)).min(b * b + (c - b) * (c - b)).min(ac).min(bc);
  const Octants past_y = (a * a + (b - a) * (b - a)).min(c * c + (b - c) * (b - c)).min(ab).min(bc);
  const Octants past_z = (b * b + (a - b) * (a - b)).min(c * c + (a - c) * (a - c)).min(ab).min(ac);
  const Octants nearest = (ex <= 0 && ey <= 0 && ez <= 0)
                              .select(inside, (ex >= ey && ex >= ez).select(past_x, (ey >= ez).select(past_y, past_z)));
  const S nearest_squared = S(std::max(0.0, nearest.maxCoeff()));
  box_excess = Stored(std::sqrt(nearest_squared));
}

template <typename S>
RS<S>& RS<S>::operator+=(const RS<S>& other)
{
  if (other.empty()) return *this;
  const auto pts = other.corners();
  if (empty()) origin = other.origin;
  // Corners carry the rounding of other's slab arithmetic and of the change of frame. The change of frame goes
  // through the origins' difference, never through model coordinates: far from the model origin those round
  // at the origins' magnitude, which can exceed the volumes themselves (a float merge 254 from the origin
  // missed a point by 9e-7 on a volume of 3e-4; found by fuzz_rs).
  const fcl::Vector3<S> shift = other.origin - origin;
  // other.axes() * c stands for other's exact inverse transpose (storageBound).
  const S abs_err = 8 * detail::eps<S>() * (other.magnitude() + shift.template lpNorm<1>()) +
                    detail::storageBound(other.magnitude());
  const fcl::Matrix3<S> A = axes(), other_axes = other.axes();
  for (const auto& c : pts) expandFrame(A.transpose() * (shift + other_axes * c), abs_err);
  updateBoxExcess();
  return *this;
}

template <typename S>
RS<S> RS<S>::operator+(const RS<S>& other) const
{
  if (other.empty()) return *this;
  if (empty()) return other;
  const auto a = corners();
  const auto b = other.corners();
  const auto frame = principalFrame<S>(64, [&](int i) -> fcl::Vector3<S> {
    return i < 32 ? toModel(a[i]) : other.toModel(b[i - 32]);
  });
  RS<S> merged(frame.axis, frame.mean);
  merged += *this;
  merged += other;
  return merged;
}

template <typename S>
S RS<S>::magnitude() const
{
  return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
}

template <typename S>
typename RS<S>::CornerPlanes RS<S>::cornerPlanes(int octant) const
{
  const bool nx = octant & 1, ny = octant & 2, nz = octant & 4;
  auto chamfer = [this](bool ni, bool nj, int plus, int minus) {
    const int k = ni == nj ? plus : minus;
    return S(M_SQRT2) * (ni ? -lo[k] : hi[k]);
  };
  return {nx ? -lo[0] : hi[0],
          ny ? -lo[1] : hi[1],
          nz ? -lo[2] : hi[2],
          chamfer(nx, ny, diagonalIndex(0, 1, +1), diagonalIndex(0, 1, -1)),
          chamfer(nx, nz, diagonalIndex(0, 2, +1), diagonalIndex(0, 2, -1)),
          chamfer(ny, nz, diagonalIndex(1, 2, +1), diagonalIndex(1, 2, -1))};
}

template <typename S>
void RS<S>::cornerVertices(int octant, fcl::Vector3<S>* v) const
{
  // Tribox, in the frame reflected so that this corner is (+,+,+) (cornerPlanes).
  const bool nx = octant & 1, ny = octant & 2, nz = octant & 4;
  const auto [X, Y, Z, Cxy, Cxz, Cyz] = cornerPlanes(octant);

  // The chamfer triple point can pass at most one principal plane (the slab values are a support
  // function), which leaves four configurations of four vertices each.
  const S ex = (Cxy + Cxz - Cyz) / 2 - X;
  const S ey = (Cxy + Cyz - Cxz) / 2 - Y;
  const S ez = (Cxz + Cyz - Cxy) / 2 - Z;
  using V = fcl::Vector3<S>;
  const V onA(X, Cxy - X, Cxz - X), onB(Cxy - Y, Y, Cyz - Y), onC(Cxz - Z, Cyz - Z, Z);
  if (ex <= 0 && ey <= 0 && ez <= 0)
  {
    v[0] = V(ex + X, ey + Y, ez + Z);
    v[1] = onA; v[2] = onB; v[3] = onC;
  }
  else if (ex >= ey && ex >= ez)
  {
    v[0] = V(X, Cxy - X, Cyz - Cxy + X);
    v[1] = V(X, Cyz - Cxz + X, Cxz - X);
    v[2] = onB; v[3] = onC;
  }
  else if (ey >= ez)
  {
    v[0] = V(Cxy - Y, Y, Cxz - Cxy + Y);
    v[1] = V(Cxz - Cyz + Y, Y, Cyz - Y);
    v[2] = onA; v[3] = onC;
  }
  else
  {
    v[0] = V(Cxz - Z, Cxy - Cxz + Z, Z);
    v[1] = V(Cxy - Cyz + Z, Cyz - Z, Z);
    v[2] = onA; v[3] = onB;
  }
  const V sign(nx ? S(-1) : S(1), ny ? S(-1) : S(1), nz ? S(-1) : S(1));
  for (int i = 0; i < 4; ++i) v[i] = v[i].cwiseProduct(sign);
}

template <typename S>
std::array<fcl::Vector3<S>, 4> RS<S>::cornerVertices(int octant) const
{
  std::array<fcl::Vector3<S>, 4> v;
  cornerVertices(octant, v.data());
  return v;
}

template <typename S>
std::array<fcl::Vector3<S>, 32> RS<S>::corners() const
{
  std::array<fcl::Vector3<S>, 32> all;
  for (int o = 0; o < 8; ++o)
  {
    cornerVertices(o, all.data() + 4 * o);
  }
  return all;
}

namespace detail {

/// support()'s corner, shared with extremeVertex. The maximum of dir . y is at one of the 4 vertices of the
/// corner in dir's octant. Reflect that corner to (+,+,+) (so e = |dir|) and write the vertices of all four
/// configurations at once: with a, b, c = how far the chamfer triple point P passes the principal planes (at
/// most one is positive), the vertices are P - a(1,-1,1) - (b+c)(-1,1,1), onA - 2a e_z, onA - 2a e_y,
/// onB - 2b e_z, onB - 2b e_x, onC - 2c e_y, onC - 2c e_x (repeats allowed). No branches, which matters in a
/// traversal where every test meets a different configuration. Slab ends are picked by indexing, not by
/// conditionals: a sign branch would be mispredicted half the time.
template <typename S>
struct SupportCorner
{
  SupportCorner(const RS<S>& rs, const fcl::Vector3<S>& dir)
    : ex(std::abs(dir[0])), ey(std::abs(dir[1])), ez(std::abs(dir[2])), nx(dir[0] < 0), ny(dir[1] < 0),
      nz(dir[2] < 0)
  {
    const S flip[2] = {S(1), S(-1)};
    const typename RS<S>::Stored* const ends[2] = {rs.hi.data(), rs.lo.data()};
    auto end = [&](int neg, int k) { return flip[neg] * ends[neg][k]; };
    X = end(nx, 0);
    Y = end(ny, 1);
    Z = end(nz, 2);
    // The chamfer over (u_i, u_j) facing this corner is the "plus" diagonal when the signs agree.
    const int minus = diagonalIndex(0, 1, -1) - diagonalIndex(0, 1, +1);
    Cxy = S(M_SQRT2) * end(nx, diagonalIndex(0, 1, +1) + minus * (nx ^ ny));
    Cxz = S(M_SQRT2) * end(nx, diagonalIndex(0, 2, +1) + minus * (nx ^ nz));
    Cyz = S(M_SQRT2) * end(ny, diagonalIndex(1, 2, +1) + minus * (ny ^ nz));
    Px = (Cxy + Cxz - Cyz) / 2;
    Py = (Cxy + Cyz - Cxz) / 2;
    Pz = (Cxz + Cyz - Cxy) / 2;
    auto positive = [](S v) { return v > 0 ? v : S(0); };
    a = positive(Px - X);
    b = positive(Py - Y);
    c = positive(Pz - Z);
    at_p = ex * Px + ey * Py + ez * Pz - a * (ex - ey + ez) - (b + c) * (ey + ez - ex);
    at_a = X * (ex - ey - ez) + Cxy * ey + Cxz * ez - 2 * a * std::min(ey, ez);
    at_b = Y * (ey - ex - ez) + Cxy * ex + Cyz * ez - 2 * b * std::min(ex, ez);
    at_c = Z * (ez - ex - ey) + Cxz * ex + Cyz * ey - 2 * c * std::min(ex, ey);
  }
  S max() const { return std::max(std::max(at_p, at_a), std::max(at_b, at_c)); }
  /// The vertex attaining max(), in the volume's frame (extremeVertex).
  fcl::Vector3<S> vertex() const
  {
    using V = fcl::Vector3<S>;
    V v;
    if (at_p >= std::max(std::max(at_a, at_b), at_c))
      v = V(Px - a + b + c, Py + a - b - c, Pz - a - b - c);
    else if (at_a >= at_b && at_a >= at_c)
      v = ez <= ey ? V(X, Cxy - X, Cxz - X - 2 * a) : V(X, Cxy - X - 2 * a, Cxz - X);
    else if (at_b >= at_c)
      v = ez <= ex ? V(Cxy - Y, Y, Cyz - Y - 2 * b) : V(Cxy - Y - 2 * b, Y, Cyz - Y);
    else
      v = ey <= ex ? V(Cxz - Z, Cyz - Z - 2 * c, Z) : V(Cxz - Z - 2 * c, Cyz - Z, Z);
    return V(nx ? -v[0] : v[0], ny ? -v[1] : v[1], nz ? -v[2] : v[2]);
  }

  S ex, ey, ez;
  int nx, ny, nz;
  S X, Y, Z, Cxy, Cxz, Cyz, Px, Py, Pz, a, b, c;
  S at_p, at_a, at_b, at_c;  ///< dir . (each configuration's best vertex)
};

}  // namespace detail

template <typename S>
S RS<S>::support(const fcl::Vector3<S>& dir) const
{
  return detail::SupportCorner<S>(*this, dir).max();
}

template <typename S>
bool RS<S>::overlap(const RS<S>& other) const
{
  return fcl_rs::overlap<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), *this, other);
}

template <typename S>
bool RS<S>::contain(const fcl::Vector3<S>& p) const
{
  if (empty()) return false;
  const fcl::Vector3<S> y = toFrame(p);
  const S tol = 8 * detail::eps<S>() * (y.template lpNorm<1>() + magnitude()) + detail::storageBound(magnitude());
  for (int k = 0; k < kNumSlabs; ++k)
  {
    const S v = projectOnSlab(y, k);
    if (v < lo[k] - tol || v > hi[k] + tol) return false;
  }
  return true;
}

template <typename S>
S RS<S>::distance(const RS<S>& other, fcl::Vector3<S>* P, fcl::Vector3<S>* Q) const
{
  return fcl_rs::distance<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), *this, other, P, Q);
}

template <typename S>
fcl::Vector3<S> RS<S>::center() const
{
  if (empty()) return origin;
  return toModel((lo.template head<3>().template cast<S>() + hi.template head<3>().template cast<S>()) / 2);
}

template <typename S>
S RS<S>::width() const { return empty() ? S(0) : S(hi[0]) - S(lo[0]); }

template <typename S>
S RS<S>::height() const { return empty() ? S(0) : S(hi[1]) - S(lo[1]); }

template <typename S>
S RS<S>::depth() const { return empty() ? S(0) : S(hi[2]) - S(lo[2]); }

template <typename S>
S RS<S>::size() const
{
  // Only orders nodes (the traversals compare sizes at every split): computed in the stored precision.
  return empty() ? S(0) : S((hi.template head<3>() - lo.template head<3>()).squaredNorm());
}

template <typename S>
S RS<S>::volume() const
{
  if (empty()) return 0;
  // Divergence theorem: V = sum over the 18 faces of area_f * (h_f - n_f . c) / 3, for any point c.
  // Each face polygon is its plane clipped by the other 17 halfspaces, in double, so thin volumes
  // need no tolerance to decide which corners lie on which face.
  using V3 = Eigen::Vector3d;
  const V3 c((double(lo[0]) + hi[0]) / 2, (double(lo[1]) + hi[1]) / 2, (double(lo[2]) + hi[2]) / 2);
  const double reach = 4 * double(magnitude()) + 1;
  double total = 0;
  for (int face = 0; face < 2 * kNumSlabs; ++face)
  {
    auto plane = [this](int f, V3& n) {
      const int k = f % kNumSlabs;
      const double side = f < kNumSlabs ? 1.0 : -1.0;
      n = side * detail::slabDirection<double>(k);
      return f < kNumSlabs ? double(hi[k]) : -double(lo[k]);
    };
    V3 n;
    const double h = plane(face, n);
    const V3 a = n.unitOrthogonal(), b = n.cross(a), base = h * n;
    std::vector<V3> poly = {base + reach * (a + b), base + reach * (b - a), base - reach * (a + b),
                            base + reach * (a - b)};
    for (int other = 0; other < 2 * kNumSlabs && !poly.empty(); ++other)
    {
      if (other == face) continue;
      V3 m;
      const double g = plane(other, m);
      std::vector<V3> kept;
      for (std::size_t i = 0; i < poly.size(); ++i)
      {
        const V3& p = poly[i];
        const V3& q = poly[(i + 1) % poly.size()];
        const double dp = m.dot(p) - g, dq = m.dot(q) - g;
        if (dp <= 0) kept.push_back(p);
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) kept.push_back(p + (q - p) * (dp / (dp - dq)));
      }
      poly.swap(kept);
    }
    double area = 0;
    for (std::size_t i = 1; i + 1 < poly.size(); ++i)
      area += (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).dot(n);
    total += 0.5 * std::abs(area) * (h - n.dot(c)) / 3;
  }
  // That is the polytope in frame coordinates; the volume is its image x = origin + A^-T y under the stored
  // frame A, orthonormal only up to its storage.
  return S(std::max(0.0, total) / std::abs(axis.template cast<double>().determinant()));
}

namespace detail {

/// The principal box of a volume: centre and half extents in its frame.
template <typename S>
struct Box
{
  Box() = default;
  /// Computed in S from any volume's stored slabs (boxedOverlap works in the storage precision).
  template <typename VolumeS>
  explicit Box(const RS<VolumeS>& b)
    : c((b.lo.template head<3>().template cast<S>() + b.hi.template head<3>().template cast<S>()) / 2),
      h((b.hi.template head<3>().template cast<S>() - b.lo.template head<3>().template cast<S>()) / 2)
  {
  }
  /// How far the box reaches from its frame's origin along an axis; every slab value of the volume is at most
  /// sqrt(2) times this (the polytope lies in the box), so it scales the rounding of anything computed from it.
  S reach() const { return (c.cwiseAbs() + h).maxCoeff(); }
  fcl::Vector3<S> c, h;
};

/// The one rounding bound of every pair test (overlap variants, distance bounds, mesh-shape bounds): an upper
/// bound on the error of a comparison made in b1's frame between quantities derived from two volumes.
/// `offsets` is the L1 size of the translations the relative frame is built from (|R o2|_1 + |T|_1 + |o1|_1),
/// `reaches` the sum of both boxes' reach(). With u = eps:
///  - M = A1^T (R A2): two nested 3-term dot products of entries <= 1, plus the stored frames' departure from
///    orthonormality at S's precision (the fits pad for the rounding of A^T x, not for A^-T = A; a frame stored
///    narrower than S departs further, storageBound below): <= 16u per entry, so a point
///    y2 of b2 (|y2|_1 <= 3 reach2) moves by <= 48u reach2, and a vector v by <= 16u |v|_1;
///  - b2's box centre in b1's frame, A1^T ((R o2 + T) + (R A2) c2 - o1): the translations carry <= 8u offsets
///    per coordinate, the centre (|c2|_1 <= 3 reach2) <= 40u reach2; d = centre2 - c1 is within
///    8u offsets + 42u reaches, and so is t = centre2 - M c2 within 8u offsets + 102u reaches;
///  - face axes of b1 (|d_i| against h1_i + sum_c |M_ic| h2_c, sum_c h2_c <= 3 reach2): <= 8u offsets + 102u
///    reaches. Face axes of b2 (e = -M^T d, against h2 + sum_r |M_ri| h1_r): they decide a pair only when no axis
///    of b1 does, so |d|_1 <= 3 reach1 + 3 sqrt(3) reach2 (+ tol), and e carries sqrt(3) times d's error plus
///    19u |d|_1: <= 14u offsets + 232u reaches with the radius;
///  - diagonals, compared sqrt(2) times (against sqrt(2) tol): a sum or difference of two of those coordinates,
///    radii that are L1 norms of sums of two rows or columns of M scaled by the half extents (<= 110u reaches),
///    slab middles (<= 12u reaches): <= 28u offsets + 466u reaches;
///  - supports, projections and corner coordinates (exact variants, distance bounds) are sums of <= 6 products
///    of values <= sqrt(2) times the reaches (|dir| <= 1): <= 12 sqrt(2) u (reach1 + reach2) on top of t or d.
///  (R A2, R o2 + T, b2's box, its moved centre, its diagonal slabs from the centre and |R o2|_1 + |T|_1 are
///  computed once per node and query, MovedFrame, by the same operations as per pair.)
/// First-order total <= 28u offsets + 466u reaches on the diagonals' sqrt(2) scale, <= 14u offsets + 232u
/// reaches elsewhere; the bound is at least 1.5 times that (sqrt(2) tol = 45u offsets + 724u reaches), and the
/// rest is of order u^2.
/// A query between posed objects adds the world frame's rounding to offsets: |t1|_1 + |t2|_1 of the poses.
/// Contacts are promised for the world-frame vertices as computed, fl(R1 p + t1) and fl(R2 q + t2), each
/// within u (|R p|_1 + |t|_1) of the exact pose per coordinate, which (R, T) in A's frame never sees: far
/// from the origin (|t| >> the meshes and T) that is the largest term, and without it grazing pairs that
/// touch in the world frame are culled. The leaf test's tolerance (narrowphase/triangle_intersection.h)
/// carries the same term.
/// Plus storageBound(reaches + separation): the same errors where they come from storing the volumes narrower
/// than S (a float frame's departure from orthonormality, slabs rounded outward one by one), 0 for RS<float>.
/// `separation` is |d|_1, the box centres' distance in b1's frame: M's storage error maps it into b2's frame (e =
/// -M^T d, centre1()). At S's precision the offsets cover it; at storage precision they would cost far-away
/// volumes all pruning, while the separation only costs volumes farther apart than their own size (overlapping
/// volumes have |d|_1 <= 3 reach1 + 3 sqrt(3) reach2; the distance bounds need it).
template <typename S>
S pairRoundingBound(S offsets, S reaches, S separation = 0)
{
  return 32 * eps<S>() * (offsets + 16 * reaches) + storageBound(reaches + separation);
}

/// pairRoundingBound of a test that computes in the storage precision C = RS<S>::Stored what PairFrame computes in
/// S (boxedOverlap): only delta, the vector from b1's frame origin to b2's moved box centre, is formed in S and
/// rounded to C. The derivation above holds at C's precision with delta's L1 size for the translations' offsets;
/// the error of delta itself is pairRoundingBound's in S. The bound's own rounding to C is far inside its margin.
template <typename S>
typename RS<S>::Stored storedPairRoundingBound(S offsets, S reaches, S separation, S delta_norm1)
{
  using C = typename RS<S>::Stored;
  S bound = pairRoundingBound<S>(offsets, reaches, separation);
  if constexpr (!std::is_same_v<C, S>) bound += 32 * S(eps<C>()) * (delta_norm1 + 16 * reaches);
  return C(bound);
}

/// A volume's six diagonal slabs in diagonalLanes' order: lo[0], hi[0] hold slabs 3-6, lo[1], hi[1] slabs 7 and 8.
template <typename S>
void diagonalSlabs(const RS<S>& b, Lanes lo[2], Lanes hi[2])
{
  using Map = Eigen::Map<const Lanes, Eigen::Unaligned>;
  lo[0] = Map(b.lo.data() + 3);
  hi[0] = Map(b.hi.data() + 3);
  lo[1] = Lanes(b.lo[7], b.lo[8], 0.0f, 0.0f);
  hi[1] = Lanes(b.hi[7], b.hi[8], 0.0f, 0.0f);
}

/// The part of the pair kernel that depends on b2 and the query only: b2's frame and box centre moved by (R, T)
/// into b1's model coordinates, and b2's principal box and diagonal slabs measured from the box centre. A
/// traversal computes it once per visited node of its second tree and reuses it for every node of the first
/// tree that node meets.
template <typename S>
struct MovedFrame
{
  /// Uninitialised, for arrays filled as a traversal reaches their nodes.
  MovedFrame() = default;
  /// world_offsets: |t1|_1 + |t2|_1 of the query's poses (pairRoundingBound), 0 without poses.
  MovedFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0) : box(b2)
  {
    const fcl::Vector3<S> o2 = R * b2.origin;
    axis.noalias() = R.lazyProduct(b2.axes());
    origin = o2 + T;
    centre.noalias() = axis * box.c + origin;
    offsets = o2.template lpNorm<1>() + T.template lpNorm<1>() + world_offsets;
    reach = box.reach();
  }
  fcl::Matrix3<S> axis;    ///< R A2
  fcl::Vector3<S> origin;  ///< R o2 + T
  Box<S> box;              ///< b2's principal box, in b2's frame
  fcl::Vector3<S> centre;  ///< the box's centre moved: R (o2 + A2 c2) + T
  S offsets;               ///< |R o2|_1 + |T|_1 (+ world_offsets), the translations' part of pairRoundingBound's offsets
  S reach;                 ///< box.reach()
};

/// MovedFrame plus what boxedOverlap reads of b2, in float lanes: collision traversals build it once per visited
/// node and query; distance traversals, which never run the boxed test, keep the plain MovedFrame.
template <typename S>
struct BoxedFrame : MovedFrame<S>
{
  BoxedFrame() = default;
  BoxedFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0)
    : MovedFrame<S>(R, T, b2, world_offsets)
  {
    const fcl::Matrix3<S>& axis = this->axis;
    const Box<S>& box = this->box;
    for (int k = 0; k < 3; ++k) axis_rows[k] = Lanes(float(axis(k, 0)), float(axis(k, 1)), float(axis(k, 2)), 0.0f);
    half_extents = Lanes(float(box.h[0]), float(box.h[1]), float(box.h[2]), 0.0f);
    Lanes lo[2], hi[2], centre_diagonal[2];
    diagonalSlabs(b2, lo, hi);
    diagonalLanes(Lanes(float(box.c[0]), float(box.c[1]), float(box.c[2]), 0.0f), centre_diagonal[0], centre_diagonal[1]);
    const float scale = float(M_SQRT1_2);
    for (int h = 0; h < 2; ++h)
    {
      diagonal_mid[h] = (lo[h] + hi[h]) * scale - centre_diagonal[h];
      diagonal_half[h] = (hi[h] - lo[h]) * scale;
    }
  }
  /// The rows of axis, box.h, and b2's six diagonal slabs from the box centre, times sqrt(2) (the middle and the
  /// half width of each interval, in diagonalLanes' order).
  Lanes axis_rows[3];
  Lanes half_extents;
  Lanes diagonal_mid[2], diagonal_half[2];
};

/// The pair kernel: b2 expressed in b1's frame (y1 = M y2 + t), both principal boxes, b2's box centre in b1's
/// frame, and the rounding bound of tests made there.
template <typename S>
struct PairFrame
{
  fcl::Matrix3<S> M;
  Box<S> box1, box2;
  fcl::Vector3<S> centre2;  ///< b2's box centre in b1's frame
  S tol;

  PairFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2)
    : PairFrame(MovedFrame<S>(R, T, b2), b1)
  {
  }

  /// moved2 = MovedFrame(R, T, b2).
  PairFrame(const MovedFrame<S>& moved2, const RS<S>& b1) : box1(b1), box2(moved2.box)
  {
    const fcl::Matrix3<S> A1 = b1.axes();
    M.noalias() = A1.transpose().lazyProduct(moved2.axis);
    centre2.noalias() = A1.transpose() * (moved2.centre - b1.origin);
    tol = pairRoundingBound<S>(moved2.offsets + b1.origin.template lpNorm<1>(), box1.reach() + moved2.reach,
                               storageEps<S>() > 0 ? (centre2 - box1.c).template lpNorm<1>() : S(0));
  }

  /// b2's frame origin in b1's frame: y1 = M y2 + t maps b2's frame into b1's.
  fcl::Vector3<S> t() const { return centre2 - M * box2.c; }
  /// b1's box centre in b2's frame.
  fcl::Vector3<S> centre1() const { return M.transpose() * (box1.c - centre2) + box2.c; }
};

/// The vertex of b farthest along dir (both in b's frame): the one support(dir) found.
template <typename S>
fcl::Vector3<S> extremeVertex(const RS<S>& b, const fcl::Vector3<S>& dir)
{
  return SupportCorner<S>(b, dir).vertex();
}

/// One volume's principal box projected on the other volume's nine slab directions: each direction
/// expressed in the projected volume's frame, and the box's interval mid +- radius along it.
template <typename S>
struct ProjectedBox
{
  /// rows: the other volume's principal axes in this volume's frame; centre: this box's centre in
  /// the other volume's frame.
  ProjectedBox(const fcl::Matrix3<S>& rows, const fcl::Vector3<S>& centre, const Box<S>& box)
  {
    for (int k = 0; k < kNumSlabs; ++k)
    {
      dir[k] = slabOfRows(rows, k);
      mid[k] = projectOnSlab(centre, k);
      radius[k] = dir[k].cwiseAbs().dot(box.h);
    }
  }
  fcl::Vector3<S> dir[kNumSlabs];
  S mid[kNumSlabs];
  S radius[kNumSlabs];
};

/// Gap between [lo, hi] and volume b (box c, projection p) along p's direction k; positive means
/// separated. An exact support is computed only on a side where the box sticks out past the
/// interval, since only there can the polytope be apart; elsewhere the box bound is as good.
template <typename S>
S slabGap(S lo, S hi, const RS<S>& b, const Box<S>& box, const ProjectedBox<S>& p, int k)
{
  const fcl::Vector3<S>& e = p.dir[k];
  const S low_box = p.mid[k] - p.radius[k], high_box = p.mid[k] + p.radius[k];
  const S shift = p.mid[k] - e.dot(box.c);  // projection of b's frame origin
  const S lowest = low_box > hi || high_box <= hi ? low_box : shift - b.support(-e);
  const S highest = high_box < lo || low_box >= lo ? high_box : shift + b.support(e);
  return std::max(lowest - hi, lo - highest);
}

}  // namespace detail

namespace detail {

/// The boxed test (OverlapTest::kBoxed): each volume's nine slabs against the other's principal box, measured
/// from the box centres (|middle of the box - middle of the slab| > radius + half width means apart). Each
/// volume's three face axes come first with one exit (most separated pairs end there, as in an OBB test); the
/// twelve diagonals, which every overlapping pair reaches, have no branch. They are compared sqrt(2) times (a
/// diagonal is (u_i +- u_j) / sqrt(2)).
template <typename S>
bool boxedOverlap(const BoxedFrame<S>& moved2, const RS<S>& b1)
{
  // PairFrame's arithmetic in float lanes, reading b1 as stored (no conversions). Lane i of a 3-vector is
  // coordinate i; unused lanes are 0 or never compared.
  static_assert(std::is_same_v<typename RS<S>::Stored, float>, "volumes are stored in float");
  using Map = Eigen::Map<const Lanes, Eigen::Unaligned>;
  // Columns u0, u1, u2; the last column's load reads one float past the frame (the next member), into a lane
  // that only the unused fourth row of a_rows receives.
  const float* A1 = b1.axis.data();
  // Rows of M = A1^T (R A2) (lane c: b2's axis c), then its columns (lane i: b1's axis i).
  Lanes m[3], w[3];
  for (int i = 0; i < 3; ++i)
    m[i] = A1[3 * i] * moved2.axis_rows[0] + A1[3 * i + 1] * moved2.axis_rows[1] + A1[3 * i + 2] * moved2.axis_rows[2];
  transpose3(m[0], m[1], m[2], w);
  Lanes a_rows[3];
  transpose3(Map(A1), Map(A1 + 3), Map(A1 + 6), a_rows);
  const fcl::Vector3<S> delta = moved2.centre - b1.origin;  // in S: both may be far from the model origin
  const Lanes centre2 = float(delta[0]) * a_rows[0] + float(delta[1]) * a_rows[1] + float(delta[2]) * a_rows[2];
  const Lanes lo1 = Map(b1.lo.data()), hi1 = Map(b1.hi.data());  // lane 3 holds the first diagonal: unused
  const Lanes c1 = (lo1 + hi1) * 0.5f, h1 = (hi1 - lo1) * 0.5f;
  const Lanes& h2 = moved2.half_extents;
  const Lanes d = centre2 - c1;  // from b1's box centre to b2's, b1's frame
  const float tol = storedPairRoundingBound<S>(
      moved2.offsets + b1.origin.template lpNorm<1>(), S((c1.abs() + h1).template head<3>().maxCoeff()) + moved2.reach,
      S(d.abs().template head<3>().sum()), delta.template lpNorm<1>());
  // b2's box reaches sum_c |M_ic| h2_c along b1's axis i; b1's box reaches sum_i |M_ic| h1_i along b2's axis c.
  const Lanes gap1 = d.abs() - (w[0].abs() * h2[0] + w[1].abs() * h2[1] + w[2].abs() * h2[2]) - h1;
  if (gap1.template head<3>().maxCoeff() > tol) return false;
  const Lanes e = -(d[0] * m[0] + d[1] * m[1] + d[2] * m[2]);  // from b2's box centre to b1's, b2's frame
  const Lanes gap2 = e.abs() - (m[0].abs() * h1[0] + m[1].abs() * h1[1] + m[2].abs() * h1[2]) - h2;
  if (gap2.template head<3>().maxCoeff() > tol) return false;
  // The diagonals, sqrt(2) times: a box's reach along b1's diagonal (i, j) is sum_c |M_ic +- M_jc| h2_c, along
  // b2's sum_i |M_ic +- M_id| h1_i. b2's slabs are measured from its box centre (MovedFrame), b1's from its frame
  // origin, as centre2. Unused lanes give 0 - 0 - 0, never above the tolerance.
  const float scale = float(M_SQRT1_2);
  Lanes diag[2], radius2[2] = {Lanes::Zero(), Lanes::Zero()}, radius1[2] = {Lanes::Zero(), Lanes::Zero()};
  for (int c = 0; c < 3; ++c)
  {
    diagonalLanes(w[c], diag[0], diag[1]);
    for (int h = 0; h < 2; ++h) radius2[h] += diag[h].abs() * h2[c];
    diagonalLanes(m[c], diag[0], diag[1]);
    for (int h = 0; h < 2; ++h) radius1[h] += diag[h].abs() * h1[c];
  }
  Lanes lo_diagonal[2], hi_diagonal[2], centre_diagonal[2], e_diagonal[2];
  diagonalSlabs(b1, lo_diagonal, hi_diagonal);
  diagonalLanes(centre2, centre_diagonal[0], centre_diagonal[1]);
  diagonalLanes(e, e_diagonal[0], e_diagonal[1]);
  Lanes worst = Lanes::Constant(-std::numeric_limits<float>::max());
  for (int h = 0; h < 2; ++h)
  {
    const Lanes gap_of_b1 = (centre_diagonal[h] - (lo_diagonal[h] + hi_diagonal[h]) * scale).abs() -
                            (hi_diagonal[h] - lo_diagonal[h]) * scale - radius2[h];
    const Lanes gap_of_b2 = (e_diagonal[h] - moved2.diagonal_mid[h]).abs() - moved2.diagonal_half[h] - radius1[h];
    worst = worst.max(gap_of_b1).max(gap_of_b2);
  }
  return !(worst.maxCoeff() > float(M_SQRT2) * tol);
}

/// Whether a triangle, its vertices y in b's frame coordinates, may meet b: its interval along each of b's nine
/// slab directions meets the slab widened by tol. The face axes come first with one exit; the diagonals are
/// compared sqrt(2) times, as in boxedOverlap.
/// Rounding (triangleOverlap's tol is pairRoundingBound of the offsets and reaches named there; u = eps): the test
/// can only go wrong for a triangle that meets b (or comes within the leaf test's tolerance of a triangle in it),
/// and then every vertex lies within the triangle's diameter of a point of b's box, so |y_v|_1 and the vertex's
/// L1 distance from b's frame origin are <= 3 reach_b + 6 reach_leaf <= 6 reaches. A coordinate of y_v is a
/// 3-term dot product of a stored (or moved) axis, entries within 16u of an orthonormal frame as in
/// pairRoundingBound, with the vertex minus the frame origin: <= 19u * 6 reaches from the product and the
/// subtraction, plus sqrt(3) times the moved origin's (or R q + T's) error, 4u per coordinate of the offsets:
/// <= 7u offsets + 114u reaches. The diagonals add two of them and round lo, hi * sqrt(2) (<= 2u reaches): <= 14u
/// offsets + 232u reaches on the sqrt(2) scale. Both fit in the first-order bound pairRoundingBound already
/// carries with its margin (14u offsets + 232u reaches on the face axes, twice that on the diagonals).
template <typename S>
bool triangleMeetsSlabs(const fcl::Vector3<S> y[3], const RS<S>& b, S tol)
{
  const auto gap = [](S v0, S v1, S v2, S lo, S hi) __attribute__((always_inline)) {
    return std::max(std::min(v0, std::min(v1, v2)) - hi, lo - std::max(v0, std::max(v1, v2)));
  };
  S worst = -std::numeric_limits<S>::max();
  for (int i = 0; i < 3; ++i) worst = std::max(worst, gap(y[0][i], y[1][i], y[2][i], b.lo[i], b.hi[i]));
  if (worst > tol) return false;
  const S scale = S(M_SQRT2);
  for (int k = 3; k < kNumSlabs; ++k)
  {
    const SlabDirection& d = kSlabDirections[std::size_t(k)];
    const S sign = S(d.sign);
    worst = std::max(worst, gap(y[0][d.i] + sign * y[0][d.j], y[1][d.i] + sign * y[1][d.j],
                                y[2][d.i] + sign * y[2][d.j], b.lo[k] * scale, b.hi[k] * scale));
  }
  return !(worst > scale * tol);
}

/// A leaf's triangle p (b1's model coordinates; leaf1 is its RS) against b2 moved into them (moved2 =
/// MovedFrame(R, T, b2)): b2's nine slabs only. The triangle lies in leaf1, so on those slabs this is tighter
/// than boxedOverlap(moved2, leaf1); it does not test leaf1's slabs against b2's box. Offsets as PairFrame's
/// (the vertices' own size enters only through their distance from b2, a reach).
template <typename S>
bool triangleOverlap(const fcl::Vector3<S> p[3], const RS<S>& leaf1, const MovedFrame<S>& moved2, const RS<S>& b2)
{
  const fcl::Vector3<S> y[3] = {moved2.axis.transpose() * (p[0] - moved2.origin),
                                moved2.axis.transpose() * (p[1] - moved2.origin),
                                moved2.axis.transpose() * (p[2] - moved2.origin)};
  const S offsets = moved2.offsets + leaf1.origin.template lpNorm<1>();
  return triangleMeetsSlabs(y, b2, pairRoundingBound<S>(offsets, Box<S>(leaf1).reach() + moved2.reach));
}

/// b1 against a leaf's triangle q of b2's model (leaf2 is its RS), mapped into b1's model coordinates by
/// x = R q + T as the leaf test maps it: b1's nine slabs only. world_offsets as MovedFrame's; the offsets count
/// the vertices' L1 size, which R q + T rounds.
template <typename S>
bool triangleOverlap(const RS<S>& b1, const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::Vector3<S> q[3],
                     const RS<S>& leaf2, S world_offsets)
{
  const fcl::Vector3<S> y[3] = {b1.toFrame(R * q[0] + T), b1.toFrame(R * q[1] + T), b1.toFrame(R * q[2] + T)};
  const S largest_q = std::max({q[0].template lpNorm<1>(), q[1].template lpNorm<1>(), q[2].template lpNorm<1>()});
  const S offsets = largest_q + T.template lpNorm<1>() + world_offsets + b1.origin.template lpNorm<1>();
  return triangleMeetsSlabs(y, b1, pairRoundingBound<S>(offsets, Box<S>(b1).reach() + Box<S>(leaf2).reach()));
}

/// The exact overlap tests (OverlapTest::kOneSided, kTwoSided), compiled once per variant.
template <OverlapTest test, typename S>
bool exactOverlap(const MovedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2)
{
  const PairFrame<S> f(moved2, b1);
  const fcl::Matrix3<S>& M = f.M;
  const fcl::Vector3<S>& m2 = f.centre2;
  const fcl::Vector3<S> m1 = f.centre1();
  constexpr bool exact_on_2 = test == OverlapTest::kTwoSided;

  // Pass 1, boxes only: slab k of b1 (k < 9) or of b2 (k >= 9) against the other's principal box
  // projected on it (mid +- radius). Apart means separated. Otherwise the other polytope's interval
  // ends lie within box_excess of the box's, so a side needs an exact support (pass 2) only where
  // the box overlaps the slab by less than that.
  // Queue entries are 2 * slab + side (0: the other volume's low end against hi, 1: its high end
  // against lo), appended without branches: which sides need work is unpredictable.
  std::uint8_t queued[4 * kNumSlabs + 1];
  int num_queued = 0;
  const S excess1 = b2.box_excess, excess2 = exact_on_2 ? b1.box_excess : S(0);
  auto boxApart = [&](int k, S mid, S radius) {
    const bool on_1 = k < kNumSlabs;
    const int j = on_1 ? k : k - kNumSlabs;
    const RS<S>& slabs = on_1 ? b1 : b2;
    const S lo = slabs.lo[j] - f.tol, hi = slabs.hi[j] + f.tol;
    const S low = mid - radius, high = mid + radius, excess = on_1 ? excess1 : excess2;
    queued[num_queued] = std::uint8_t(2 * k);
    num_queued += low + excess > hi;
    queued[num_queued] = std::uint8_t(2 * k + 1);
    num_queued += high - excess < lo;
    return low > hi || high < lo;
  };

  // The six face axes first: most separated pairs are rejected there, as in an OBB test.
  const fcl::Matrix3<S> A = M.cwiseAbs();
  const fcl::Vector3<S> r2 = A * f.box2.h, r1 = A.transpose() * f.box1.h;
  for (int i = 0; i < 3; ++i)
    if (boxApart(i, m2[i], r2[i]) || boxApart(kNumSlabs + i, m1[i], r1[i])) return false;
  for (int k = 3; k < kNumSlabs; ++k)
  {
    const SlabDirection& d = kSlabDirections[k];
    const S sign = S(d.sign), scale = S(M_SQRT1_2);
    const fcl::Vector3<S> e1 = (M.row(d.i) + sign * M.row(d.j)).transpose().cwiseAbs();
    if (boxApart(k, (m2[d.i] + sign * m2[d.j]) * scale, e1.dot(f.box2.h) * scale)) return false;
    const fcl::Vector3<S> e2 = (M.col(d.i) + sign * M.col(d.j)).cwiseAbs();
    if (boxApart(kNumSlabs + k, (m1[d.i] + sign * m1[d.j]) * scale, e2.dot(f.box1.h) * scale)) return false;
  }

  // Pass 2: exact supports of the other polytope on the queued sides (octant trick).
  // With sigma = -1 for a low end and +1 for a high end, the other volume is apart when
  // sigma * shift + support(sigma * e) < sigma * (hi or lo) - tol.
  for (int q = 0; q < num_queued; ++q)
  {
    const int k = queued[q] >> 1, high_end = queued[q] & 1;
    const bool on_1 = k < kNumSlabs;
    const int j = on_1 ? k : k - kNumSlabs;
    const RS<S>& slabs = on_1 ? b1 : b2;
    const RS<S>& other = on_1 ? b2 : b1;
    const S sigma = high_end ? S(1) : S(-1);
    const fcl::Vector3<S> e = sigma * (on_1 ? slabOfRows(M, j) : slabOfColumns(M, j));
    // Projection of the other volume's frame origin on sigma * e.
    const S shift = sigma * projectOnSlab(on_1 ? m2 : m1, j) - e.dot(on_1 ? f.box2.c : f.box1.c);
    const S bound = sigma * (high_end ? slabs.lo[j] : slabs.hi[j]);
    if (shift + other.support(e) < bound - f.tol) return false;
  }
  return true;
}

/// overlap() with b2's frame already moved: moved2 = MovedFrame(R, T, b2).
template <typename S>
bool overlap(const BoxedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2, OverlapTest test)
{
  if (b1.empty() || b2.empty()) return false;
  switch (test)
  {
    case OverlapTest::kOneSided: return exactOverlap<OverlapTest::kOneSided>(moved2, b1, b2);
    case OverlapTest::kBoxed: return boxedOverlap(moved2, b1);
    default: return exactOverlap<OverlapTest::kTwoSided>(moved2, b1, b2);
  }
}

}  // namespace detail

template <typename S>
bool overlap(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2, OverlapTest test,
             S world_offsets)
{
  if (b1.empty() || b2.empty()) return false;
  return detail::overlap(detail::BoxedFrame<S>(R, T, b2, world_offsets), b1, b2, test);
}

template <typename S>
S distance(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
           fcl::Vector3<S>* P, fcl::Vector3<S>* Q)
{
  if (b1.empty() || b2.empty()) return std::numeric_limits<S>::max();
  const detail::PairFrame<S> f(R, T, b1, b2);
  const detail::ProjectedBox<S> on1(f.M, f.centre2, f.box2);              // b2's box on b1's directions
  const detail::ProjectedBox<S> on2(f.M.transpose(), f.centre1(), f.box1);  // b1's box on b2's directions
  S best = -std::numeric_limits<S>::max();
  int best_k = 0;
  for (int k = 0; k < 2 * kNumSlabs; ++k)
  {
    const S gap = k < kNumSlabs ? detail::slabGap<S>(b1.lo[k], b1.hi[k], b2, f.box2, on1, k)
                                : detail::slabGap<S>(b2.lo[k - kNumSlabs], b2.hi[k - kNumSlabs], b1, f.box1, on2,
                                                  k - kNumSlabs);
    if (gap > best) { best = gap; best_k = k; }
  }
  if (P || Q)
  {
    // Extreme points of each volume along the best direction n (b1's frame), facing each other.
    fcl::Vector3<S> n = best_k < kNumSlabs ? detail::slabDirection<S>(best_k)
                                           : detail::slabOfColumns(f.M, best_k - kNumSlabs);
    if (n.dot(f.centre2 - f.box1.c) < 0) n = -n;
    if (P) *P = b1.toModel(detail::extremeVertex(b1, n));
    if (Q) *Q = b2.toModel(detail::extremeVertex(b2, fcl::Vector3<S>(-(f.M.transpose() * n))));
  }
  return std::max(S(0), best - f.tol);
}

template <typename S, typename PointAt>
RS<S> fitPoints(int n, PointAt point_at)
{
  const PrincipalFrame<S> frame = principalFrame<S>(n, point_at);
  RS<S> bv(frame.axis, frame.mean);
  bv.expandPoints(n, point_at);
  return bv;
}

template <typename S>
RS<S> fitPoints(const fcl::Vector3<S>* points, int n)
{
  return fitPoints<S>(n, [points](int i) -> const fcl::Vector3<S>& { return points[i]; });
}

template <typename S>
void fit(const fcl::Vector3<S>* const points, int n, RS<S>& bv)
{
  bv = n > 0 ? fitPoints<S>(points, n) : RS<S>();
}

template <typename S>
RS<S> transform(const RS<S>& bv, const fcl::Transform3<S>& tf)
{
  const fcl::Matrix3<S> axis = tf.linear() * bv.axes();
  RS<S> moved(axis, tf * bv.origin);
  moved.box_excess = bv.box_excess;
  // The moved frame is rounded to storage again: the slabs are padded by what that moves the points by, unless
  // storage holds the moved frame exactly (a rotation by a permutation, the identity), so that placing a volume
  // at the identity leaves it as it is.
  if (bv.empty() || moved.axes() == axis)
  {
    moved.lo = bv.lo;
    moved.hi = bv.hi;
    return moved;
  }
  const S pad = detail::storageBound(bv.magnitude());
  for (int k = 0; k < kNumSlabs; ++k)
  {
    moved.lo[k] = RS<S>::slabBelow(S(bv.lo[k]) - pad);
    moved.hi[k] = RS<S>::slabAbove(S(bv.hi[k]) + pad);
  }
  moved.updateBoxExcess();
  return moved;
}

}  // namespace fcl_rs

#endif
