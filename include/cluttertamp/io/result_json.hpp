#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// Identifies the layout of result.json; raised when a field changes meaning.
inline constexpr const char* kResultSchema = "cluttertamp.result/1";

/// One operator input of a guided session (GRTC-HITL, run::GuidedSession).
struct OperatorInput {
  std::string object;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< world x, y, m
  double diameter = 0.0;                             ///< m
  bool satisfied = false;
  double planning_time = 0.0;  ///< s
  std::string reason;          ///< why not, when not satisfied
};

/// The record of a guided session (Papallas & Dogar, Table I): its inputs and the
/// operator's interaction time, the session's wall-clock time outside planning (s).
struct HumanGuidance {
  std::vector<OperatorInput> inputs;
  double interaction_time = 0.0;
};

/// Facts about a run that are not part of the planner's Result.
struct RunInfo {
  std::string planner;
  double time_limit = 0.0;
  std::uint64_t seed = 0;
  int exit_code = 0;
  std::optional<HumanGuidance> human_guidance;  ///< written as "human_guidance" when set
};

/// result.json as text (schema: docs/file-formats.md, "result.json"). Object indices are written
/// as the scene's object ids.
CLUTTERTAMP_API std::string result_to_json(const Problem& problem, const Result& result, const RunInfo& run);

/// The planner's drawings (Result::drawings: roadmaps, retrieval graphs) as JSON:
/// {"schema": "cluttertamp-drawings/1", "drawings": [{name, nodes: [[x, y]...] (m),
/// labels, edges: [[a, b]...], path}]}. Kept out of result.json: a roadmap is tens of
/// times the size of the rest.
CLUTTERTAMP_API std::string drawings_to_json(const Result& result);

/// Writes result_to_json to `file`, creating its directory. Throws InputError when the
/// file cannot be written (a bad --output is bad input).
CLUTTERTAMP_API void write_result_json(const std::filesystem::path& file, const Problem& problem,
                                       const Result& result, const RunInfo& run);

}  // namespace cluttertamp::io
