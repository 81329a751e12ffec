// Out-of-line destructors (so each interface's vtable and type information live in
// libcluttertamp, shared by every plugin) and the small helpers of the interfaces.
#include <algorithm>
#include <array>
#include <stdexcept>
#include <cmath>
#include <limits>

#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/plugin/world_view.hpp"

namespace cluttertamp::plugin {

Plugin::~Plugin() = default;
void Plugin::configure(const Parameters&) {}
TaskPlanner::~TaskPlanner() = default;
std::vector<std::string> TaskPlanner::required_kinds() const { return {}; }
void TaskPlanner::check_inputs(const Problem&) const {}
ObjectPruner::~ObjectPruner() = default;
GraspSampler::~GraspSampler() = default;
PlacementSampler::~PlacementSampler() = default;
MotionSampler::~MotionSampler() = default;
PushSampler::~PushSampler() = default;
StreamSampler::~StreamSampler() = default;
StreamPayload::~StreamPayload() = default;
const Trajectory* StreamPayload::trajectory() const { return nullptr; }
std::vector<double> StreamPayload::numbers() const { return {}; }

ValuePayload::ValuePayload(Value value) : value_(std::move(value)) {}
ValuePayload::~ValuePayload() = default;
std::vector<double> ValuePayload::numbers() const { return value_.numbers().value_or(std::vector<double>{}); }

const Value* as_value(const StreamValue& v) {
  const auto* payload = std::get_if<std::shared_ptr<const StreamPayload>>(&v);
  if (!payload) return nullptr;
  const auto* value = dynamic_cast<const ValuePayload*>(payload->get());
  return value ? &value->value() : nullptr;
}

StreamValue stream_value(const Value& value) {
  if (const auto x = value.number()) return *x;
  if (const auto numbers = value.numbers(); numbers && !numbers->empty()) {
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(numbers->data(), static_cast<Eigen::Index>(numbers->size())));
  }
  if (const std::string* s = value.string()) return *s;
  return std::make_shared<const ValuePayload>(value);
}
StreamGenerator::~StreamGenerator() = default;
WorldView::~WorldView() = default;
WorldSource::~WorldSource() = default;

std::shared_ptr<Plugin> Samplers::get(std::string_view kind) const {
  const auto it = by_kind_.find(kind);
  return it == by_kind_.end() ? nullptr : it->second;
}

void Samplers::set(std::string_view kind, std::shared_ptr<Plugin> plugin) {
  if (plugin) by_kind_.insert_or_assign(std::string(kind), std::move(plugin));
  else if (const auto it = by_kind_.find(kind); it != by_kind_.end()) by_kind_.erase(it);
}

std::vector<std::string> Samplers::kinds() const {
  std::vector<std::string> out;
  for (const auto& [kind, plugin] : by_kind_) out.push_back(kind);
  return out;
}

void Samplers::wrong_type(const char* kind) {
  throw std::logic_error(std::string("the plugin set as ") + kind + " does not implement that kind's interface");
}

Deadline Deadline::after(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0 || seconds > 1e9) return never();
  return Deadline(Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)));
}

Deadline Deadline::never() { return Deadline(Clock::time_point::max()); }

bool Deadline::expired() const { return Clock::now() >= at_; }

double Deadline::remaining() const {
  if (at_ == Clock::time_point::max()) return std::numeric_limits<double>::max();
  return std::max(0.0, std::chrono::duration<double>(at_ - Clock::now()).count());
}

Phase::Phase(const PlanningContext& context, std::string name)
    : context_(context), name_(std::move(name)), checks_at_start_(context.checks_done()), started_(Deadline::Clock::now()) {}

void add_phase(const PlanningContext& context, const std::string& name, std::uint64_t checks, double seconds) {
  if (!context.phases) return;
  PhaseTotals& totals = (*context.phases)[name];
  ++totals.calls;
  totals.collision_checks += checks;
  totals.seconds += seconds;
}

Phase::~Phase() {
  if (!context_.phases) return;
  add_phase(context_, name_, context_.checks_done() - checks_at_start_,
            std::chrono::duration<double>(Deadline::Clock::now() - started_).count());
}

const BlockedGrasp* GraspAnswer::least_blocked() const {
  const BlockedGrasp* best = nullptr;
  for (const BlockedGrasp& b : blocked) {
    if (b.freeable && (!best || b.blocking_objects.size() < best->blocking_objects.size())) best = &b;
  }
  return best;
}

std::vector<ObjectIndex> PruneAnswer::movable_objects() const {
  std::vector<ObjectIndex> all;
  for (const auto& sequence : removal_sequences) all.insert(all.end(), sequence.begin(), sequence.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

}  // namespace cluttertamp::plugin
