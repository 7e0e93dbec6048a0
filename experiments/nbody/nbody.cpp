// N-body simulator: loading and placing bodies, the declared rigid-motion effects, per-frame pair tests.
#include "nbody/nbody.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <numeric>
#include <random>
#include <stdexcept>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/detail/BV_fitter.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/geometry.h>
#include <fcl/narrowphase/collision_object.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/mesh/shapes.h"

namespace fcl_rs {

const char* pairTestName(PairTest test)
{
  switch (test)
  {
    case PairTest::kSphere: return "sphere";
    case PairTest::kAABB: return "aabb";
    case PairTest::kOBB: return "obb";
    case PairTest::kKDOP18: return "kdop18";
    case PairTest::kRS: return "rs";
    case PairTest::kKDOP18Realigned: return "kdop18_realigned";
    case PairTest::kRSOneSided: return "rs_one_sided";
    case PairTest::kExact: return "exact";
  }
  return "?";
}

namespace {

/// Uniform doubles in [0, 1) from the raw 64-bit stream, so a seed gives the same scene with every
/// standard library (std::uniform_real_distribution is implementation-defined).
class Uniform
{
public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  double operator()() { return double(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform on the unit sphere.
  fcl::Vector3d direction()
  {
    const double z = 2 * (*this)() - 1, phi = 2 * M_PI * (*this)(), s = std::sqrt(std::max(0.0, 1 - z * z));
    return fcl::Vector3d(s * std::cos(phi), s * std::sin(phi), z);
  }
  /// Uniform rotation (Shoemake: a uniform unit quaternion).
  fcl::Quaterniond rotation()
  {
    const double u1 = (*this)(), u2 = 2 * M_PI * (*this)(), u3 = 2 * M_PI * (*this)();
    const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
    return fcl::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
  }

private:
  std::mt19937_64 engine_;
};

TriangleMesh<double> generate(const SceneBody& b)
{
  if (b.shape == "sphere") return makePoleQuadSphere<double>(1);
  if (b.shape == "ellipsoid") return makeEllipsoid<double>(b.axes[0], b.axes[1], b.axes[2]);
  if (b.shape == "diamond") return makeDiamond<double>(1, b.height, b.facets);
  if (b.shape == "kdop18") return makeKdop18Solid<double>(b.extents[0], b.extents[1], b.extents[2], b.chamfer);
  throw std::invalid_argument("unknown shape '" + b.shape + "'");
}

/// CPU time of the calling thread: on a shared machine it is far steadier than wall-clock time.
double threadSeconds()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Broadphase callback data: the narrow-phase request and where intersecting pairs go.
template <typename S>
struct ExactQuery
{
  fcl::CollisionRequest<S> request{1, false};
  BodyPairs* pairs = nullptr;
};

/// Broadphase callback: records the candidate pair when the RS trees intersect.
template <typename S>
bool pairCollides(fcl::CollisionObject<S>* o1, fcl::CollisionObject<S>* o2, void* data)
{
  auto* query = static_cast<ExactQuery<S>*>(data);
  fcl::CollisionResult<S> result;
  fcl_rs::collide(o1, o2, query->request, result);
  if (result.isCollision())
  {
    const int a = *static_cast<const int*>(o1->getUserData()), b = *static_cast<const int*>(o2->getUserData());
    query->pairs->emplace_back(std::min(a, b), std::max(a, b));
  }
  return false;  // visit every candidate pair
}

}  // namespace

template <typename S>
struct NBodySimulator<S>::Impl
{
  /// What the copies of one scene body share.
  struct Kind
  {
    std::string name;
    TriangleMesh<S> mesh;
    S radius = 0;
    std::shared_ptr<fcl::BVHModel<RS<S>>> model;
    fcl::OBB<S> obb;
    std::vector<fcl::Vector3<S>> dop_corners;  // the 32 corners of the mesh's 18-DOP in the body frame
  };

  Scene scene;
  std::vector<std::shared_ptr<const Kind>> kind;  // per body
  std::vector<BodyState<S>> state;
  std::vector<int> id;  // user data of the collision objects
  std::vector<std::unique_ptr<fcl::CollisionObject<S>>> objects;
  fcl::DynamicAABBTreeCollisionManager<S> manager;
  int frame = 0;
  int exact_frame = -1;  // frame whose exact pairs are in `exact`
  BodyPairs exact;
  std::vector<fcl::Matrix3<S>> rotation;  // scratch, per body

