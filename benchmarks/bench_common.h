// Pieces shared by the benchmark programs: machine description, random poses, timing, progress, output.
#ifndef FCL_RS_BENCHMARKS_BENCH_COMMON_H
#define FCL_RS_BENCHMARKS_BENCH_COMMON_H

#include <fcl_rs/fcl_rs.h>

#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace fcl_rs {
namespace bench {

using S = double;
using Mesh = TriangleMesh<S>;
using Clock = std::chrono::steady_clock;
using fcl::Transform3d;
using fcl::Vector3d;

// ---------------------------------------------------------------------------------------------------
// Machine description

/// Like nproc: the CPUs this process may run on.
inline int onlineCpus()
{
  cpu_set_t set;
  return sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : int(std::thread::hardware_concurrency());
}

inline std::string cpuModel()
{
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0)
    {
      const auto colon = line.find(':');
      return colon == std::string::npos ? line : line.substr(colon + 2);
    }
  return "unknown";
}

inline std::string baseName(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

inline bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

/// Two meshes queried against each other, named "a x b".
struct MeshPair
{
  std::string name;
  Mesh a, b;
};

/// fcl_rs_compare's default pairs (also fcl_rs_bench_distance --compare-pairs): three generated pairs, three of
/// assimp's test models and FCL's env x rob; pairs whose files are missing are skipped with a note.
inline std::vector<MeshPair> comparePairs(const std::string& assimp_models_dir, const std::string& shared_data_dir)
{
  std::vector<MeshPair> pairs;
  pairs.push_back({"sphere x torus", makeSphere<S>(1.0), makeTorus<S>(1.0, 0.35, 48, 24)});
  pairs.push_back({"ellipsoid x ellipsoid", makeEllipsoid<S>(2.0, 1.0, 0.2, 25, 48), makeEllipsoid<S>(1.5, 0.3, 0.3)});
  pairs.push_back({"diamond x box", makeDiamond<S>(1.0, 1.2, 24), makeBox<S>(1.5, 0.4, 0.2)});
  const std::string& assimp = assimp_models_dir;
  const std::string data = shared_data_dir + "/models";
  const struct { std::string a, b; } files[] = {
      {assimp + "/STL/Spider_binary.stl", assimp + "/STL/Spider_binary.stl"},
      {assimp + "/OFF/Wuson.off", assimp + "/PLY/Wuson.ply"},
      {assimp + "/Collada/duck.dae", assimp + "/Collada/teapots.DAE"},
      {data + "/fcl_env.obj", data + "/fcl_rob.obj"},
  };
  for (const auto& f : files)
  {
    if (!fileExists(f.a) || !fileExists(f.b))
    {
      std::printf("note: skipping %s x %s (not found; README.md, 'Data')\n", f.a.c_str(), f.b.c_str());
      continue;
    }
    pairs.push_back({baseName(f.a) + " x " + baseName(f.b), loadMesh<S>(f.a), loadMesh<S>(f.b)});
  }
  return pairs;
}

/// The RS overlap tests the benchmarks measure and their names in tables (extend when OverlapTest grows).
inline const std::vector<std::pair<OverlapTest, std::string>> kOverlapTests = {
    {OverlapTest::kTwoSided, "two-sided"}, {OverlapTest::kOneSided, "one-sided"}, {OverlapTest::kBoxed, "boxed"}};

// ---------------------------------------------------------------------------------------------------
// Random poses

class Random
{
public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// 53 random bits, so the sequence does not depend on the standard library's distributions.
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }

private:
  std::mt19937_64 engine_;
};

/// Shoemake, "Uniform random rotations", Graphics Gems III.
inline fcl::Matrix3d randomRotation(Random& rng)
{
  const double u1 = rng.uniform(), u2 = 2 * M_PI * rng.uniform(), u3 = 2 * M_PI * rng.uniform();
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return fcl::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3)).toRotationMatrix();
}

