// The one descent of every tree-pair traversal (mesh-mesh and mesh-shape collision and distance, mesh-octree):
// an explicit stack (or heap) of node pairs, FCL's split rule, early exit. What differs between traversals is a
// policy: the node test, the leaf test, the children of a split node in the order they are visited, the stop rule.
#ifndef FCL_RS_DESCENT_H
#define FCL_RS_DESCENT_H

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace fcl_rs {
namespace detail {

/// Settings of a best-first descent.
struct DescentConfig
{
  /// Pairs the heap holds before it first grows: most queries never grow it.
  std::size_t reserve = 128;
};

}  // namespace detail

/// Requests for at most this many contacts descend into the nearer child first (collideTrees, the octree).
constexpr std::size_t kNearerFirstMaxContacts = 16;

namespace detail {

/// Whether a collision request visits the nearer children first: it stops after a few contacts and asks no cost
/// (an exhaustive request visits every overlapping pair in any order, and ordering would only cost it).
template <typename Request>
bool visitsNearerFirst(const Request& request)
{
  return !request.enable_cost && request.num_max_contacts <= kNearerFirstMaxContacts;
}

/// FCL's split rule (firstOverSecond): the first tree's node is split unless it is a leaf, or the second's is
/// larger (and not a leaf). Sizes are asked only when both nodes are inner ones.
template <typename Policy>
bool splitsFirst(const Policy& policy, const typename Policy::Visit& v)
{
  return v.leaf2 || (!v.leaf1 && policy.size1(v) > policy.size2(v));
}

/// A policy supplies, for its pair type Pair (one node of each tree) and Visit (what the descent and the tests read
/// of a visited pair, at least the bools leaf1 and leaf2):
///   Visit visit(const Pair&)                   the pair's nodes;
///   S size1(const Visit&), size2(const Visit&)  the split rule's node sizes (inner nodes only);
///   int children(const Visit&, bool first, Pair* out)
///                                              the pairs of the split node's children (of the first tree's node
///                                              when `first`) with the other node, in the order to visit them;
///                                              at most kMaxChildren, at least one (depth first: none prunes
///                                              the pair);
/// and, depth first:
///   bool leafTest(const Visit&)                the test of two leaves; true when the query is done (stop rule);
///   bool nodeApart(const Visit&)               the node test of a pair with an inner node: true prunes the pair;
/// or, best first:
///   S bound(const Pair&)                       a lower bound on what the pair can still give (distance);
///   bool canStop(S bound)                      whether a pair of that bound cannot improve the result;
///   void leafTest(const Visit&)                the test of a pair of two leaves the descent reaches.

/// A stack whose first N entries live in the object itself, the rest on the heap: a small query's descent never
/// reaches the allocator (a deep one spills).
template <typename T, std::size_t N>
class SmallStack
{
public:
  bool empty() const { return size_ == 0; }
  void push(const T& x)
  {
    if (size_ < N)
      local_[size_] = x;
    else
      spill_.push_back(x);
    ++size_;
  }
  T pop()
  {
    if (--size_ < N) return local_[size_];
    const T x = spill_.back();
    spill_.pop_back();
    return x;
  }

private:
  T local_[N];
  std::vector<T> spill_;  // entries N and up
  std::size_t size_ = 0;
};

/// Depth first from `root`: a visited pair of leaves goes to the leaf test, any other pair to the node test, and
/// an overlapping pair goes on at once with its first child pair, stacking the others (a pair split goes on
/// without a stack round trip). Stops when the leaf test says so or nothing is left.
template <typename Policy>
void descendDepthFirst(Policy& policy, typename Policy::Pair root)
{
  using Pair = typename Policy::Pair;
  SmallStack<Pair, 64> stack;  // the later children of the pairs split so far
  Pair pair = root;
  for (;;)
  {
    const typename Policy::Visit v = policy.visit(pair);
    bool descend = false;
    if (v.leaf1 && v.leaf2)
    {
      if (policy.leafTest(v)) return;
    }
    else
      descend = !policy.nodeApart(v);
    if (descend)
    {
      Pair children[Policy::kMaxChildren];
      const int n = policy.children(v, splitsFirst(policy, v), children);
      for (int i = n - 1; i > 0; --i) stack.push(children[i]);
      if (n > 0)
      {
        pair = children[0];
        continue;
      }
    }
    if (stack.empty()) return;
    pair = stack.pop();
  }
}

/// Best first from `root`, for distance: the pair with the smallest bound is split next, every child pair is
/// bounded when its parent is split, and the search ends when the smallest bound left cannot improve the result,
/// so that every pair split has a bound below the final distance. Depth first (FCL's ordered descent) splits
/// every pair whose bound is below the distance found when it reaches it, which in the subtrees searched first is
/// still far above the final one; best first shares depth first's split rule and children and differs only in
/// what is visited next. The nearest child goes on at once when no waiting pair is nearer, which spares most heap
/// operations. A policy may settle a child pair in bound() (two leaves measured at once: return a bound that
/// canStop) so that it is never visited.
template <typename Policy, typename S>
void descendBestFirst(Policy& policy, typename Policy::Pair root, const DescentConfig& config = {})
{
  using Pair = typename Policy::Pair;
  struct Waiting
  {
    Pair pair;
    S bound;
  };
  std::vector<Waiting> waiting;  // a min-heap on bound; ties pop in no particular order
  waiting.reserve(config.reserve);
  const auto farther = [](const Waiting& x, const Waiting& y) { return x.bound > y.bound; };
  const auto wait = [&](const Waiting& w) {
    if (policy.canStop(w.bound)) return;
    waiting.push_back(w);
    std::push_heap(waiting.begin(), waiting.end(), farther);
  };
  Pair pair = root;
  for (;;)
  {
    const typename Policy::Visit v = policy.visit(pair);
    if (v.leaf1 && v.leaf2)
      policy.leafTest(v);
    else
    {
      Pair children[Policy::kMaxChildren];
      const int n = policy.children(v, splitsFirst(policy, v), children);
      // The nearest child so far is kept, the others wait (ties keep the first).
      Waiting next{children[0], policy.bound(children[0])};
      for (int i = 1; i < n; ++i)
      {
        Waiting other{children[i], policy.bound(children[i])};
        if (other.bound < next.bound) std::swap(other, next);
        wait(other);
      }
      if (!policy.canStop(next.bound) && (waiting.empty() || !(waiting.front().bound < next.bound)))
      {
        pair = next.pair;
        continue;
      }
      wait(next);
    }
    // The nearest waiting pair; if it cannot improve the result, no pair left can.
    if (waiting.empty()) return;
    std::pop_heap(waiting.begin(), waiting.end(), farther);
    const Waiting w = waiting.back();
    waiting.pop_back();
    if (policy.canStop(w.bound)) return;
    pair = w.pair;
  }
}

}  // namespace detail
}  // namespace fcl_rs

#endif
