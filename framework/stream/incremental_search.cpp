#include <cstdint>
#include <utility>
#include <vector>

#include "stream/searches.hpp"

namespace cluttertamp::stream::detail {

void incremental_search(SearchCore& core) {
  FactBase& base = core.facts();
  StreamEvaluator& evaluator = core.evaluator();
  plugin::PlanningContext& context = core.context();
  StreamSolution& out = core.out();
  for (;;) {
    evaluator.close_real();
    if (context.deadline.expired()) return;
    if (auto steps = core.plan_symbolic(false); steps && core.verify(*steps) && core.accept(std::move(*steps))) return;
    if (core.improved_enough()) return;  // checked after every search: improve_work 0 stops at once
    std::vector<int> open;
    for (int s = 0; s < static_cast<int>(core.problem().streams->streams.size()); ++s) {
      const StreamDecl::Kind kind = base.decl(s).kind;
      if (kind == StreamDecl::Kind::rule || kind == StreamDecl::Kind::function) continue;
      if (context.deadline.expired()) return;
      for (int id : evaluator.real_instances(s)) {
        if (!base.instance_at(id).exhausted) open.push_back(id);
      }
    }
    if (open.empty()) {
      out.reason = "no plan exists: every stream instance is exhausted";
      return core.settle();
    }
    ++out.statistics.level;
    for (int id : open) {
      if (context.deadline.expired()) return;
      const std::uint64_t checks_before = context.checks_done();
      evaluator.call(id);
      core.work() += core.options().call_cost + static_cast<double>(context.checks_done() - checks_before);
    }
  }
}

}  // namespace cluttertamp::stream::detail
