// `cluttertamp guide`: an operator guides a reach problem from a browser (GRTC-HITL,
// run::GuidedSession behind a small HTTP API), or, with --auto, the automatic guidance
// (physics::generate_guidance) is written to a file for grtc to read.
#include <pthread.h>

#include <atomic>
#include <cstdlib>
#include <csignal>
#include <iomanip>
#include <iostream>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/guide_api.hpp"
#include "cli/http_server.hpp"
#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/physics/guidance.hpp"
#include "cluttertamp/run/guided_session.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "cluttertamp/io/text_file.hpp"


namespace cluttertamp::assets {
extern const char* const guide_html;  // framework/cli/guide.html, embedded at build time
}

namespace cluttertamp::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

int write_automatic_guidance(const GuideArgs& args, const Problem& problem) {
  if (!args.output) throw InputError({"--output", 0, 0}, "guide --auto needs --output FILE, the guidance file to write");
  io::check_writable(*args.output, "guidance file");
  const Scene& scene = problem.scene;
  const WorldState initial = WorldState::initial(scene);
  const physics::PushWorld world(scene, initial, physics::push_settings(problem));
  const Eigen::Vector3d start = world.start_pose();
  const physics::Guidance guidance = physics::generate_guidance(world, world.state_of(initial, start), world.hand(start).head<2>(),
                                                                args.max_guides, args.diameter);
  io::write_text_file(*args.output, io::guidance_to_yaml(scene, guidance), "guidance file");
  if (args.verbosity != Verbosity::quiet) {
    std::cout << "wrote " << args.output->string() << ": " << guidance.size() << " guide" << (guidance.size() == 1 ? "" : "s")
              << "\n";
    for (const physics::Guide& g : guidance) {
      std::cout << std::fixed << std::setprecision(3) << "  push " << scene.objects[g.object].id << " to (" << g.centre.x()
                << ", " << g.centre.y() << "), diameter " << g.diameter << " m\n";
    }
  }
  return 0;
}

// Stops the server on SIGINT or SIGTERM. Made before any other thread exists, it
// blocks the signals in every thread and takes them in its own, so the server stops
// outside a signal handler; a signal before the server exists stops it as it starts. A
// second signal ends the process at once.
class StopOnSignal {
 public:
  StopOnSignal() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, &old_);
    thread_ = std::thread([this] {
      int signal = 0;
      sigwait(&signals_, &signal);
      if (done_) return;
      requested_ = true;
      if (HttpServer* server = server_.load()) server->stop();
      sigwait(&signals_, &signal);
      if (!done_) std::_Exit(128 + signal);
    });
  }
  ~StopOnSignal() {
    done_ = true;
    pthread_kill(thread_.native_handle(), SIGTERM);
    thread_.join();
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

  /// The server a signal stops, until detach(), which must come before it is destroyed.
  void attach(HttpServer& server) {
    server_ = &server;
    if (requested_) server.stop();
  }
  void detach() { server_ = nullptr; }

 private:
  sigset_t signals_, old_;
  std::atomic<bool> done_{false}, requested_{false};
  std::atomic<HttpServer*> server_{nullptr};
  std::thread thread_;
};

int serve(const GuideArgs& args, const Problem& problem) {
  const fs::path dir = args.output.value_or("out/guide");
  if (dir.extension() == ".yaml" || dir.extension() == ".yml") {
    throw InputError({"--output", 0, 0}, "serving saves a session into a directory, not " + dir.string() +
                                             "; to write the automatic guidance to a file, add --auto");
  }
  io::check_writable_directory(dir, "session directory (--output)");
  StopOnSignal stop;
  const plugin::Registry registry(run::plugin_search_paths(problem, {}));
  run::GuidedSession session(problem, registry, {args.diameter, args.push_time});

  std::unique_ptr<GuideApi> api;
  HttpServer server(args.host, args.port, ServerLimits{},
                    [&api](const HttpRequest& request) { return api->respond(request); });
  stop.attach(server);
  struct Detach {
    StopOnSignal& stop;
    ~Detach() { stop.detach(); }
  } detach_before_the_server_goes{stop};
  const int port = server.port();
  GuideAccess access = guide_access(args.host, port, server.loopback(), server.wildcard());
  const std::string url = "http://" + access.hosts.back() + ":" + std::to_string(port) + "/?token=" + access.token;
  api = std::make_unique<GuideApi>(session, dir, std::move(access), assets::guide_html, args.verbosity == Verbosity::quiet);
  api->save();
  // The address line is what scripts (and the browser tests) wait for.
  std::cout << "guide: serving " << problem.name << " on " << url << " (Ctrl-C to stop); "
            << "the session is saved in " << dir.string() << std::endl;
  // Four threads: one may plan a push for seconds while the others keep answering.
  server.run(4);

  const Json final_state = Json::parse(api->finish_and_save());
  if (args.verbosity != Verbosity::quiet) {
    int ok = 0;
    for (const Json& in : final_state["inputs"]) ok += in["satisfied"].get<bool>() ? 1 : 0;
    std::cout << "guide: stopped; " << ok << " successful and " << final_state["inputs"].size() - ok << " failed inputs; "
              << (final_state["solved"].get<bool>() ? "the target was reached" : "the target was not reached")
              << "; saved in " << dir.string() << std::endl;
  }
  return final_state["solved"].get<bool>() ? run::ExitCode::solved : run::ExitCode::no_plan;
}

}  // namespace

int guide(const GuideArgs& args) {
  Problem problem = io::load_problem(args.problem);
  if (args.time_limit) problem.time_limit = *args.time_limit;
  if (args.seed) problem.seed = *args.seed;
  if (!std::holds_alternative<ReachTask>(problem.task)) {
    throw InputError({args.problem.string(), 0, 0}, "guide needs a problem with task: {reach: <target>}");
  }
  return args.automatic ? write_automatic_guidance(args, problem) : serve(args, problem);
}

}  // namespace cluttertamp::cli
