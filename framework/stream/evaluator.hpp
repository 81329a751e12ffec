#pragma once
// Internal: the part of a stream search that calls the user's streams.

#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/stream/stream_search.hpp"
#include "stream/fact_base.hpp"

namespace cluttertamp::stream::detail {

/// Evaluates stream instances on real values: creates their generators through the
/// bound StreamSamplers, calls them, turns what they yield into objects and certified
/// facts of the FactBase, and files what went wrong as failures of the solution.
/// Both searches (incremental and adaptive) evaluate through it; it decides nothing
/// about which instance to call.
class StreamEvaluator {
 public:
  /// Every argument must outlive the evaluator. Statistics, failures and the values
  /// made go to `out`.
  StreamEvaluator(const StreamProblem& problem, FactBase& base, plugin::PlanningContext& context,
                  const StreamSearchOptions& options, StreamSolution& out);

  /// The options given for stream `d` (defaults when none).
  const StreamOptions& options_of(const StreamDecl& d) const;

  /// One call of a real instance's generator (made on the first call); its outputs
  /// become objects and its certified facts real, at one more than the highest
  /// complexity of its domain facts. A rule certifies at once. Returns whether it
  /// produced anything; an exhausted instance produces nothing.
  bool call(int instance);

  /// Calls, until nothing changes, the rules, functions and eager streams whose domain
  /// facts hold with real facts (an eager stream once per instance).
  void close_real();

  /// The instances of `stream` whose domain facts all hold as real facts.
  std::vector<int> real_instances(int stream);

  /// The highest complexity of an instance's domain facts when they all hold as real
  /// facts; nothing when one does not (yet).
  std::optional<int> real_domain(const Instance& instance);

  /// Files a failure of stream `d` (the first 100 distinct ones are kept).
  void fail(const StreamDecl& d, const std::string& reason, std::vector<ObjectIndex> blocking = {});

  /// Destroys every generator (plugin code, which must not outlive its sampler).
  void release_generators();

 private:
  plugin::StreamValue value_of(ObjectId id) const;
  ObjectId object_for(const plugin::StreamValue& value, const std::string& variable);
  void certify(int instance, const std::vector<ObjectId>& outputs, int complexity);

  const StreamProblem& problem_;
  FactBase& base_;
  plugin::PlanningContext& context_;
  const StreamSearchOptions& options_;
  StreamSolution& out_;
  int generated_ = 0;  ///< values made so far: "#p3" is the third
};

}  // namespace cluttertamp::stream::detail
