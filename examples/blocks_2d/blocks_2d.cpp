// blocks_2d: the streams of examples/blocks_2d/stream.pddl, a complete stream plugin
// for a 2-D pick-and-place world (a vertical plane: x along the table, y up).
//
// The stream protocol, as this plugin uses it (docs/symbolic-planning.md, "Writing a stream plugin"):
//  - instantiate() is called once per stream instance (a stream and its inputs) and
//    returns a generator, or nullptr when these inputs can never make anything.
//  - A generator's next() returns a batch: zero or more output tuples (one value per
//    :outputs variable), `exhausted` when no later call can make more, and a
//    `failure` saying why when it made nothing.
//  - A test (no :outputs) says "certified" with one empty tuple and "not" with none;
//    it is asked once.
//  - A function returns one tuple holding one number (a double).
//  - Inputs arrive as the values of the objects: a problem object's value from the
//    problem file (`values:`; numbers, lists of numbers, strings as such, maps as a
//    ValuePayload), a generated object's value as this plugin made it.
//  - Same seed, same values: every random draw comes from the run's seed and the
//    order in which the search makes generators, never from the clock or addresses.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"

namespace {

using namespace cluttertamp;
using plugin::StreamBatch;
using plugin::StreamValue;

struct Block {
  double width = 0, height = 0;  // m
};

// A block's value from the problem file: {width: w, height: h}.
Block block_of(const StreamValue& v) {
  const Value* value = plugin::as_value(v);
  if (!value || !value->map()) throw InputError({}, "blocks_2d: a block's value must be a map {width: w, height: h}");
  Block b;
  for (auto [key, field] : {std::pair{"width", &b.width}, std::pair{"height", &b.height}}) {
    const Value* entry = value->find(key);
    const auto x = entry ? entry->number() : std::nullopt;
    if (!x || *x <= 0) throw InputError(value->where(), std::string("blocks_2d: a block needs a positive '") + key + "' (m)");
    *field = *x;
  }
  return b;
}

// A pose, a configuration, a grasp or a region: two numbers.
Eigen::Vector2d pair_of(const StreamValue& v, const char* what) {
  const auto* x = std::get_if<Eigen::VectorXd>(&v);
  if (!x || x->size() != 2) throw InputError({}, std::string("blocks_2d: ") + what + " must be two numbers [x, y]");
  return {(*x)[0], (*x)[1]};
}

StreamValue value_of(const Eigen::Vector2d& x) { return Eigen::VectorXd(x); }

// The table interval a block covers at pose p.
std::pair<double, double> footprint(const Block& b, const Eigen::Vector2d& p) {
  return {p.x() - b.width / 2, p.x() + b.width / 2};
}

// A motion of the gripper's tip: up to the carry height, across, down.
class Path final : public plugin::StreamPayload {
 public:
  explicit Path(std::vector<Eigen::Vector2d> points) : points_(std::move(points)) {
    trajectory_.joint_names = {"x", "y"};
    double t = 0;
    for (std::size_t k = 0; k < points_.size(); ++k) {
      if (k) t += (points_[k] - points_[k - 1]).norm();  // at 1 m/s
      trajectory_.times.push_back(t);
      trajectory_.positions.emplace_back(points_[k]);
    }
  }
  const Trajectory* trajectory() const override { return &trajectory_; }
  std::vector<double> numbers() const override {
    std::vector<double> out;
    for (const Eigen::Vector2d& p : points_) out.insert(out.end(), {p.x(), p.y()});
    return out;
  }

 private:
  std::vector<Eigen::Vector2d> points_;
  Trajectory trajectory_;
};

// A generator that answers once.
class Once final : public plugin::StreamGenerator {
 public:
  explicit Once(StreamBatch batch) : batch_(std::move(batch)) { batch_.exhausted = true; }
  StreamBatch next(plugin::PlanningContext&) override { return batch_; }

 private:
  StreamBatch batch_;
};

StreamBatch answer(std::vector<StreamValue> outputs) { return StreamBatch{{std::move(outputs)}, true, std::nullopt}; }
StreamBatch nothing(std::string why) { return StreamBatch{{}, true, Failure{"blocks_2d", std::move(why), {}}}; }
StreamBatch test(bool certified, const std::string& why_not) { return certified ? answer({}) : nothing(why_not); }

// Poses of a block inside a region, uniformly at random; infinitely many.
class SamplePlacement final : public plugin::StreamGenerator {
 public:
  SamplePlacement(double lowest, double highest, std::uint64_t seed) : lowest_(lowest), highest_(highest), rng_(seed) {}
  StreamBatch next(plugin::PlanningContext&) override {
    const double x = std::uniform_real_distribution<double>(lowest_, highest_)(rng_);
    return StreamBatch{{{value_of({x, 0.0})}}, false, std::nullopt};
  }

