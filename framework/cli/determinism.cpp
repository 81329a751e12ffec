#include "cli/determinism.hpp"

#include <atomic>
#include <thread>
#include <vector>

#include <sched.h>

#include <nlohmann/json.hpp>

namespace cluttertamp::cli {

namespace {

using Json = nlohmann::json;

bool ignored(const std::string& key) {
  if (key == "time_limit") return false;
  return key == "time" || key == "problem" || key == "scene" ||
         (key.size() > 5 && key.compare(key.size() - 5, 5, "_time") == 0);
}

std::string shown(const Json& v) {
  std::string text = v.dump();
  return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

std::optional<std::string> difference(const Json& a, const Json& b, const std::string& at) {
  if (a.type() != b.type()) return at + ": " + shown(a) + " against " + shown(b);
  if (a.is_object()) {
    for (const auto& [key, value] : a.items()) {
      if (ignored(key)) continue;
      if (!b.contains(key)) return at + "/" + key + ": only in the first";
      if (auto d = difference(value, b.at(key), at + "/" + key)) return d;
    }
    for (const auto& [key, value] : b.items()) {
      if (!ignored(key) && !a.contains(key)) return at + "/" + key + ": only in the second";
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
  impl_->cpu = sched_getcpu();
  if (impl_->cpu < 0) impl_->cpu = 0;
  sched_getaffinity(0, sizeof impl_->before, &impl_->before);
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(impl_->cpu, &one);
  sched_setaffinity(0, sizeof one, &one);  // this thread; the burners inherit it
  for (int k = 0; k < threads; ++k) {
    impl_->burners.emplace_back([stop = &impl_->stop] {
      volatile std::uint64_t spin = 0;
      while (!stop->load(std::memory_order_relaxed)) spin = spin + 1;
    });
  }
}

CpuLoad::~CpuLoad() {
  impl_->stop = true;
  for (std::thread& t : impl_->burners) t.join();
  if (impl_->cpu >= 0) sched_setaffinity(0, sizeof impl_->before, &impl_->before);
}

int CpuLoad::cpu() const { return impl_->cpu; }

}  // namespace cluttertamp::cli
