// The descent engine (fcl_rs/traversal/descent.h) on toy trees of 1-D points: depth first reports every pair a
// brute force reports, in FCL's order, and stops when told; best first finds the nearest pair, splitting no pair
// whose bound is above the final distance.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "fcl_rs/traversal/descent.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

/// A complete binary tree over sorted points: node i covers [lo, hi] and has children 2i+1, 2i+2 unless a leaf.
struct Tree
{
  std::vector<double> lo, hi;
  std::vector<int> point;  ///< the point index of a leaf, -1 for an inner node
  std::vector<double> points;

  explicit Tree(std::vector<double> p) : points(std::move(p))
  {
    std::sort(points.begin(), points.end());
    build(0, 0, int(points.size()));
  }
  void build(int node, int begin, int end)
  {
    if (std::size_t(node) >= lo.size())
    {
      lo.resize(std::size_t(node) + 1);
      hi.resize(std::size_t(node) + 1);
      point.resize(std::size_t(node) + 1, -1);
    }
    lo[std::size_t(node)] = points[std::size_t(begin)];
    hi[std::size_t(node)] = points[std::size_t(end - 1)];
    if (end - begin == 1)
    {
      point[std::size_t(node)] = begin;
      return;
    }
    const int mid = (begin + end) / 2;
    build(2 * node + 1, begin, mid);
    build(2 * node + 2, mid, end);
  }
  bool leaf(int n) const { return point[std::size_t(n)] >= 0; }
  double size(int n) const { return hi[std::size_t(n)] - lo[std::size_t(n)]; }
};

struct ToyPolicy
{
  struct Pair
  {
    int a, b;
  };
  struct Visit
  {
    int a, b;
    bool leaf1, leaf2;
  };
  static constexpr int kMaxChildren = 2;

  ToyPolicy(const Tree& a, const Tree& b, double e) : A(a), B(b), eps(e) {}

  const Tree& A;
  const Tree& B;
  double eps;
  std::size_t max_pairs = std::numeric_limits<std::size_t>::max();
  std::vector<std::pair<int, int>> found;
  double best = std::numeric_limits<double>::max();
  int leaf_tests = 0;
  bool record_splits = false;
  std::vector<double> split_bounds;  ///< with record_splits: the bound of every pair split

  Visit visit(const Pair& p) const { return Visit{p.a, p.b, A.leaf(p.a), B.leaf(p.b)}; }
  double size1(const Visit& v) const { return A.size(v.a); }
  double size2(const Visit& v) const { return B.size(v.b); }
  double gap(int a, int b) const
  {
    return std::max({0.0, B.lo[std::size_t(b)] - A.hi[std::size_t(a)], A.lo[std::size_t(a)] - B.hi[std::size_t(b)]});
  }
  int children(const Visit& v, bool first, Pair* out)
  {
    out[0] = first ? Pair{2 * v.a + 1, v.b} : Pair{v.a, 2 * v.b + 1};
    out[1] = first ? Pair{2 * v.a + 2, v.b} : Pair{v.a, 2 * v.b + 2};
    if (record_splits) split_bounds.push_back(gap(v.a, v.b));
    return 2;
  }
  // Depth first.
  bool nodeApart(const Visit& v) const { return gap(v.a, v.b) > eps; }
  bool leafTest(const Visit& v)
  {
    ++leaf_tests;
    const int i = A.point[std::size_t(v.a)], j = B.point[std::size_t(v.b)];
    const double d = std::abs(A.points[std::size_t(i)] - B.points[std::size_t(j)]);
    if (d <= eps) found.emplace_back(i, j);
    best = std::min(best, d);
    return found.size() >= max_pairs;
  }
  // Best first.
  double bound(const Pair& p) const { return gap(p.a, p.b); }
  bool canStop(double bound) const { return bound >= best; }
};

std::vector<double> randomPoints(std::mt19937_64& rng, int n, double offset)
{
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> p;
  for (int i = 0; i < n; ++i) p.push_back(offset + u(rng));
  return p;
}

TEST(Descent, DepthFirstReportsEveryPairInFCLsOrderAndStopsWhenTold)
{
  auto rng = test::seededRng("DescentDepthFirst");
  for (int trial = 0; trial < 50; ++trial)
  {
    const Tree A(randomPoints(rng, 1 + trial % 37, 0)), B(randomPoints(rng, 1 + trial % 23, 0.5));
    const double eps = 0.02;
    ToyPolicy all(A, B, eps);
    detail::descendDepthFirst(all, {0, 0});
    std::set<std::pair<int, int>> brute;
    for (std::size_t i = 0; i < A.points.size(); ++i)
      for (std::size_t j = 0; j < B.points.size(); ++j)
        if (std::abs(A.points[i] - B.points[j]) <= eps) brute.emplace(int(i), int(j));
    const std::set<std::pair<int, int>> reported(all.found.begin(), all.found.end());
    EXPECT_EQ(reported, brute) << "trial " << trial;
    EXPECT_EQ(all.found.size(), brute.size()) << "trial " << trial;  // each pair once
    // FCL's recursion order (first child before second, the larger node split) is lexicographic in the leaves'
    // positions along the split: with sorted points, pairs come in the order the recursion would report them.
    const std::function<void(int, int, std::vector<std::pair<int, int>>&)> recurse =
        [&](int a, int b, std::vector<std::pair<int, int>>& out) {
          if (A.leaf(a) && B.leaf(b))
          {
            const int i = A.point[std::size_t(a)], j = B.point[std::size_t(b)];
            if (std::abs(A.points[std::size_t(i)] - B.points[std::size_t(j)]) <= eps) out.emplace_back(i, j);
            return;
          }
          if (all.gap(a, b) > eps) return;
          if (B.leaf(b) || (!A.leaf(a) && A.size(a) > B.size(b)))
          {
            recurse(2 * a + 1, b, out);
            recurse(2 * a + 2, b, out);
          }
          else
          {
            recurse(a, 2 * b + 1, out);
            recurse(a, 2 * b + 2, out);
          }
        };
    std::vector<std::pair<int, int>> in_order;
    recurse(0, 0, in_order);
    EXPECT_EQ(all.found, in_order) << "trial " << trial;
    if (brute.size() < 2) continue;
    ToyPolicy first(A, B, eps);
    first.max_pairs = 1;
    detail::descendDepthFirst(first, {0, 0});
    ASSERT_EQ(first.found.size(), 1u);
    EXPECT_EQ(first.found.front(), in_order.front());
    EXPECT_LT(first.leaf_tests, all.leaf_tests);
  }
}

TEST(Descent, BestFirstFindsTheNearestPairSplittingOnlyPairsBelowIt)
{
  auto rng = test::seededRng("DescentBestFirst");
  for (int trial = 0; trial < 50; ++trial)
  {
    const Tree A(randomPoints(rng, 1 + trial % 41, 0)), B(randomPoints(rng, 1 + trial % 29, 1.0 + 0.01 * trial));
    ToyPolicy nearest(A, B, 0);
    nearest.record_splits = true;
    detail::descendBestFirst<ToyPolicy, double>(nearest, {0, 0});
    double brute = std::numeric_limits<double>::max();
    for (double a : A.points)
      for (double b : B.points) brute = std::min(brute, std::abs(a - b));
    EXPECT_EQ(nearest.best, brute) << "trial " << trial;
    for (double split : nearest.split_bounds)
      EXPECT_LE(split, nearest.best) << "trial " << trial;
    EXPECT_LT(nearest.leaf_tests, int(A.points.size() * B.points.size()) + 1);
  }
}

}  // namespace
}  // namespace fcl_rs
