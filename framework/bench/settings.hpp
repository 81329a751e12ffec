#pragma once
// A bench's settings as JSON: what its list of runs and its report depend on. Every
// records file's header carries them, and a child process of -j and `bench merge` read
// them back, so that each of them sees the sweep the parent saw.

#include <string>

#include <nlohmann/json.hpp>

#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::bench {

/// Every field of `args` but its outputs, verbosity, goal check and sweep options;
/// paths made absolute.
nlohmann::ordered_json settings_of(const BenchArgs& args);

/// The arguments `settings` (as settings_of wrote them) describe. Throws InputError at
/// `where` naming a field that is missing or of the wrong type.
BenchArgs args_of(const nlohmann::ordered_json& settings, const SourceLocation& where);

/// `args` with the paths of its settings made absolute, as settings_of writes them: what
/// a bench records (problem files, instances) is then the same in this process, in its
/// child processes and in every shard, wherever each was started.
BenchArgs with_absolute_paths(BenchArgs args);

}  // namespace cluttertamp::bench