  static std::shared_ptr<const Kind> makeKind(const Scene& scene, std::size_t index)
  {
    const SceneBody& b = scene.bodies[index];
    const std::string where =
        "fcl_rs scene '" + scene.source + "': bodies[" + std::to_string(index) + "] ('" + b.name + "'): ";
    try
    {
      TriangleMesh<double> m = b.mesh.empty() ? generate(b) : loadMeshFile(b.mesh_path);
      validateMesh(m.vertices, m.triangles);
      // Centre on the bounding-box centre, then scale.
      fcl::Vector3d lo = m.vertices[0], hi = m.vertices[0];
      for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      double r0 = 0;
      for (auto& v : m.vertices) v -= (lo + hi) / 2, r0 = std::max(r0, v.norm());
      if (!(r0 > 0)) throw std::invalid_argument("the mesh has no extent");
      const double factor = b.size > 0 ? b.size / (2 * r0) : b.scale;

      auto k = std::make_shared<Kind>();
      k->name = b.name;
      for (const auto& v : m.vertices) k->mesh.vertices.push_back((v * factor).cast<S>());
      k->mesh.triangles = std::move(m.triangles);
      for (const auto& v : k->mesh.vertices) k->radius = std::max(k->radius, v.norm());
      if (!(2 * double(k->radius) < scene.cube))
        throw std::invalid_argument("its bounding ball (diameter " + std::to_string(2 * double(k->radius)) +
                                    ") does not fit in the cube (side " + std::to_string(scene.cube) + ")");
      k->model = buildModel<RS<S>>(k->mesh);
      // FCL's OBB of the whole mesh, fitted as the root of an FCL OBB tree would be.
      fcl::detail::BVFitter<fcl::OBB<S>> fitter;
      fitter.set(k->model->vertices, k->model->tri_indices, fcl::BVH_MODEL_TRIANGLES);
      std::vector<unsigned int> all(k->mesh.triangles.size());
      std::iota(all.begin(), all.end(), 0u);
      k->obb = fitter.fit(all.data(), int(all.size()));
      RS<S> dop(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero());  // an 18-DOP in the body's axes
      for (const auto& v : k->mesh.vertices) dop += v;
      for (const auto& c : dop.corners()) k->dop_corners.push_back(dop.toModel(c));
      return k;
    }
    catch (const std::exception& e)
    {
      throw std::runtime_error(where + e.what());
    }
  }

  explicit Impl(const Scene& s) : scene(s)
  {
    Uniform uniform(scene.seed);
    const SceneEffects& fx = scene.effects;
    for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    {
      const std::shared_ptr<const Kind> k = makeKind(scene, b);
      for (int c = 0; c < scene.bodies[b].count; ++c)
      {
        // Twelve draws per body whatever the effects, so effects do not change the start.
        const double h = scene.cube / 2 - double(k->radius);
        fcl::Vector3d p;
        for (int a = 0; a < 3; ++a) p[a] = (2 * uniform() - 1) * h;
        const fcl::Quaterniond q = uniform.rotation();
        const double speed = fx.speed_min + uniform() * (fx.speed_max - fx.speed_min);
        const fcl::Vector3d dir = uniform.direction();
        const double rate = fx.rate_min + uniform() * (fx.rate_max - fx.rate_min);
        const fcl::Vector3d axis = uniform.direction();
        BodyState<S> st;
        st.position = p.cast<S>();
        st.orientation = q.cast<S>();
        st.velocity = fx.linear_motion ? fcl::Vector3<S>((speed * dir).cast<S>()) : fcl::Vector3<S>::Zero();
        st.angular_velocity = fx.spin ? fcl::Vector3<S>((rate * axis).cast<S>()) : fcl::Vector3<S>::Zero();
        kind.push_back(k);
        state.push_back(st);
      }
    }
    const int n = int(state.size());
    id.resize(std::size_t(n));
    std::iota(id.begin(), id.end(), 0);
    std::vector<fcl::CollisionObject<S>*> raw;
    for (int i = 0; i < n; ++i)
    {
      objects.push_back(std::make_unique<fcl::CollisionObject<S>>(kind[std::size_t(i)]->model, pose(i)));
      objects.back()->setUserData(&id[std::size_t(i)]);
      raw.push_back(objects.back().get());
    }
    manager.registerObjects(raw);
    manager.setup();
    rotation.resize(std::size_t(n));
  }

  fcl::Transform3<S> pose(int i) const
  {
    const BodyState<S>& st = state[std::size_t(i)];
    fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
    tf.linear() = st.orientation.toRotationMatrix();
    tf.translation() = st.position;
    return tf;
  }

  void updateRotations()
  {
    for (std::size_t i = 0; i < state.size(); ++i) rotation[i] = state[i].orientation.toRotationMatrix();
  }

