// N-body experiment (paper section 5): rigid motion of a scene's bodies, and per frame the body pairs each
// bounding-volume type reports next to the pairs whose meshes really intersect.
#ifndef FCL_RS_NBODY_H
#define FCL_RS_NBODY_H

#include <array>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/mesh/triangle_mesh.h"
#include "nbody/scene.h"

namespace fcl_rs {

/// What decides that two bodies "collide": the root volumes of one bounding-volume type, or the meshes.
enum class PairTest
{
  kSphere,  ///< bounding balls about the bodies' centres
  kAABB,    ///< world-axis boxes refitted to the moved meshes' vertices
  kOBB,     ///< FCL's OBB (PCA of the triangles' vertices), moved with the body
  kKDOP18,  ///< FCL's KDOP<S, 18> refitted to the moved meshes' vertices (as the paper does)
  kRS,      ///< the RS tree's root, moved with the body, fcl_rs::overlap (two-sided test)
  /// Variants that bracket how the paper may have done it:
  kKDOP18Realigned,  ///< KDOP18 of the moved corners of the body's own 18-DOP (O(1) per frame, looser)
  kRSOneSided,       ///< the RS root with the paper's one-sided overlap test (OverlapTest::kOneSided)
  kExact,  ///< the meshes intersect: FCL's dynamic AABB tree broadphase, then fcl_rs::collide on RS trees
};
constexpr int kNumPairTests = 8;
/// Every test, in enum order (the index of a test is its enum value; kExact is last).
constexpr std::array<PairTest, kNumPairTests> kPairTests{
    {PairTest::kSphere, PairTest::kAABB, PairTest::kOBB, PairTest::kKDOP18, PairTest::kRS, PairTest::kKDOP18Realigned,
     PairTest::kRSOneSided, PairTest::kExact}};
/// "sphere", "aabb", "obb", "kdop18", "rs", "kdop18_realigned", "rs_one_sided", "exact".
const char* pairTestName(PairTest test);

/// Body pairs (i, j), i < j, in increasing order.
using BodyPairs = std::vector<std::pair<int, int>>;

template <typename S>
struct BodyState
{
  fcl::Vector3<S> position;  ///< the body's centre (its bounding-box centre) in the world
  fcl::Quaternion<S> orientation;
  fcl::Vector3<S> velocity;          ///< zero unless the scene declares linear motion
  fcl::Vector3<S> angular_velocity;  ///< world frame; zero unless the scene declares spin
};

/// How many pairs each test reported in one frame, and the CPU time it took (including refits).
struct FrameRecord
{
  int frame = 0;
  std::array<int, kNumPairTests> count{};
  std::array<double, kNumPairTests> seconds{};
};

template <typename S>
class NBodySimulator
{
public:
  /// Loads or generates every body, builds its RS tree and root volumes, and places the bodies with the
  /// scene's seed: uniform positions with the bounding ball inside the cube, uniform orientations, and
  /// random velocities and spins for the declared effects only (the random draws do not depend on the
  /// effects, so one seed gives the same start in every variant). Mesh files are read from mesh_path
  /// (see loadScene); errors name the scene and the body.
  explicit NBodySimulator(const Scene& scene);
  ~NBodySimulator();
  NBodySimulator(const NBodySimulator&) = delete;
  NBodySimulator& operator=(const NBodySimulator&) = delete;

  const Scene& scene() const;
  int numBodies() const;
  /// Time steps taken so far.
  int frame() const;
  const BodyState<S>& state(int body) const;
  fcl::Transform3<S> pose(int body) const;
  /// Radius of the bounding ball about the body's centre.
  S radius(int body) const;
  const std::string& name(int body) const;
  /// The body's mesh in its own frame (centred and scaled); the copies of one scene body share it.
  const TriangleMesh<S>& mesh(int body) const;

  /// The pairs the test reports at the current poses. Volume tests are padded by the rounding error of
  /// the pose, so a pair whose meshes touch is never reported apart.
  BodyPairs pairs(PairTest test);
  /// Every test once, in kPairTests order, timed by the calling thread's CPU clock.
  FrameRecord record();
  /// Advances one time step applying exactly the declared effects: linear motion, spin about the centre,
  /// wall bounce of the bounding ball, and collision response on the current frame's exact pairs.
  void step();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

extern template class NBodySimulator<float>;
extern template class NBodySimulator<double>;

/// Averages over the frames of a run.
struct SceneSummary
{
  int frames = 0;
  std::array<double, kNumPairTests> mean_count{};    ///< pairs per frame
  std::array<double, kNumPairTests> mean_seconds{};  ///< time per frame
  /// Share of reported pairs whose meshes do not intersect: 1 - sum(exact) / sum(test) (NaN: none reported).
  std::array<double, kNumPairTests> false_positive_rate{};
  double rs_fewer_than_obb = std::numeric_limits<double>::quiet_NaN();    ///< -percentMore(kRS, kOBB)
  double kdop18_more_than_rs = std::numeric_limits<double>::quiet_NaN();  ///< percentMore(kKDOP18, kRS)

  /// 100 (a - b) / b over the run's totals (NaN when b never reported a pair).
  double percentMore(PairTest a, PairTest b) const;
};

SceneSummary summarize(const std::vector<FrameRecord>& records);

}  // namespace fcl_rs

#endif
