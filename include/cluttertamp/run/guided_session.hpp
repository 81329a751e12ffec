#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "cluttertamp/plugin/registry.hpp"

namespace cluttertamp::run {

/// Settings of an operator's session.
struct GuidedSessionOptions {
  double diameter = 0.1;     ///< m: each guide's region
  double push_time = 10.0;   ///< s: at most this much planning per guide (and never beyond the time left)
  /// The push sampler when the problem's `plugins:` block names none.
  std::string default_push_sampler = "push_ompl";
};

/// Reaching through clutter guided by a person, one guide at a time (Papallas & Dogar
/// 2020, Section V-B, Algorithm 2, GRTC-HITL). The operator names an object and a point
/// on the shelf; the push sampler plans the push from the current state; a push that
/// works moves the state on, one that fails leaves it and is logged as a failed input.
/// When the operator lets the robot finish, kinodynamic planning (the problem's
/// planner parameters: `planner`, tolerances, bounds) reaches the target in the time
/// left: the problem's time limit less the planning time of every input. The log is
/// the seed's Table I record: successful and failed inputs and interaction time (the
/// session's wall-clock time outside planning). Not thread-safe: callers serialise.
class CLUTTERTAMP_API GuidedSession {
 public:
  /// Throws InputError for a problem that is not a reach task, or whose plugins are
  /// missing or reject their parameters.
  GuidedSession(Problem problem, const plugin::Registry& registry, GuidedSessionOptions options = {});
  ~GuidedSession();
  GuidedSession(const GuidedSession&) = delete;
  GuidedSession& operator=(const GuidedSession&) = delete;

  /// What became of one input.
  struct Outcome {
    bool ok = false;
    bool planned = false;  ///< false: refused before planning (bad input); not logged
    std::string message;   ///< what happened, for the operator
  };

  /// Push `object` (a scene id) into the disc of `diameter` (default: the options')
  /// about `centre` (world x, y, m). Refused without planning (ok false, not logged)
  /// for an unknown or fixed object, a disc that leaves the shelf, or a finished session.
  Outcome guide(const std::string& object, const Eigen::Vector2d& centre, std::optional<double> diameter = {});

  /// "Let the robot finish": plans the reach from the current state in the time left.
  /// Refused when already finished.
  Outcome finish();

  bool finished() const;
  double time_left() const;  ///< s of planning time the reach would get
  const Problem& problem() const;

  /// The page's view of the session as JSON: the shelf, the objects where they are now,
  /// the gripper, the log, and once finished the result.
  std::string state_json() const;

  /// The successful guides so far, as a guidance file (io::guidance_to_yaml).
  std::string guidance_yaml() const;
  /// The session as a result.json: the pushes so far (and the reach once finished),
  /// with the operator's record under "human_guidance".
  std::string result_json() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cluttertamp::run
