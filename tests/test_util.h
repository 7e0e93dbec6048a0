// Shared test helpers: seeded and logged randomness, uniform rotations, meshes, brute-force oracle.
#ifndef FCL_RS_TESTS_TEST_UTIL_H
#define FCL_RS_TESTS_TEST_UTIL_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fcl/math/geometry.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>
#include <gtest/gtest.h>

#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/bvh/refit_model.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/mesh/shapes.h"

namespace fcl_rs {
namespace test {

using Scalars = ::testing::Types<float, double>;

/// A seeded generator; the seed (FCL_RS_TEST_SEED, or a fixed default) is logged so any failure replays.
inline std::mt19937_64 seededRng(const std::string& what)
{
  const char* env = std::getenv("FCL_RS_TEST_SEED");
  const unsigned long long seed = env ? std::strtoull(env, nullptr, 10) : 20261121ULL;
  std::cout << "[seed] " << what << ": FCL_RS_TEST_SEED=" << seed << "\n";
  return std::mt19937_64(seed ^ std::hash<std::string>()(what));
}

/// Uniformly distributed rotation (Shoemake's method: a uniform unit quaternion).
template <typename S, typename Rng>
fcl::Matrix3<S> randomRotation(Rng& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  const double u1 = u(rng), u2 = 2 * M_PI * u(rng), u3 = 2 * M_PI * u(rng);
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                             std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
  return q.toRotationMatrix().cast<S>();
}

/// Rigid transform with a uniform rotation and a translation uniform in [-extent, extent]^3.
template <typename S, typename Rng>
fcl::Transform3<S> randomPose(Rng& rng, S extent)
{
  std::uniform_real_distribution<double> u(-1, 1);
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = randomRotation<S>(rng);
  tf.translation() = fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * extent;
  return tf;
}

/// Radius of the ball about the origin containing every vertex.
template <typename S>
S meshRadius(const TriangleMesh<S>& m)
{
  S r = 0;
  for (const auto& v : m.vertices) r = std::max(r, v.norm());
  return r;
}

using TrianglePairs = std::set<std::pair<int, int>>;

/// Every intersecting triangle pair, with FCL's own local-frame triangle test (x1 = R x2 + T) on every pair
/// whose padded boxes touch. Candidates come from a uniform grid over mesh 2's padded boxes (about one
/// triangle per cell) rather than a loop over all n x m pairs, so the oracle stays affordable on large
/// meshes and under the sanitizers; a box is in every cell it overlaps, so no touching pair is skipped.
template <typename S>
TrianglePairs bruteForcePairs(const TriangleMesh<S>& m1, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& m2,
                              const fcl::Transform3<S>& tf2)
{
  // The same relative transform, rounded the same way, as FCL's oriented traversal setup.
  fcl::Matrix3<S> R;
  fcl::Vector3<S> T;
  fcl::relativeTransform(tf1.linear(), tf1.translation(), tf2.linear(), tf2.translation(), R, T);
  std::vector<fcl::Vector3<S>> moved;
  moved.reserve(m2.vertices.size());
  for (const auto& v : m2.vertices) moved.push_back(R * v + T);
  using Box = std::pair<fcl::Vector3<S>, fcl::Vector3<S>>;
  auto box = [](const fcl::Vector3<S>& a, const fcl::Vector3<S>& b, const fcl::Vector3<S>& c) {
    return Box(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
  };
  S scale = 0;
  for (const auto& v : m1.vertices) scale = std::max(scale, v.cwiseAbs().maxCoeff());
  for (const auto& v : moved) scale = std::max(scale, v.cwiseAbs().maxCoeff());
  const S pad = 64 * std::numeric_limits<S>::epsilon() * (scale + T.cwiseAbs().maxCoeff());
  TrianglePairs pairs;
  if (m1.triangles.empty() || m2.triangles.empty()) return pairs;

  // Mesh 2's boxes grown by pad: box 1 touches one of them exactly when the padded check below passes.
  std::vector<Box> boxes2;
  Eigen::Vector3d grid_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d grid_hi = -grid_lo;
  for (const auto& t : m2.triangles)
  {
    boxes2.push_back(box(moved[t[0]], moved[t[1]], moved[t[2]]));
    grid_lo = grid_lo.cwiseMin((boxes2.back().first.array() - pad).matrix().template cast<double>());
    grid_hi = grid_hi.cwiseMax((boxes2.back().second.array() + pad).matrix().template cast<double>());
  }
  const int cells = std::max(1, int(std::cbrt(double(boxes2.size()))));
  const Eigen::Vector3d cell_size = ((grid_hi - grid_lo) / cells).cwiseMax(std::numeric_limits<double>::min());
  // Cell index range of [lo, hi]: floor is monotone, so overlapping intervals share a cell.
  auto cellRange = [&](const fcl::Vector3<S>& lo, const fcl::Vector3<S>& hi, Eigen::Vector3i& first, Eigen::Vector3i& last) {
    for (int a = 0; a < 3; ++a)
    {
      const auto index = [&](S x) {
        return int(std::clamp(std::floor((double(x) - grid_lo[a]) / cell_size[a]), 0.0, double(cells - 1)));
      };
      first[a] = index(lo[a]);
      last[a] = index(hi[a]);
    }
  };
  auto forCells = [&](const Eigen::Vector3i& first, const Eigen::Vector3i& last, auto visit) {
    for (int x = first[0]; x <= last[0]; ++x)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int z = first[2]; z <= last[2]; ++z) visit((x * cells + y) * cells + z);
  };
  std::vector<std::vector<int>> grid(std::size_t(cells) * cells * cells);
  Eigen::Vector3i first, last;
  for (std::size_t j = 0; j < boxes2.size(); ++j)
  {
    cellRange((boxes2[j].first.array() - pad).matrix(), (boxes2[j].second.array() + pad).matrix(), first, last);
    forCells(first, last, [&](int cell) { grid[cell].push_back(int(j)); });
  }

  std::vector<int> seen_by(boxes2.size(), -1);
  for (std::size_t i = 0; i < m1.triangles.size(); ++i)
  {
    const auto& t1 = m1.triangles[i];
    const Box b1 = box(m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]]);
    cellRange(b1.first, b1.second, first, last);
    forCells(first, last, [&](int cell) {
      for (const int j : grid[cell])
      {
        if (seen_by[j] == int(i)) continue;
        seen_by[j] = int(i);
        const Box& b2 = boxes2[j];
        if (((b1.first.array() - pad) > b2.second.array()).any() || ((b2.first.array() - pad) > b1.second.array()).any())
          continue;
        const auto& t2 = m2.triangles[j];
        if (fcl::detail::Intersect<S>::intersect_Triangle(m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]],
                                                            m2.vertices[t2[0]], m2.vertices[t2[1]], m2.vertices[t2[2]],
                                                            R, T))
          pairs.emplace(int(i), j);
      }
    });
  }
  return pairs;
}

/// The triangle pairs a collision result reports.
template <typename S>
TrianglePairs contactPairs(const fcl::CollisionResult<S>& result)
{
  TrianglePairs pairs;
  for (std::size_t i = 0; i < result.numContacts(); ++i)
    pairs.emplace(result.getContact(i).b1, result.getContact(i).b2);
  return pairs;
}

/// Path under ../shared/data, or empty when that folder is absent.
inline std::string sharedData(const std::string& relative)
{
  const std::filesystem::path p = std::filesystem::path(FCL_RS_SHARED_DATA_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// Path of a Debian assimp-testmodels file, or empty when the package is not installed.
inline std::string assimpModel(const std::string& relative)
{
  const std::filesystem::path p = std::filesystem::path(FCL_RS_ASSIMP_MODELS_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

}  // namespace test
}  // namespace fcl_rs

#endif
