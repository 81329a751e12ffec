// A pddl task's files parsed once, and the one check that its streams and its
// problem file's bindings agree.
#include "cluttertamp/stream/stream_task.hpp"

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"

namespace cluttertamp::stream {

std::shared_ptr<const ParsedTask> parse_task(const PddlTask& task) {
  auto parsed = std::make_shared<ParsedTask>();
  parsed->domain = pddl::load_domain(task.domain);
  parsed->warnings = parsed->domain.warnings;
  if (task.problem) parsed->problem = pddl::load_problem(*task.problem, parsed->domain);
  if (task.streams) {
    parsed->streams = load_stream_file(*task.streams, &parsed->domain);
    parsed->warnings.insert(parsed->warnings.end(), parsed->streams->warnings.begin(), parsed->streams->warnings.end());
  }
  return parsed;
}

std::shared_ptr<const ParsedTask> parsed_task(const PddlTask& task) {
  return task.parsed ? task.parsed : parse_task(task);
}

void check_streams_bound(const StreamFile& streams, const std::function<bool(const std::string&)>& is_bound,
                         Diagnostics& diagnostics) {
  for (const StreamDecl& s : streams.streams) {
    if (s.kind == StreamDecl::Kind::rule || is_bound(s.name)) continue;
    diagnostics.error(s.where, "'" + s.name + "' is bound to no stream_sampler: it has no code behind it (bind it "
                               "under plugins: streams: of the problem file)");
  }
}

void check_bindings_declared(const StreamFile& streams, const std::map<std::string, PluginChoice>& bindings,
                             Diagnostics& diagnostics) {
  for (const auto& [name, choice] : bindings) {
    if (!streams.find(pddl::lower_name(name))) {
      diagnostics.error(choice.where, "stream '" + name + "' is not declared in " + streams.file);
    }
  }
}

}  // namespace cluttertamp::stream
