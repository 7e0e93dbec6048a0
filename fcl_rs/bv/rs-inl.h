// Definitions of RS<S>: growth, merge, Tribox corners, support, volume and fit (the pair tests are in
// fcl_rs/bv/pair_kernel.h).
#ifndef FCL_RS_RS_INL_H
#define FCL_RS_RS_INL_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

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