 private:
  double lowest_, highest_;
  std::mt19937_64 rng_;
};

// FNV-1a: a hash that is the same on every machine, for seeds.
std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t n) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
  return h;
}

class Blocks2d final : public plugin::StreamSampler {
 public:
  void configure(const Parameters& p) override {
    carry_height_ = p.get_double("carry_height", carry_height_, "m: the gripper's tip crosses at least this high");
    p.require(carry_height_ > 0, "carry_height", "must be positive (m)");
    if (const Value* workspace = p.get("workspace", "{min_x, max_x}, m: where the gripper's tip can reach")) {
      const Value* lo = workspace->find("min_x");
      const Value* hi = workspace->find("max_x");
      if (!lo || !hi || !lo->number() || !hi->number() || *hi->number() <= *lo->number() || workspace->map()->size() != 2) {
        throw InputError(workspace->where(), "parameter 'workspace' must be {min_x: a, max_x: b} with a < b (m)");
      }
      min_x_ = *lo->number();
      max_x_ = *hi->number();
    }
  }

  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext& context, std::string_view stream,
                                                       const std::vector<StreamValue>& in,
                                                       const std::vector<plugin::StreamFact>&) override {
    if (stream == "sample-placement") {
      const Block b = block_of(in[0]);
      const Eigen::Vector2d region = pair_of(in[1], "a region");
      const double lowest = region.x() + b.width / 2, highest = region.y() - b.width / 2;
      if (lowest > highest) return std::make_unique<Once>(nothing("the block is wider than the region"));
      // The n-th placement generator of the run draws from the n-th seed: blocks alike in
      // size still get poses of their own, and the search's order is the seed's.
      return std::make_unique<SamplePlacement>(lowest, highest, seed(context, stream, placements_++));
    }
    if (stream == "test-contained") {
      const auto [left, right] = footprint(block_of(in[0]), pair_of(in[1], "a pose"));
      const Eigen::Vector2d region = pair_of(in[2], "a region");
      return std::make_unique<Once>(test(region.x() <= left && right <= region.y(), "the block sticks out of the region"));
    }
    if (stream == "sample-grasp") {
      return std::make_unique<Once>(answer({value_of({0.0, block_of(in[0]).height})}));  // the top's centre
    }
    if (stream == "inverse-kinematics") {
      const Eigen::Vector2d q = pair_of(in[1], "a pose") + pair_of(in[2], "a grasp");
      if (q.x() < min_x_ || q.x() > max_x_) return std::make_unique<Once>(nothing("out of the gripper's reach"));
      return std::make_unique<Once>(answer({value_of(q)}));
    }
    if (stream == "plan-motion") {
      return std::make_unique<Once>(answer({std::make_shared<const Path>(path(pair_of(in[0], "a configuration"),
                                                                             pair_of(in[1], "a configuration")))}));
    }
    if (stream == "test-cfree") {
      const auto [l1, r1] = footprint(block_of(in[0]), pair_of(in[1], "a pose"));
      const auto [l2, r2] = footprint(block_of(in[2]), pair_of(in[3], "a pose"));
      return std::make_unique<Once>(test(r1 <= l2 || r2 <= l1, "the blocks overlap"));
    }
    if (stream == "distance") {
      const std::vector<Eigen::Vector2d> points = path(pair_of(in[0], "a configuration"), pair_of(in[1], "a configuration"));
      double length = 0;
      for (std::size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
      return std::make_unique<Once>(answer({length}));
    }
    throw InputError({}, "blocks_2d has no stream '" + std::string(stream) +
                             "' (it has sample-placement, test-contained, sample-grasp, inverse-kinematics, "
                             "plan-motion, test-cfree and distance)");
  }

 private:
  std::vector<Eigen::Vector2d> path(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
    const double y = std::max({carry_height_, from.y(), to.y()});
    return {from, {from.x(), y}, {to.x(), y}, to};
  }

  static std::uint64_t seed(const plugin::PlanningContext& context, std::string_view stream, std::uint64_t n) {
    std::uint64_t h = fnv(1469598103934665603ull ^ context.seed, stream.data(), stream.size());
    for (int byte = 0; byte < 8; ++byte) {  // little end first, whatever the machine's order
      const unsigned char b = static_cast<unsigned char>(n >> (8 * byte));
      h = fnv(h, &b, 1);
    }
    return h;
  }

  double carry_height_ = 5.0;
  double min_x_ = -12.0, max_x_ = 12.0;
  std::uint64_t placements_ = 0;  // placement generators made so far
};

}  // namespace

CLUTTERTAMP_EXPORT_STREAM_SAMPLER(Blocks2d, blocks_2d,
                                  "Example: streams of a 2-D pick-and-place world (examples/blocks_2d)", "1.0.0")