inline Vector3d randomInUnitBall(Random& rng)
{
  for (;;)
  {
    const Vector3d p(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    if (p.squaredNorm() <= 1) return p;
  }
}

struct Sphere
{
  Vector3d center;
  double radius;
};

/// Centre of the bounding box and the radius of the ball around it holding every vertex.
inline Sphere boundingSphere(const Mesh& m)
{
  Vector3d lo = m.vertices.front(), hi = lo;
  for (const auto& v : m.vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  Sphere s{(lo + hi) / 2, 0};
  for (const auto& v : m.vertices) s.radius = std::max(s.radius, (v - s.center).norm());
  return s;
}

struct PoseSample
{
  fcl::Matrix3d r1, r2;
  Vector3d offset;  ///< in the unit ball
};

struct Pose
{
  Transform3d tf1, tf2;
};

inline std::vector<PoseSample> samplePoses(std::size_t n, std::uint64_t seed)
{
  Random rng(seed);
  std::vector<PoseSample> samples(n);
  for (auto& s : samples)
  {
    s.r1 = randomRotation(rng);
    s.r2 = randomRotation(rng);
    s.offset = randomInUnitBall(rng);
  }
  return samples;
}

/// Mesh a's centre at the origin, mesh b's centre at scale * (ra + rb) * offset.
inline std::vector<Pose> posesAt(const std::vector<PoseSample>& samples, const Sphere& sa, const Sphere& sb,
                                 double scale)
{
  std::vector<Pose> poses(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    const PoseSample& s = samples[i];
    Pose& p = poses[i];
    p.tf1.setIdentity();
    p.tf1.linear() = s.r1;
    p.tf1.translation() = -(s.r1 * sa.center);
    p.tf2.setIdentity();
    p.tf2.linear() = s.r2;
    p.tf2.translation() = scale * (sa.radius + sb.radius) * s.offset - s.r2 * sb.center;
  }
  return poses;
}

inline fcl::CollisionRequest<S> exhaustiveRequest()
{
  return fcl::CollisionRequest<S>(std::numeric_limits<std::size_t>::max(), false);
}

inline fcl::CollisionRequest<S> firstContactRequest() { return fcl::CollisionRequest<S>(1, false); }

/// Translation scale giving about target_share colliding poses among the first `head` samples (with
/// RS trees and the default overlap test). The share is not monotone in the scale (hollow or sparse
/// meshes such as FCL's env are free near their centre), so the scan runs from far to near and
/// refines the first crossing by bisection.
inline double calibrateScale(const fcl::BVHModel<RSd>& ma, const fcl::BVHModel<RSd>& mb,
                             const std::vector<PoseSample>& samples, const Sphere& sa, const Sphere& sb,
                             double target_share, std::size_t head)
{
  const std::vector<PoseSample> first(samples.begin(), samples.begin() + std::ptrdiff_t(std::min(head, samples.size())));
  const auto share = [&](double scale) {
    int hits = 0;
    for (const Pose& p : posesAt(first, sa, sb, scale))
    {
      fcl::CollisionResult<S> result;
      collideWithStats(ma, p.tf1, mb, p.tf2, firstContactRequest(), result);
      hits += result.isCollision();
    }
    return double(hits) / double(first.size());
  };
  constexpr int kSteps = 20;
  constexpr double kFar = 2.0;
  double far = kFar, best_scale = kFar, best_share = share(kFar);
  if (best_share >= target_share) return kFar;
  for (int step = kSteps - 1; step >= 0; --step)
  {
    double near = kFar * step / kSteps;
    const double s = share(near);
    if (s >= target_share)
    {
      for (int i = 0; i < 8; ++i)
      {
        const double mid = (near + far) / 2;
        (share(mid) >= target_share ? near : far) = mid;
      }
      return near;
    }
    if (s > best_share)
    {
      best_share = s;
      best_scale = near;
    }
    far = near;
  }
  return best_scale;
}

// ---------------------------------------------------------------------------------------------------
// Queries

inline std::vector<Vector3d> transformedVertices(const Mesh& m, const Transform3d& tf)
{
  std::vector<Vector3d> out(m.vertices.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = tf * m.vertices[i];
  return out;
}

/// Traversal of two world-frame trees (identity transforms: FCL's initialize then leaves them alone).
template <typename BV>
QueryStats collideWorldTrees(fcl::BVHModel<BV>& wa, fcl::BVHModel<BV>& wb, const fcl::CollisionRequest<S>& request,
                             fcl::CollisionResult<S>& result)
{
  Transform3d i1 = Transform3d::Identity(), i2 = Transform3d::Identity();
  fcl::detail::MeshCollisionTraversalNode<BV> node;
  fcl::detail::initialize(node, wa, i1, wb, i2, request, result);
  node.enable_statistics = true;
  fcl::detail::collide(&node);
  return {node.num_bv_tests, node.num_leaf_tests, node.num_bv_tests};  // FCL's recursion tests every pair it reaches
}

// ---------------------------------------------------------------------------------------------------
// Timing

/// What a timed pass is measured with: wall time (steady_clock), or the CPU time of the calling thread,
/// which leaves out the time other processes hold the CPU (far steadier on a shared machine; it still
/// counts the cache misses they cause).
enum class TimeSource
{
  kWall,
  kThreadCpu,
};

inline double seconds(TimeSource source)
{
  if (source == TimeSource::kThreadCpu)
  {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
  }
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

/// Shortest duration of one call of pass() over repeated calls: at least min_passes of them, and more
/// until min_seconds have elapsed. The minimum is the measure least disturbed by other load.
inline double bestSeconds(const std::function<void()>& pass, double min_seconds, int min_passes,
                          TimeSource source = TimeSource::kWall)
{
  double best = std::numeric_limits<double>::max(), total = 0;
  for (int passes = 0; passes < min_passes || total < min_seconds; ++passes)
  {
    const double start = seconds(source);
    pass();
    const double t = seconds(source) - start;
    best = std::min(best, t);
    total += t;
  }
  return best;
}

/// Sink for query results, so that no timed call can be dropped as unused.
inline volatile std::size_t g_sink = 0;

/// One status line on stderr: rewritten in place on a terminal, one line per item otherwise.
class Progress
{
public:
  explicit Progress(std::size_t num_items) : num_items_(num_items), tty_(isatty(STDERR_FILENO)) {}
  void item(std::size_t index, const std::string& name)
  {
    index_ = index;
    name_ = name;
    if (!tty_) std::fprintf(stderr, "[%zu/%zu] %s\n", index_ + 1, num_items_, name_.c_str());
  }
  void stage(const std::string& what)
  {
    if (tty_) std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s", index_ + 1, num_items_, name_.c_str(), what.c_str());
  }
  void done()
  {
    if (tty_) std::fprintf(stderr, "\r\033[K");
  }

private:
  std::size_t num_items_, index_ = 0;
  std::string name_;
  bool tty_;
};

// ---------------------------------------------------------------------------------------------------
// Output

inline std::string fixed(double x, int decimals)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  return buf;
}

/// Three significant digits or so, for times spanning 1 µs to 10 ms.
inline std::string timeText(double us) { return fixed(us, us < 10 ? 2 : us < 100 ? 1 : 0); }

inline double median(std::vector<double> v)
{
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

/// NaN when the reference is 0 (e.g. no triangle tests at all); printed as "-" and left out of medians.
inline double ratio(double a, double b) { return b > 0 ? a / b : std::numeric_limits<double>::quiet_NaN(); }

inline std::string ratioText(double r) { return std::isnan(r) ? "-" : fixed(r, 3); }

}  // namespace bench
}  // namespace fcl_rs

#endif
