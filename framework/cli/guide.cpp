// `cluttertamp guide`: an operator guides a reach problem from a browser (GRTC-HITL,
// run::GuidedSession behind a small HTTP API), or, with --auto, the automatic guidance
// (physics::generate_guidance) is written to a file for grtc to read.
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <csignal>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/physics/guidance.hpp"
#include "cluttertamp/run/guided_session.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "cluttertamp/io/text_file.hpp"

// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen's headers after it.
#include <httplib.h>

namespace cluttertamp::assets {
extern const char* const guide_html;  // framework/cli/guide.html, embedded at build time
}

namespace cluttertamp::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

int write_automatic_guidance(const GuideArgs& args, const Problem& problem) {
  if (!args.output) throw InputError({"--output", 0, 0}, "guide --auto needs --output FILE, the guidance file to write");
  const Scene& scene = problem.scene;
  const WorldState initial = WorldState::initial(scene);
  const physics::PushWorld world(scene, initial);
  const Eigen::Vector3d exit = physics::gripper_at_exit(scene);
  const physics::Guidance guidance = physics::generate_guidance(world, world.state_of(initial, exit), exit.head<2>(),
                                                                args.max_guides, args.diameter);
  std::ofstream out(*args.output);
  if (!out) throw InputError({args.output->string(), 0, 0}, "cannot write the guidance file");
  out << io::guidance_to_yaml(scene, guidance);
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

// The session's files, rewritten after every input so that nothing is lost when the
// server is stopped. The replay page is a view: failing to write it is only reported.
void save(const run::GuidedSession& session, const fs::path& dir) {
  io::write_text_file(dir / "guidance.yaml", session.guidance_yaml(), "session file");
  const std::string result = session.result_json();
  io::write_text_file(dir / "result.json", result, "session file");
  if (!session.finished()) return;
  try {
    viewer::write_plan_html(dir / "plan.html", session.problem(), {result, "", (dir / "result.json").string()});
  } catch (const InputError& e) {
    std::cerr << "warning: no replay page: " << e.diagnostics().str();
  }
}

void reply(httplib::Response& res, int status, const Json& body) {
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json");
}

void error(httplib::Response& res, int status, const std::string& message) { reply(res, status, {{"error", message}}); }

// The body of a guide request: {"object": id, "x": m, "y": m, "diameter": m (optional)}.
std::optional<std::string> read_guide(const std::string& body, std::string& object, Eigen::Vector2d& centre,
                                      std::optional<double>& diameter) {
  const Json j = Json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return "the request body is not a JSON object";
  if (!j.contains("object") || !j["object"].is_string()) return "\"object\" must be an object id (a string)";
  if (!j.contains("x") || !j["x"].is_number() || !j.contains("y") || !j["y"].is_number()) return "\"x\" and \"y\" must be numbers (m)";
  if (j.contains("diameter") && !j["diameter"].is_number()) return "\"diameter\" must be a number (m)";
  object = j["object"].get<std::string>();
  centre = {j["x"].get<double>(), j["y"].get<double>()};
  if (j.contains("diameter")) diameter = j["diameter"].get<double>();
  return std::nullopt;
}

// Only JSON requests change the session: a page on another site can send a "simple"
// POST to localhost without asking, but not one with this content type.
bool json_request(const httplib::Request& req, httplib::Response& res) {
  if (req.get_header_value("Content-Type").rfind("application/json", 0) == 0) return true;
  error(res, 415, "send the request as Content-Type: application/json");
  return false;
}

// Stops the server on SIGINT or SIGTERM. Made before any other thread exists, it
// blocks the signals in every thread and takes them in its own, so the server stops
// outside a signal handler, once it runs; a second signal ends the process at once.
class StopOnSignal {
 public:
  explicit StopOnSignal(httplib::Server& server) {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, &old_);
    thread_ = std::thread([this, &server] {
      int signal = 0;
      sigwait(&signals_, &signal);
      if (done_) return;
      while (!server.is_running() && !done_) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      server.stop();
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

 private:
  sigset_t signals_, old_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

int serve(const GuideArgs& args, const Problem& problem) {
  const fs::path dir = args.output.value_or("out/guide");
  if (dir.extension() == ".yaml" || dir.extension() == ".yml") {
    throw InputError({"--output", 0, 0}, "serving saves a session into a directory, not " + dir.string() +
                                             "; to write the automatic guidance to a file, add --auto");
  }
  httplib::Server server;
  const StopOnSignal stop(server);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError({dir.string(), 0, 0}, "cannot create the session directory: " + ec.message());

  const plugin::Registry registry(run::plugin_search_paths(problem, {}));
  run::GuidedSession session(problem, registry, {args.diameter, args.push_time});
  save(session, dir);
  // One request at a time plans; the others read the state as it was last saved
  // (planning holds `planning`, never `shown`), or are told the session is busy.
  std::mutex planning, shown;
  std::string state = session.state_json();
  // Publishes the session's state to readers; returns it for the reply.
  auto show = [&] {
    std::string text = session.state_json();
    const std::lock_guard lock(shown);
    state = text;
    return Json::parse(text);
  };
  const bool quiet = args.verbosity == Verbosity::quiet;

  server.set_keep_alive_timeout(1);  // s: stopping waits for open connections to close
  server.Get("/", [](const httplib::Request&, httplib::Response& res) { res.set_content(assets::guide_html, "text/html; charset=utf-8"); });
  server.Get("/api/state", [&](const httplib::Request&, httplib::Response& res) {
    const std::lock_guard lock(shown);
    res.set_content(state, "application/json");
  });
  server.Post("/api/guide", [&](const httplib::Request& req, httplib::Response& res) {
    if (!json_request(req, res)) return;
    std::string object;
    Eigen::Vector2d centre;
    std::optional<double> diameter;
    if (const auto bad = read_guide(req.body, object, centre, diameter)) return error(res, 400, *bad);
    std::unique_lock lock(planning, std::try_to_lock);
    if (!lock) return error(res, 409, "busy: another request is being planned");
    const run::GuidedSession::Outcome out = session.guide(object, centre, diameter);
    if (!out.planned) return error(res, session.finished() ? 409 : 400, out.message);
    save(session, dir);
    const Json now = show();
    if (!quiet) std::cout << (out.ok ? "  ok     " : "  failed ") << out.message << std::endl;
    reply(res, 200, {{"ok", out.ok}, {"message", out.message}, {"state", now}});
  });
  server.Post("/api/finish", [&](const httplib::Request& req, httplib::Response& res) {
    if (!json_request(req, res)) return;
    std::unique_lock lock(planning, std::try_to_lock);
    if (!lock) return error(res, 409, "busy: another request is being planned");
    const run::GuidedSession::Outcome out = session.finish();
    if (!out.planned) return error(res, 409, out.message);
    save(session, dir);
    const Json now = show();
    if (!quiet) std::cout << (out.ok ? "  SOLVED " : "  NOT SOLVED ") << out.message << "\n  saved " << dir.string() << std::endl;
    reply(res, 200, {{"ok", out.ok}, {"message", out.message}, {"state", now}});
  });
  server.Get("/replay", [&](const httplib::Request&, httplib::Response& res) {
    const fs::path page = dir / "plan.html";
    const std::lock_guard lock(shown);  // the page is written before the state says finished
    if (!Json::parse(state)["finished"].get<bool>() || !fs::exists(page)) {
      return error(res, 404, "the replay exists once the robot has finished");
    }
    res.set_content(io::read_text_file(page, "replay page"), "text/html; charset=utf-8");
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr e) {
    try {
      std::rethrow_exception(e);
    } catch (const std::exception& x) {
      error(res, 500, std::string("internal error: ") + x.what());
    } catch (...) {
      error(res, 500, "internal error");
    }
  });

  const int port = args.port == 0 ? server.bind_to_any_port(args.host) : (server.bind_to_port(args.host, args.port) ? args.port : -1);
  if (port < 0) throw InputError({"--port", 0, 0}, "cannot listen on " + args.host + ":" + std::to_string(args.port) + " (in use? try --port 0)");
  // The address line is what scripts (and the browser tests) wait for.
  std::cout << "guide: serving " << problem.name << " on http://" << args.host << ":" << port << "/ (Ctrl-C to stop); "
            << "the session is saved in " << dir.string() << std::endl;
  server.listen_after_bind();

  const std::lock_guard lock(planning);
  save(session, dir);
  const Json final_state = Json::parse(session.state_json());
  if (!quiet) {
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
