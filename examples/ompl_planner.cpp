// OMPL's RRTConnect planning with fcl_rs: the Environment as OMPL's state validity checker and its exact motion
// check as OMPL's motion validator.
//
//   fcl_rs_ompl_planner ROBOT.urdf ROBOT.srdf                 one seeded query on a table-and-shelf scene, with the
//                                                            path re-checked segment by segment
//   fcl_rs_ompl_planner ROBOT.urdf ROBOT.srdf --group NAME [--rest STATE]  the same, planned in the SRDF group's
//                                                            joints, the others at the default configuration (or
//                                                            at the SRDF's group state STATE)
//   fcl_rs_ompl_planner ROBOT.urdf ROBOT.srdf --motions N [STEP]  exact motion checks against discrete ones at
//                                                            0.01 rad on N seeded segments
//   fcl_rs_ompl_planner ROBOT.urdf ROBOT.srdf --benchmark N [BUDGET] [--validator discrete|exact] [--bv RS,OBB,...]
//                       [--clutter K]                      N seeded queries per BV type and motion validator,
//                                                            each BV type in its own process (same OMPL seed), the
//                                                            searches asserted identical, times compared; the
//                                                            state checks replayed for the self and world parts;
//                                                            K small boxes out of the robot's reach added
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <ctime>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fcl/config.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#endif
#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "fcl_rs/mesh/shapes.h"
#include "fcl_rs/mesh/surface_octree.h"
#include "fcl_rs/robot.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;
using fcl_rs::Environment;

