// Four float lanes for the boxed overlap test: Eigen's Array4f (SSE, NEON) plus the two lane moves it lacks.
#ifndef FCL_RS_LANES_H
#define FCL_RS_LANES_H

#include <Eigen/Core>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fcl_rs {
namespace detail {

/// A 3-vector (or six values in two) in four float lanes; unused lanes hold 0 unless said.
using Lanes = Eigen::Array4f;

/// (v[a], v[b], v[c], v[d]).
template <int a, int b, int c, int d>
inline Lanes shuffle(const Lanes& v)
{
#if defined(__SSE2__)
  Lanes out;
  const __m128 x = _mm_load_ps(v.data());
  _mm_store_ps(out.data(), _mm_shuffle_ps(x, x, _MM_SHUFFLE(d, c, b, a)));
  return out;
#else
  return Lanes(v[a], v[b], v[c], v[d]);
#endif
}

/// The first three lanes of x, y and z as columns: out[i] = (x[i], y[i], z[i], 0) for i < 3.
inline void transpose3(const Lanes& x, const Lanes& y, const Lanes& z, Lanes out[3])
{
#if defined(__SSE2__)
  __m128 r0 = _mm_load_ps(x.data()), r1 = _mm_load_ps(y.data()), r2 = _mm_load_ps(z.data()), r3 = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  _mm_store_ps(out[0].data(), r0);
  _mm_store_ps(out[1].data(), r1);
  _mm_store_ps(out[2].data(), r2);
#else
  for (int i = 0; i < 3; ++i) out[i] = Lanes(x[i], y[i], z[i], 0.0f);
#endif
}

/// sqrt(2) times the projections of frame coordinates v (the first three lanes) on the six diagonal slab
/// directions, in kSlabDirections' order, in two Lanes: (v0 + v1, v0 + v2, v1 + v2, v0 - v1), (v0 - v2, v1 - v2, 0, 0).
inline void diagonalLanes(const Lanes& v, Lanes& first, Lanes& second)
{
  const Lanes sign(1.0f, 1.0f, 1.0f, -1.0f);  // exact: a sign flip
  first = shuffle<0, 0, 1, 0>(v) + shuffle<1, 2, 2, 1>(v) * sign;
  second = shuffle<0, 1, 0, 0>(v) - shuffle<2, 2, 0, 0>(v);
}

}  // namespace detail
}  // namespace fcl_rs

#endif
