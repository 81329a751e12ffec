#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/value.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// A value a stream makes that is none of the plain kinds: a grasp, a trajectory.
/// Plugins derive from it; the stream search only passes it around.
class CLUTTERTAMP_API StreamPayload {
 public:
  virtual ~StreamPayload();
  /// The robot motion the value stands for, if any: a plan step's trajectory.
  virtual const Trajectory* trajectory() const;
  /// Numbers describing the value in result.json (e.g. a pose as x y z qx qy qz qw).
  virtual std::vector<double> numbers() const;
};

/// A problem object's value from the problem file (`task: pddl: values:`) that is not a
/// number, a list of numbers or a string: a map, a nested list. The stream receives it
/// as this payload; as_value() unwraps it.
class CLUTTERTAMP_API ValuePayload final : public StreamPayload {
 public:
  explicit ValuePayload(Value value);
  ~ValuePayload() override;
  const Value& value() const { return value_; }
  /// The value's numbers if it is a list of numbers, else none.
  std::vector<double> numbers() const override;

 private:
  Value value_;
};

/// A value flowing through streams: a PDDL object name, a number, a vector (a
/// configuration), a pose, or a payload.
using StreamValue =
    std::variant<std::string, double, Eigen::VectorXd, Eigen::Isometry3d, std::shared_ptr<const StreamPayload>>;

/// The problem file's Value behind `v` when it is a ValuePayload; nullptr otherwise.
CLUTTERTAMP_API const Value* as_value(const StreamValue& v);

/// `value` as streams receive it: an integer or a number as a double, a list of numbers
/// as an Eigen::VectorXd, a string as a std::string, anything else as a ValuePayload.
CLUTTERTAMP_API StreamValue stream_value(const Value& value);

/// What one call of a generator produced.
struct StreamBatch {
  std::vector<std::vector<StreamValue>> outputs;  ///< each: one value per stream output
  bool exhausted = false;                         ///< no further call can yield more
  std::optional<Failure> failure;                 ///< why nothing was produced
};

/// A fact of the state a stream with :fluents is evaluated in: (AtPose o p) is
/// {"atpose", {"o", <the pose of p>}}. Arguments are StreamValues as for inputs.
struct StreamFact {
  std::string predicate;  ///< lower case, as the domain declares it
  std::vector<StreamValue> args;
};

/// A lazy generator for one stream instance (fixed inputs). Must not outlive the
/// StreamSampler that created it.
class CLUTTERTAMP_API StreamGenerator {
 public:
  virtual ~StreamGenerator();
  virtual StreamBatch next(PlanningContext& context) = 0;
};

/// Binds a stream of a user's stream file to code: certifies facts by producing
/// outputs for given inputs (PDDLStream's generators and tests). Scene objects that are
/// not movable (context.scene().objects[o].movable false: declared so, or left out by
/// stream_planner's object pruner) have no pose facts in a scene-derived problem, so no
/// test is asked about them: a sampler must treat them as fixed geometry.
class CLUTTERTAMP_API StreamSampler : public Plugin {
 public:
  ~StreamSampler() override;
  /// A generator for `stream` on `inputs` (in the order of the stream's :inputs),
  /// or nullptr when these inputs can make nothing. `fluents` is empty unless the stream
  /// declares :fluents; then it holds every fact of those predicates in the state the
  /// outputs will be used in (the state before the plan step that needs them), and the
  /// outputs are trusted in that state only.
  virtual std::unique_ptr<StreamGenerator> instantiate(PlanningContext& context, std::string_view stream,
                                                       const std::vector<StreamValue>& inputs,
                                                       const std::vector<StreamFact>& fluents) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::StreamSampler, stream_sampler)

/// Exports CLASS as the stream_sampler NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_STREAM_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(stream_sampler, CLASS, NAME, DESCRIPTION, VERSION)
