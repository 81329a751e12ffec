#include "cli/determinism.hpp"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <sched.h>

#include <nlohmann/json.hpp>

namespace cluttertamp::cli {

namespace {

using Json = nlohmann::json;

// Time fields anywhere (`time`, `..._time`), and the file paths a result names: the
// problem and scene at the top, a PDDL task's domain, problem and streams.
bool ignored(const std::string& at, const std::string& key) {
  if (key == "time" || (key.size() > 5 && key.compare(key.size() - 5, 5, "_time") == 0)) return true;
  if (at.empty()) return key == "problem" || key == "scene";
  return at == "/task" && (key == "domain" || key == "problem" || key == "streams");
}

std::string shown(const Json& v) {
  std::string text = v.dump();
  return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

std::optional<std::string> difference(const Json& a, const Json& b, const std::string& at) {
  if (a.type() != b.type()) return at + ": " + shown(a) + " against " + shown(b);
  if (a.is_object()) {
    for (const auto& [key, value] : a.items()) {
      if (ignored(at, key)) continue;
      if (!b.contains(key)) return at + "/" + key + ": only in the first";
      if (auto d = difference(value, b.at(key), at + "/" + key)) return d;
    }
    for (const auto& [key, value] : b.items()) {
      if (!ignored(at, key) && !a.contains(key)) return at + "/" + key + ": only in the second";
    }
    return std::nullopt;
  }
  if (a.is_array()) {
    if (a.size() != b.size()) return at + ": " + std::to_string(a.size()) + " items against " + std::to_string(b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (auto d = difference(a[i], b[i], at + "/" + std::to_string(i))) return d;
    }
    return std::nullopt;
  }
  // Numbers bit for bit: the same seed must give the same floating-point values.
  if (a != b) return (at.empty() ? "/" : at) + ": " + shown(a) + " against " + shown(b);
  return std::nullopt;
}

}  // namespace

std::optional<std::string> result_difference(const std::string& a, const std::string& b) {
  return difference(Json::parse(a), Json::parse(b), "");
}

struct CpuLoad::Impl {
  int cpu = -1;
  cpu_set_t before{};
  std::atomic<bool> stop{false};
  std::vector<std::thread> burners;
};

CpuLoad::CpuLoad(int threads) : impl_(std::make_unique<Impl>()) {
  if (threads <= 0) return;
  const int cpu = std::max(0, sched_getcpu());
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  // This thread; the burners inherit it. Without it the load would prove nothing.
  if (sched_getaffinity(0, sizeof impl_->before, &impl_->before) != 0 || sched_setaffinity(0, sizeof one, &one) != 0) {
    throw std::runtime_error("--load: cannot hold the planner to one CPU (sched_setaffinity failed)");
  }
  impl_->cpu = cpu;
  try {
    for (int k = 0; k < threads; ++k) {
      impl_->burners.emplace_back([stop = &impl_->stop] {
        volatile std::uint64_t spin = 0;
        while (!stop->load(std::memory_order_relaxed)) spin = spin + 1;
      });
    }
  } catch (...) {
    stop();
    throw;
  }
}

void CpuLoad::stop() {
  impl_->stop = true;
  for (std::thread& t : impl_->burners) t.join();
  impl_->burners.clear();
  if (impl_->cpu >= 0) sched_setaffinity(0, sizeof impl_->before, &impl_->before);
  impl_->cpu = -1;
}

CpuLoad::~CpuLoad() { stop(); }

int CpuLoad::cpu() const { return impl_->cpu; }

}  // namespace cluttertamp::cli
