// Fuzz target: bytes sent to the guide server, parsed with its parser and limits and
// answered by its API over a session of problems/push/shelf10/p01 (short planning
// times; a finished session is started anew). Every input gets an HTTP answer.
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "cli/guide_api.hpp"
#include "cli/http_server.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "fuzz_support.hpp"

namespace {
namespace ct = cluttertamp;

// The session token of the fuzzing session, fixed so that the seed corpus can carry it.
constexpr const char* kToken = "00112233445566778899aabbccddeeff";

struct Served {
  ct::plugin::Registry registry{ct::plugin::Registry::default_search_paths()};
  std::unique_ptr<ct::run::GuidedSession> session;
  std::unique_ptr<ct::cli::GuideApi> api;

  void start() {
    ct::Problem problem = ct::io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p01.yaml");
    problem.time_limit = 0.2;
    api.reset();
    session = std::make_unique<ct::run::GuidedSession>(problem, registry, ct::run::GuidedSessionOptions{0.1, 0.05});
    ct::cli::GuideAccess access = ct::cli::guide_access("127.0.0.1", 8080, true, false);
    access.token = kToken;
    api = std::make_unique<ct::cli::GuideApi>(*session, ct::fuzz::workspace() / "guide", access, "<html></html>", true);
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Served served;
  if (!served.session || served.session->finished()) served.start();
  ct::cli::ServerLimits limits;
  const ct::cli::HttpResponse answer = ct::cli::respond_to_bytes(ct::fuzz::text(data, size), limits,
                                                                 [](const ct::cli::HttpRequest& r) { return served.api->respond(r); });
  if (answer.status < 200 || answer.status > 599) {
    std::fprintf(stderr, "an answer with status %d\n", answer.status);
    std::abort();
  }
  return 0;
}