namespace {

double threadSeconds()
{
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

Eigen::Map<const Eigen::VectorXd> toVector(const ob::State* state, int dof)
{
  return {state->as<ob::RealVectorStateSpace::StateType>()->values, dof};
}

/// What OMPL plans in: every variable of the robot, or those of an SRDF planning group with the others held where
/// `rest` (a whole configuration) puts them.
struct PlanningSpace
{
  const fcl_rs::PlanningGroup* group = nullptr;
  Eigen::VectorXd rest;

  int dimension() const { return group ? int(group->variables.size()) : int(rest.size()); }
  /// The configuration variable of the space's i-th coordinate.
  int variable(int i) const { return group ? group->variables[std::size_t(i)] : i; }
  /// The robot's configuration at an OMPL state.
  void configuration(const ob::State* state, Eigen::VectorXd& q) const
  {
    if (group)
      q = group->expand(Eigen::VectorXd(toVector(state, dimension())), rest);
    else
      q = toVector(state, dimension());
  }
};

/// Number of calls of one kind of check and, when `timed`, their time (two clock reads per call, which a planner
/// does not pay: the planning time is measured in a run without them).
struct Tally
{
  bool timed = false;
  long calls = 0;
  double seconds = 0;
};

/// A state is valid when the robot touches neither itself nor an obstacle. Appends every checked state to
/// `checked` when given (the benchmark replays them).
class ValidityChecker : public ob::StateValidityChecker
{
public:
  ValidityChecker(const ob::SpaceInformationPtr& si, const Environment<double>& env, const PlanningSpace& space,
                  Tally& tally, std::vector<Eigen::VectorXd>* checked)
    : ob::StateValidityChecker(si), env_(env), space_(space), tally_(tally), checked_(checked)
  {
  }
  bool isValid(const ob::State* state) const override
  {
    // Per thread and reused: a planner checks millions of states, and an allocation per check is not free.
    static thread_local Eigen::VectorXd q;
    space_.configuration(state, q);
    const double start = tally_.timed ? threadSeconds() : 0;
    const bool valid = !env_.query(q).colliding;
    if (tally_.timed) tally_.seconds += threadSeconds() - start;
    ++tally_.calls;
    if (checked_) checked_->push_back(q);
    return valid;
  }

private:
  const Environment<double>& env_;
  const PlanningSpace& space_;
  Tally& tally_;
  std::vector<Eigen::VectorXd>* checked_;
};

/// Every configuration of the straight segment is checked (Environment::checkMotion), not samples of it.
class ExactMotionValidator : public ob::MotionValidator
{
public:
  ExactMotionValidator(const ob::SpaceInformationPtr& si, const Environment<double>& env, const PlanningSpace& space)
    : ob::MotionValidator(si), env_(env), space_(space)
  {
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2) const override
  {
    fcl_rs::MotionRequest<double> request;
    request.earliest = false;  // a yes-or-no question: stop at any colliding configuration
    return record(env_.checkMotion(end(s1, 0), end(s2, 1), request)).colliding == false;
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override
  {
    const fcl_rs::MotionResult<double> r = record(env_.checkMotion(end(s1, 0), end(s2, 1)));
    if (r.colliding)
    {
      last_valid.second = r.free_until;
      if (last_valid.first) si_->getStateSpace()->interpolate(s1, s2, r.free_until, last_valid.first);
    }
    return !r.colliding;
  }

private:
  /// The segment's end `which` (0 or 1) as a configuration, per thread and reused.
  const Eigen::VectorXd& end(const ob::State* state, int which) const
  {
    static thread_local Eigen::VectorXd q[2];
    space_.configuration(state, q[which]);
    return q[which];
  }
  const fcl_rs::MotionResult<double>& record(const fcl_rs::MotionResult<double>& r) const
  {
    (r.colliding ? invalid_ : valid_)++;
    return r;
  }
  const Environment<double>& env_;
  const PlanningSpace& space_;
};

/// Times any motion validator (OMPL's discrete one included: its state checks count in both tallies).
class TimedMotionValidator : public ob::MotionValidator
{
public:
  TimedMotionValidator(const ob::SpaceInformationPtr& si, std::shared_ptr<ob::MotionValidator> inner, Tally& tally)
    : ob::MotionValidator(si), inner_(std::move(inner)), tally_(tally)
  {
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2) const override
  {
    return timed([&] { return inner_->checkMotion(s1, s2); });
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override
  {
    return timed([&] { return inner_->checkMotion(s1, s2, last_valid); });
  }

private:
  template <typename F>
  bool timed(F f) const
  {
    const double start = tally_.timed ? threadSeconds() : 0;
    const bool valid = f();
    if (tally_.timed) tally_.seconds += threadSeconds() - start;
    ++tally_.calls;
    (valid ? valid_ : invalid_)++;
    return valid;
  }
  std::shared_ptr<ob::MotionValidator> inner_;
  Tally& tally_;
};

/// A table under the robot, a shelf of two boards on two sides in front of it, two mesh obstacles and, where FCL
/// has octomap support, a crate on the table as a depth sensor would see it (an octomap of its surface), scaled
/// to the robot's reach; and `clutter` small boxes between 2 and 4 reaches from the base, out of the reach of a robot
/// no longer than the scene's (the Panda, the UR5): the search stays the one without them, and what they cost is
/// the environment's broad phase.
void addScene(Environment<double>& env, double reach, int clutter = 0)
{
  const auto at = [](double x, double y, double z) {
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.translation() = fcl::Vector3d(x, y, z);
    return tf;
  };
  const double r = reach;
  env.addShape("table", std::make_shared<fcl::Boxd>(3 * r, 3 * r, 0.04), at(0, 0, -0.03));
  env.addShape("shelf_low", std::make_shared<fcl::Boxd>(0.35 * r, 0.9 * r, 0.02), at(0.75 * r, 0, 0.35 * r));
  env.addShape("shelf_high", std::make_shared<fcl::Boxd>(0.35 * r, 0.9 * r, 0.02), at(0.75 * r, 0, 0.8 * r));
  env.addShape("shelf_left", std::make_shared<fcl::Boxd>(0.35 * r, 0.02, 0.9 * r), at(0.75 * r, 0.45 * r, 0.45 * r));
  env.addShape("shelf_right", std::make_shared<fcl::Boxd>(0.35 * r, 0.02, 0.9 * r), at(0.75 * r, -0.45 * r, 0.45 * r));
  env.addShape("post", std::make_shared<fcl::Cylinderd>(0.03, 1.2 * r), at(-0.4 * r, 0.5 * r, 0.6 * r));
  env.addMesh("ball", fcl_rs::makeSphere<double>(0.1 * r, 12, 24), at(0.1 * r, -0.6 * r, 0.5 * r));
  env.addMesh("ring", fcl_rs::makeTorus<double>(0.15 * r, 0.03 * r, 24, 12), at(-0.5 * r, -0.4 * r, 0.4 * r));
#if FCL_HAVE_OCTOMAP
  const auto crate = fcl_rs::surfaceOcTree(fcl_rs::makeBox<double>(0.25 * r, 0.25 * r, 0.3 * r), 0.02 * r);
  env.addOcTree("scan", std::make_shared<fcl::OcTreed>(crate), at(0.35 * r, 0.5 * r, 0.15 * r));
#endif
  std::mt19937_64 rng(clutter);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < clutter; ++i)
  {
    const double angle = 2 * M_PI * unit(rng), distance = (2 + 2 * unit(rng)) * r;
    env.addShape("clutter" + std::to_string(i), std::make_shared<fcl::Boxd>(0.05 * r, 0.05 * r, 0.05 * r),
                 at(distance * std::cos(angle), distance * std::sin(angle), 2 * r * unit(rng)));
  }
}

/// How far the robot reaches: the largest distance of a link's geometry from the root at the zero configuration
/// plus the joint offsets (an estimate, for scaling the scene only).
double reachOf(const fcl_rs::RobotModel& robot)
{
  double reach = 0;
  for (const fcl_rs::RobotJoint& j : robot.joints) reach += j.origin.translation().norm();
  return std::min(reach, 1.2);
}

struct QueryStats
{
  bool solved = false;
  long state_checks = 0, motion_checks = 0;
  double plan_seconds = 0, state_seconds = 0, motion_seconds = 0;
  std::size_t path_states = 0;
  double path_length = 0;
  std::string path_digest;  ///< the path's states printed in full precision, hashed
};

/// Plans one seeded query in `planning` (start and goal drawn free from `seed`) with a budget of checks (state
/// checks, OMPL's discrete validator's included, plus motion checks). With `checked` given, the planner's state
/// checks are appended to it and every check is timed; without, only the planning is (QueryStats::state_seconds
/// and motion_seconds stay 0).
QueryStats plan(const Environment<double>& env, const PlanningSpace& planning, bool exact_motions, std::uint64_t seed,
                long budget, og::PathGeometric* path_out = nullptr, std::vector<Eigen::VectorXd>* checked = nullptr)
{
  const fcl_rs::Kinematics<double>& kin = env.kinematics();
  const int dof = planning.dimension();
  auto space = std::make_shared<ob::RealVectorStateSpace>(dof);
  ob::RealVectorBounds bounds(dof);
  for (int i = 0; i < dof; ++i)
  {
    bounds.setLow(i, kin.lower()[planning.variable(i)]);
    bounds.setHigh(i, kin.upper()[planning.variable(i)]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  Tally states, motions;
  states.timed = motions.timed = checked != nullptr;
  si->setStateValidityChecker(std::make_shared<ValidityChecker>(si, env, planning, states, checked));
  const std::size_t checked_before = checked ? checked->size() : 0;
  std::shared_ptr<ob::MotionValidator> inner;
  if (exact_motions)
    inner = std::make_shared<ExactMotionValidator>(si, env, planning);
  else
    inner = std::make_shared<ob::DiscreteMotionValidator>(si);
  si->setMotionValidator(std::make_shared<TimedMotionValidator>(si, inner, motions));
  si->setup();

  std::mt19937_64 rng(seed);
  const auto freeConfiguration = [&] {
    for (;;)
    {
      Eigen::VectorXd q = kin.randomConfiguration(rng);
      if (planning.group) q = planning.group->expand(planning.group->extract(q), planning.rest);
      if (!env.query(q).colliding) return q;
    }
  };
  const Eigen::VectorXd start = freeConfiguration(), goal = freeConfiguration();
  ob::ScopedState<> s(space), g(space);
  for (int i = 0; i < dof; ++i) s[i] = start[planning.variable(i)], g[i] = goal[planning.variable(i)];
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(s, g);
  og::RRTConnect planner(si);
  planner.setProblemDefinition(pdef);
  planner.setup();
  states.calls = 0;  // the start and goal draws are not the planner's
  states.seconds = 0;
  if (checked) checked->resize(checked_before);
  const double t0 = threadSeconds();
  const ob::PlannerTerminationCondition out_of_budget([&] { return states.calls + motions.calls >= budget; });
  const ob::PlannerStatus status = planner.solve(out_of_budget);
  QueryStats q;
  q.plan_seconds = threadSeconds() - t0;
  q.solved = status == ob::PlannerStatus::EXACT_SOLUTION;
  q.state_checks = states.calls;
  q.motion_checks = motions.calls;
  q.state_seconds = states.seconds;
  q.motion_seconds = motions.seconds;
  if (q.solved)
  {
    auto& path = *pdef->getSolutionPath()->as<og::PathGeometric>();
    q.path_states = path.getStateCount();
    q.path_length = path.length();
    std::ostringstream digest;
    digest.precision(17);
    for (std::size_t i = 0; i < path.getStateCount(); ++i)
      for (int d = 0; d < dof; ++d) digest << path.getState(i)->as<ob::RealVectorStateSpace::StateType>()->values[d] << ' ';
    q.path_digest = std::to_string(std::hash<std::string>()(digest.str()));
    if (path_out) *path_out = path;
  }
  return q;
}

/// The planner's state checks replayed after planning, in the order it made them: the fastest of `passes` passes
/// over all of them of the self check alone (SelfCollision::query, kinematics included) and of the whole check
/// (Environment::query), interleaved. The world part is the difference.
struct Replay
{
  double self_seconds = 0, whole_seconds = 0;
};

Replay replay(const Environment<double>& env, const std::vector<Eigen::VectorXd>& checked, int passes)
{
  Replay best{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  long colliding = 0;  // kept live, so that no check is optimised away
  for (int pass = 0; pass < passes; ++pass)
  {
    double t0 = threadSeconds();
    for (const Eigen::VectorXd& q : checked) colliding += env.selfCollision().query(q, {}).colliding;
    best.self_seconds = std::min(best.self_seconds, threadSeconds() - t0);
    t0 = threadSeconds();
    for (const Eigen::VectorXd& q : checked) colliding += env.query(q).colliding;
    best.whole_seconds = std::min(best.whole_seconds, threadSeconds() - t0);
  }
  if (colliding < 0) std::abort();
  return best;
}

/// The benchmark lines of one BV type and validator (one process: OMPL's seed is global and set once): one per
/// query, then, when `timed_checks`, the replay of the state checks (see plan for what is timed).
std::string benchmarkRun(const std::string& urdf, const std::string& srdf, fcl_rs::BVType bv, bool exact, int queries,
                         long budget, int clutter, bool timed_checks)
{
  ompl::RNG::setSeed(20261126);
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);
  Environment<double> env(robot, bv, fcl_rs::loadDisabledCollisions(srdf, robot));
  addScene(env, reachOf(robot), clutter);
  const PlanningSpace every_variable{nullptr, env.kinematics().defaultConfiguration()};
  std::ostringstream out;
  out.precision(9);
  std::vector<Eigen::VectorXd> checked;
  for (int i = 0; i < queries; ++i)
  {
    const QueryStats q =
        plan(env, every_variable, exact, 1000 + std::uint64_t(i), budget, nullptr, timed_checks ? &checked : nullptr);
    out << i << ' ' << q.solved << ' ' << q.state_checks << ' ' << q.motion_checks << ' ' << q.path_states << ' '
        << (q.path_digest.empty() ? "-" : q.path_digest) << ' ' << q.plan_seconds << ' ' << q.state_seconds << ' '
        << q.motion_seconds << '\n';
  }
  if (timed_checks)
  {
    const Replay r = replay(env, checked, 3);
    out << "replay " << checked.size() << ' ' << r.self_seconds << ' ' << r.whole_seconds << '\n';
  }
  return out.str();
}

/// Runs benchmarkRun in a child process and returns its output.
std::string inChild(const std::function<std::string()>& run)
{
  int fd[2];
  if (pipe(fd) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid == 0)
  {
    close(fd[0]);
    const std::string text = run();
    const ssize_t written = write(fd[1], text.data(), text.size());
    _exit(written == ssize_t(text.size()) ? 0 : 1);
  }
  close(fd[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = read(fd[0], buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error("benchmark child failed");
  return text;
}

struct Row
{
  std::string search;  ///< solved, checks, path per query: must be equal across BV types
  double plan = 0, state = 0, motion = 0;
  long states = 0, motions = 0, solved = 0;
  long replayed = 0;
  Replay replay;
};

Row parse(const std::string& text)
{
  Row row;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream l(line);
    if (line.rfind("replay ", 0) == 0)
    {
      std::string word;
      l >> word >> row.replayed >> row.replay.self_seconds >> row.replay.whole_seconds;
      continue;
    }
    int index, solved;
    long states, motions;
    std::size_t path_states;
    std::string digest;
    double plan, state, motion;
    l >> index >> solved >> states >> motions >> path_states >> digest >> plan >> state >> motion;
    row.search += std::to_string(solved) + ' ' + std::to_string(states) + ' ' + std::to_string(motions) + ' ' + digest + '\n';
    row.plan += plan, row.state += state, row.motion += motion;
    row.states += states, row.motions += motions, row.solved += solved;
  }
  return row;
}

int benchmark(const std::string& urdf, const std::string& srdf, int queries, long budget,
              const std::vector<bool>& validators, const std::vector<fcl_rs::BVType>& bvs, int clutter)
{
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  bool identical = true;
  for (bool exact : validators)
  {
    std::cout << (exact ? "fcl_rs exact motion validator" : "OMPL discrete motion validator (default resolution)")
              << ", " << queries << " RRTConnect queries, budget " << budget << " state + motion checks each\n";
    std::cout << "  BV      solved  state checks  motion checks  plan s   state us  motion us  plan / "
              << fcl_rs::bvTypeName(bvs.front()) << "  replayed: self us  world us\n";
    std::string reference;
    double first_plan = 0;
    for (fcl_rs::BVType bv : bvs)
    {
      if (exact && bv == fcl_rs::BVType::kOBB) continue;  // FCL has no OBB distance
      // Planning is timed in a process without clock reads per check; a second one, which must make the same
      // search, times the checks.
      Row row = parse(inChild([&] { return benchmarkRun(urdf, srdf, bv, exact, queries, budget, clutter, false); }));
      const Row timed =
          parse(inChild([&] { return benchmarkRun(urdf, srdf, bv, exact, queries, budget, clutter, true); }));
      const bool same_twice = timed.search == row.search;
      row.state = timed.state, row.motion = timed.motion, row.replayed = timed.replayed, row.replay = timed.replay;
      if (reference.empty())
      {
        reference = row.search;
        first_plan = row.plan;
      }
      const bool same = row.search == reference && same_twice;
      identical = identical && same;
      const double replayed = double(std::max(1L, row.replayed));
      std::printf("  %-7s %6ld  %12ld  %13ld  %7.3f  %8.2f  %9.2f  %9.3f  %17.2f  %8.2f%s\n", fcl_rs::bvTypeName(bv),
                  row.solved, row.states, row.motions, row.plan, 1e6 * row.state / double(std::max(1L, row.states)),
                  1e6 * row.motion / double(std::max(1L, row.motions)), row.plan / first_plan,
                  1e6 * row.replay.self_seconds / replayed,
                  1e6 * (row.replay.whole_seconds - row.replay.self_seconds) / replayed,
                  same ? "" : "  SEARCH DIFFERS");
    }
  }
  std::cout << (identical ? "every BV type explored identical trees\n" : "SEARCHES DIFFER\n");
  return identical ? 0 : 1;
}

/// Exact motion checks against discrete checks at `resolution` radians (every joint moves at most that much between
/// two checked configurations, first contact stops), on seeded segments from free configurations, `step` radians
/// per joint at most. Reports the CPU time of each and the segments the discrete check calls free but the exact
/// check does not.
int compareMotions(const std::string& urdf, const std::string& srdf, int count, double step, double resolution)
{
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);
  Environment<double> env(robot, fcl_rs::BVType::kRS, fcl_rs::loadDisabledCollisions(srdf, robot));
  addScene(env, reachOf(robot));
  const fcl_rs::Kinematics<double>& kin = env.kinematics();
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> u(-step, step);
  double exact_seconds = 0, discrete_seconds = 0;
  long discrete_states = 0, exact_colliding = 0, discrete_colliding = 0, missed = 0, wrong = 0;
  for (int i = 0; i < count; ++i)
  {
    Eigen::VectorXd from = kin.randomConfiguration(rng);
    while (env.query(from).colliding) from = kin.randomConfiguration(rng);
    Eigen::VectorXd to = from;
    for (int v = 0; v < to.size(); ++v) to[v] = std::clamp(to[v] + u(rng), kin.lower()[v], kin.upper()[v]);
    fcl_rs::MotionRequest<double> request;
    request.earliest = false;
    double t0 = threadSeconds();
    const bool exact = env.checkMotion(from, to, request).colliding;
    exact_seconds += threadSeconds() - t0;
    t0 = threadSeconds();
    const int n = std::max(1, int(std::ceil((to - from).cwiseAbs().maxCoeff() / resolution)));
    bool discrete = false;
    for (int k = 1; k <= n && !discrete; ++k, ++discrete_states)
      discrete = env.query(from + (double(k) / n) * (to - from)).colliding;
    discrete_seconds += threadSeconds() - t0;
    exact_colliding += exact;
    discrete_colliding += discrete;
    missed += exact && !discrete;
    wrong += discrete && !exact;  // would break the exact check's guarantee
  }
  std::printf("%s: %d segments (each joint within +-%.2f rad), RS\n", robot.name.c_str(), count, step);
  std::printf("  exact motion check:             %9.1f us per segment, %ld colliding\n", 1e6 * exact_seconds / count,
              exact_colliding);
  std::printf("  discrete at %.3f rad:           %9.1f us per segment, %ld colliding, %.1f states per segment\n",
              resolution, 1e6 * discrete_seconds / count, discrete_colliding, double(discrete_states) / count);
  std::printf("  colliding segments the discrete check calls free: %ld; the reverse (must be 0): %ld\n", missed, wrong);
  return wrong == 0 ? 0 : 1;
}

int run(int argc, char** argv)
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0]
              << " ROBOT.urdf ROBOT.srdf [--group NAME [--rest STATE] |"
                 " --benchmark QUERIES [BUDGET] [--validator discrete|exact] [--bv RS,OBB,...] [--clutter K] |"
                 " --motions SEGMENTS [STEP]]\n";
    return 2;
  }
  const std::string urdf = argv[1], srdf = argv[2];
  if (argc >= 5 && std::strcmp(argv[3], "--motions") == 0)
    return compareMotions(urdf, srdf, std::stoi(argv[4]), argc >= 6 ? std::stod(argv[5]) : 0.5, 0.01);
  if (argc >= 5 && std::strcmp(argv[3], "--benchmark") == 0)
  {
    int arg = 5;
    const long budget = argc > arg && argv[arg][0] != '-' ? std::stol(argv[arg++]) : 100000;
    std::vector<bool> validators = {false, true};
    int clutter = 0;
    std::vector<fcl_rs::BVType> bvs;  // KDOP18 trees are refitted in place per check: not shareable
    for (fcl_rs::BVType bv : fcl_rs::kRobotBVTypes)
      if (bv != fcl_rs::BVType::kKDOP18) bvs.push_back(bv);
    for (; arg + 1 < argc; arg += 2)
    {
      const std::string option = argv[arg], value = argv[arg + 1];
      if (option == "--validator" && (value == "discrete" || value == "exact"))
        validators = {value == "exact"};
      else if (option == "--bv")
      {
        bvs.clear();
        std::istringstream names(value);
        for (std::string name; std::getline(names, name, ',');) bvs.push_back(fcl_rs::parseBVType(name));
      }
      else if (option == "--clutter" && !value.empty() && value.find_first_not_of("0123456789") == std::string::npos)
        clutter = std::stoi(value);
      else
        break;
    }
    if (arg != argc || bvs.empty())
    {
      std::cerr << "usage: " << argv[0]
                << " ROBOT.urdf ROBOT.srdf --benchmark QUERIES [BUDGET] [--validator discrete|exact] [--bv RS,OBB,...]"
                   " [--clutter K]\n";
      return 2;
    }
    return benchmark(urdf, srdf, std::stoi(argv[4]), budget, validators, bvs, clutter);
  }

  // Without --group OMPL plans in every variable; with it, in the SRDF group's, the others held at the default
  // configuration or at a group state of the SRDF.
  std::string group_name, rest_state;
  for (int arg = 3; arg < argc; arg += 2)
  {
    const std::string option = argv[arg];
    if (arg + 1 < argc && option == "--group")
      group_name = argv[arg + 1];
    else if (arg + 1 < argc && option == "--rest")
      rest_state = argv[arg + 1];
    else
    {
      std::cerr << "usage: " << argv[0] << " ROBOT.urdf ROBOT.srdf [--group NAME [--rest STATE]]\n";
      return 2;
    }
  }
  ompl::RNG::setSeed(7);
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);
  Environment<double> env(robot, fcl_rs::BVType::kRS, fcl_rs::loadDisabledCollisions(srdf, robot));
  addScene(env, reachOf(robot));
  const fcl_rs::PlanningGroups groups =
      group_name.empty() && rest_state.empty() ? fcl_rs::PlanningGroups() : fcl_rs::loadPlanningGroups(srdf, robot);
  PlanningSpace planning{nullptr, env.kinematics().defaultConfiguration()};
  if (!group_name.empty()) planning.group = &groups.group(group_name);
  if (!rest_state.empty()) planning.rest = groups.state(rest_state).applyTo(planning.rest);
  og::PathGeometric path(nullptr);
  const QueryStats q = plan(env, planning, /*exact_motions=*/true, 1000, 100000, &path);
  std::cout << robot.name << (planning.group ? " (group " + group_name + ")" : std::string()) << ": "
            << (q.solved ? "solved" : "not solved") << " with " << q.state_checks << " state checks and "
            << q.motion_checks << " motion checks; path of " << q.path_states << " states\n";
  if (!q.solved) return 1;
  // Every segment of the path is free, for every configuration on it (a second, independent check); with a group,
  // the variables outside it stayed where they were.
  std::vector<Eigen::VectorXd> waypoints(path.getStateCount());
  for (std::size_t i = 0; i < path.getStateCount(); ++i) planning.configuration(path.getState(i), waypoints[i]);
  if (planning.group)
    for (const Eigen::VectorXd& w : waypoints)
      if (planning.group->expand(planning.group->extract(planning.rest), w) != planning.rest)
      {
        std::cout << "a waypoint moved a variable outside group " << group_name << "\n";
        return 1;
      }
  const fcl_rs::MotionResult<double> whole = env.checkPath(waypoints);
  std::cout << "path re-checked: " << (whole.colliding ? "COLLIDES" : "free") << "\n";
  return whole.colliding ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv)
{
  // Bad arguments and unreadable robots end with their message, not with std::terminate's abort.
  try
  {
    return run(argc, argv);
  }
  catch (const std::exception& e)
  {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    return 2;
  }
}