  /// Bound on the rounding error of body i's world coordinates (and of the relative transforms built
  /// from them), to pad the volume tests.
  S pad(std::size_t i) const
  {
    return 16 * std::numeric_limits<S>::epsilon() * (state[i].position.cwiseAbs().maxCoeff() + kind[i]->radius);
  }

  /// Calls test(i, j) for every pair i < j and collects those it accepts.
  template <typename Test>
  static BodyPairs allPairs(int n, Test test)
  {
    BodyPairs out;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (test(std::size_t(i), std::size_t(j))) out.emplace_back(i, j);
    return out;
  }

  /// Relative transform of body j in body i's frame (x_i = R x_j + T), as FCL's oriented traversal forms it.
  void relative(std::size_t i, std::size_t j, fcl::Matrix3<S>& R, fcl::Vector3<S>& T) const
  {
    fcl::relativeTransform(rotation[i], state[i].position, rotation[j], state[j].position, R, T);
  }

  BodyPairs pairs(PairTest test)
  {
    const int n = int(state.size());
    updateRotations();
    switch (test)
    {
      case PairTest::kSphere:
        return allPairs(n, [&](std::size_t i, std::size_t j) {
          const S reach = kind[i]->radius + kind[j]->radius + pad(i) + pad(j);
          return (state[i].position - state[j].position).squaredNorm() <= reach * reach;
        });
      case PairTest::kAABB:
      {
        std::vector<fcl::AABB<S>> box(state.size());
        for (std::size_t i = 0; i < box.size(); ++i)
        {
          fcl::Vector3<S> lo = fcl::Vector3<S>::Constant(std::numeric_limits<S>::max()), hi = -lo;
          for (const auto& v : kind[i]->mesh.vertices)
          {
            const fcl::Vector3<S> w = rotation[i] * v + state[i].position;
            lo = lo.cwiseMin(w);
            hi = hi.cwiseMax(w);
          }
          box[i] = fcl::AABB<S>(lo - fcl::Vector3<S>::Constant(pad(i)), hi + fcl::Vector3<S>::Constant(pad(i)));
        }
        return allPairs(n, [&](std::size_t i, std::size_t j) { return box[i].overlap(box[j]); });
      }
      case PairTest::kOBB:
        return allPairs(n, [&](std::size_t i, std::size_t j) {
          fcl::Matrix3<S> R;
          fcl::Vector3<S> T;
          relative(i, j, R, T);
          return fcl::overlap(R, T, kind[i]->obb, kind[j]->obb);
        });
      case PairTest::kKDOP18:
      case PairTest::kKDOP18Realigned:
      {
        std::vector<fcl::KDOP<S, 18>> dop(state.size());
        for (std::size_t i = 0; i < dop.size(); ++i)
        {
          const auto& points = test == PairTest::kKDOP18 ? kind[i]->mesh.vertices : kind[i]->dop_corners;
          for (const auto& v : points) dop[i] += rotation[i] * v + state[i].position;
          // Slabs 3..8 are along unnormalised diagonals (x+y, ...): twice the error.
          for (int s = 0; s < 9; ++s)
          {
            const S e = (s < 3 ? 1 : 2) * pad(i);
            dop[i].dist(std::size_t(s)) -= e;
            dop[i].dist(std::size_t(s + 9)) += e;
          }
        }
        return allPairs(n, [&](std::size_t i, std::size_t j) { return dop[i].overlap(dop[j]); });
      }
      case PairTest::kRS:
      case PairTest::kRSOneSided:
      {
        const OverlapTest variant = test == PairTest::kRS ? OverlapTest::kTwoSided : OverlapTest::kOneSided;
        return allPairs(n, [&](std::size_t i, std::size_t j) {
          fcl::Matrix3<S> R;
          fcl::Vector3<S> T;
          relative(i, j, R, T);
          return fcl_rs::overlap(R, T, kind[i]->model->getBV(0).bv, kind[j]->model->getBV(0).bv, variant);
        });
      }
      case PairTest::kExact:
      {
        for (std::size_t i = 0; i < objects.size(); ++i)
        {
          objects[i]->setTransform(rotation[i], state[i].position);
          objects[i]->computeAABB();
        }
        manager.update();
        exact.clear();
        ExactQuery<S> query;
        query.pairs = &exact;
        manager.collide(&query, pairCollides<S>);
        std::sort(exact.begin(), exact.end());
        exact_frame = frame;
        return exact;
      }
    }
    throw std::invalid_argument("fcl_rs::NBodySimulator: unknown pair test");
  }

