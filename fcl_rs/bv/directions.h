// The nine slab directions of an RS volume, expressed in the volume's own frame (u0, u1, u2).
#ifndef FCL_RS_DIRECTIONS_H
#define FCL_RS_DIRECTIONS_H

#include <array>
#include <cmath>

namespace fcl_rs {

/// One slab direction: (u_i + sign * u_j) / norm. Principal axes have j == i and norm 1;
/// the six diagonal directions (the frame rotated by 45 degrees about one axis) have norm sqrt(2).
struct SlabDirection
{
  int i;
  int j;
  int sign;
  const char* name;
};

/// The single table used by the code and the docs. Order: 3 principal axes, 3 "plus" diagonals,
/// 3 "minus" diagonals (the paper's list has u2-u1 where u0-u1 belongs; these are the nine distinct slabs).
inline constexpr std::array<SlabDirection, 9> kSlabDirections = {{
    {0, 0, 0, "u0"},      {1, 1, 0, "u1"},      {2, 2, 0, "u2"},
    {0, 1, +1, "u0+u1"},  {0, 2, +1, "u0+u2"},  {1, 2, +1, "u1+u2"},
    {0, 1, -1, "u0-u1"},  {0, 2, -1, "u0-u2"},  {1, 2, -1, "u1-u2"},
}};

inline constexpr int kNumSlabs = 9;

/// Index in kSlabDirections of the diagonal over axes (i, j), i < j, with the given sign.
constexpr int diagonalIndex(int i, int j, int sign)
{
  const int pair = (i == 0) ? (j == 1 ? 0 : 1) : 2;
  return 3 + pair + (sign > 0 ? 0 : 3);
}

/// Projection of frame coordinates y on slab k's unit direction.
template <typename Vec>
inline auto projectOnSlab(const Vec& y, int k) -> typename std::decay<decltype(y[0])>::type
{
  using S = typename std::decay<decltype(y[0])>::type;
  const SlabDirection& d = kSlabDirections[k];
  if (d.sign == 0) return y[d.i];
  return (y[d.i] + S(d.sign) * y[d.j]) * S(M_SQRT1_2);
}

}  // namespace fcl_rs

#endif
