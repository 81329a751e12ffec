#pragma once

#include <filesystem>
#include <string>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// Identifies the layout of result.json; raised when a field changes meaning.
inline constexpr const char* kResultSchema = "cluttertamp.result/1";

/// Facts about a run that are not part of the planner's Result.
struct RunInfo {
  std::string planner;
  double time_limit = 0.0;
  std::uint64_t seed = 0;
  int exit_code = 0;
};

/// result.json as text (schema: README, "result.json"). Object indices are written
/// as the scene's object ids.
CLUTTERTAMP_API std::string result_to_json(const Problem& problem, const Result& result, const RunInfo& run);

/// Writes result_to_json to `file`, creating its directory. Throws InputError when
/// the file cannot be written (a bad --output is bad input).
CLUTTERTAMP_API void write_result_json(const std::filesystem::path& file, const Problem& problem,
                                       const Result& result, const RunInfo& run);

}  // namespace cluttertamp::io