  void step()
  {
    const SceneEffects& fx = scene.effects;
    const S dt = S(scene.time_step);
    if (fx.collision_response)
    {
      if (exact_frame != frame) pairs(PairTest::kExact);
      for (const auto& [i, j] : exact)
      {
        BodyState<S>&a = state[std::size_t(i)], &b = state[std::size_t(j)];
        const fcl::Vector3<S> line = b.position - a.position;
        if (!(line.squaredNorm() > 0)) continue;
        const fcl::Vector3<S> nrm = line.normalized();
        const S approach = (b.velocity - a.velocity).dot(nrm);
        if (approach >= 0) continue;  // already separating
        a.velocity += approach * nrm;
        b.velocity -= approach * nrm;
      }
    }
    for (std::size_t i = 0; i < state.size(); ++i)
    {
      BodyState<S>& st = state[i];
      const S rate = st.angular_velocity.norm();
      if (rate > 0)
      {
        st.orientation = fcl::Quaternion<S>(Eigen::AngleAxis<S>(rate * dt, st.angular_velocity / rate)) * st.orientation;
        st.orientation.normalize();
      }
      st.position += st.velocity * dt;
      if (fx.wall_bounce)
      {
        const S h = S(scene.cube / 2) - kind[i]->radius;
        for (int a = 0; a < 3; ++a)
          while (std::abs(st.position[a]) > h)
          {
            const S side = st.position[a] > 0 ? h : -h;
            st.position[a] = 2 * side - st.position[a];
            st.velocity[a] = -std::copysign(st.velocity[a], side);
          }
      }
    }
    ++frame;
  }
};

template <typename S>
NBodySimulator<S>::NBodySimulator(const Scene& scene) : impl_(std::make_unique<Impl>(scene))
{
}

template <typename S>
NBodySimulator<S>::~NBodySimulator() = default;

template <typename S>
const Scene& NBodySimulator<S>::scene() const { return impl_->scene; }

template <typename S>
int NBodySimulator<S>::numBodies() const { return int(impl_->state.size()); }

template <typename S>
int NBodySimulator<S>::frame() const { return impl_->frame; }

template <typename S>
const BodyState<S>& NBodySimulator<S>::state(int body) const { return impl_->state.at(std::size_t(body)); }

template <typename S>
fcl::Transform3<S> NBodySimulator<S>::pose(int body) const { return impl_->pose(body); }

template <typename S>
S NBodySimulator<S>::radius(int body) const { return impl_->kind.at(std::size_t(body))->radius; }

template <typename S>
const std::string& NBodySimulator<S>::name(int body) const { return impl_->kind.at(std::size_t(body))->name; }

template <typename S>
const TriangleMesh<S>& NBodySimulator<S>::mesh(int body) const { return impl_->kind.at(std::size_t(body))->mesh; }

template <typename S>
BodyPairs NBodySimulator<S>::pairs(PairTest test) { return impl_->pairs(test); }

template <typename S>
FrameRecord NBodySimulator<S>::record()
{
  FrameRecord r;
  r.frame = impl_->frame;
  for (int t = 0; t < kNumPairTests; ++t)
  {
    const double start = threadSeconds();
    r.count[std::size_t(t)] = int(impl_->pairs(kPairTests[std::size_t(t)]).size());
    r.seconds[std::size_t(t)] = threadSeconds() - start;
  }
  return r;
}

template <typename S>
void NBodySimulator<S>::step() { impl_->step(); }

template class NBodySimulator<float>;
template class NBodySimulator<double>;

SceneSummary summarize(const std::vector<FrameRecord>& records)
{
  SceneSummary s;
  s.frames = int(records.size());
  std::array<double, kNumPairTests> total{};
  for (const FrameRecord& r : records)
    for (std::size_t t = 0; t < std::size_t(kNumPairTests); ++t)
    {
      total[t] += r.count[t];
      s.mean_seconds[t] += r.seconds[t];
    }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double exact = total[std::size_t(PairTest::kExact)];
  for (std::size_t t = 0; t < std::size_t(kNumPairTests); ++t)
  {
    s.mean_count[t] = s.frames ? total[t] / s.frames : nan;
    s.mean_seconds[t] = s.frames ? s.mean_seconds[t] / s.frames : nan;
    s.false_positive_rate[t] = total[t] > 0 ? 1 - exact / total[t] : nan;
  }
  s.rs_fewer_than_obb = -s.percentMore(PairTest::kRS, PairTest::kOBB);
  s.kdop18_more_than_rs = s.percentMore(PairTest::kKDOP18, PairTest::kRS);
  return s;
}

double SceneSummary::percentMore(PairTest a, PairTest b) const
{
  const double mb = mean_count[std::size_t(b)];
  return mb > 0 ? 100 * (mean_count[std::size_t(a)] - mb) / mb : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace fcl_rs
