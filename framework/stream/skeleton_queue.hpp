#pragma once
// Internal: the adaptive stream search's skeleton queue (PDDLStream's): the optimistic
// plans waiting for their streams, each with its stream plan refined as a tree of
// bindings of optimistic objects to real values.

#include <cstddef>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "stream/search_core.hpp"

namespace cluttertamp::stream::detail {

/// One stream instance of a stream plan; `negated`: a test that must come out false.
/// A stream with :fluents is evaluated in the state before action `step` (the goal's
/// state when it is the plan's length); -1 for the others.
struct PlannedInstance {
  int instance = 0;
  bool negated = false;
  int step = -1;
  auto operator<=>(const PlannedInstance&) const = default;
};

/// A node of the binding tree: optimistic objects bound so far, the next instance of
/// the stream plan to evaluate, and how many of that instance's values became children.
struct Binding {
  std::map<ObjectId, ObjectId> mapping;
  std::size_t index = 0;
  std::size_t consumed = 0;
};

/// An optimistic plan waiting for its streams: actions, stream plan, binding tree
/// (depth first: the last binding is the deepest).
struct Skeleton {
  std::string key;
  std::vector<Step> actions;
  std::vector<PlannedInstance> stream_plan;
  std::vector<Binding> stack;
  bool waiting = false;  ///< every binding waits for the level to rise
};

/// The skeletons queued so far, worked on shortest plan first.
class SkeletonQueue {
 public:
  /// `core` must outlive the queue.
  explicit SkeletonQueue(SearchCore& core);

  /// The stream plan behind the optimistic facts a plan relies on, in an order where
  /// every instance comes after those making its inputs; nothing when the plan does not
  /// hold on the optimistic facts.
  ///
  /// An instance of a stream with :fluents is evaluated in the state before the first
  /// step that needs it (a test: before each such step), after the instances whose
  /// optimistic outputs that state holds; an instance it feeds needs it as early.
  std::optional<Skeleton> skeleton_of(const std::vector<Step>& steps);

  /// Queues `skeleton` unless a skeleton of the same plan was queued before; returns
  /// whether it was queued.
  bool add(Skeleton skeleton);

  /// Works through the queue for `budget` units of work (StreamSearchOptions), shortest
  /// plan first: a skeleton is worked on until all its bindings wait. An instance whose
  /// next call would exceed `level` waits for the level to rise. Returns a plan, if one
  /// comes out; `progress` tells whether a stream was called.
  std::optional<std::vector<Step>> refine(double budget, int level, bool& progress);

  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }

 private:
  enum class Move { moved, called, waiting };

  static ObjectId bound(const Binding& b, ObjectId o);
  static std::vector<Step> bound_steps(std::vector<Step> steps, const Binding& b);
  /// Evaluates one step of a skeleton's binding tree (its deepest binding). Returns a
  /// finished plan, if any.
  std::optional<std::vector<Step>> advance(Skeleton& sk, Move& move, int level);

  SearchCore& core_;
  FactBase& base_;
  StreamEvaluator& evaluator_;
  plugin::PlanningContext& context_;
  const StreamSearchOptions& options_;
  std::deque<Skeleton> queue_;
  std::set<std::string> queued_;  ///< the keys of every skeleton ever queued
};

}  // namespace cluttertamp::stream::detail
