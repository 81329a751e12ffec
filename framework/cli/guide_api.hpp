#pragma once
// The HTTP API of `cluttertamp guide` over a run::GuidedSession: routes, the checks
// that keep other web pages out (Host, Origin, the session token), and saving the
// session after every input. Independent of sockets, so that it can be fuzzed.

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "cli/http_server.hpp"
#include "cluttertamp/run/guided_session.hpp"

namespace cluttertamp::cli {

/// Who may talk to the session.
struct GuideAccess {
  /// Host names (no port) accepted in Host and Origin, e.g. 127.0.0.1 and localhost.
  std::vector<std::string> hosts;
  int port = 0;           ///< the port every accepted Host and Origin names
  bool any_ip = false;    ///< also accept any IP literal (a server bound to every interface)
  std::string token;      ///< every state-changing request carries it (X-Guide-Token)
};

/// The access of a server bound to `host`:`port` with a fresh random token: loopback
/// names for a loopback address, the address itself otherwise, any IP literal for a
/// wildcard address.
GuideAccess guide_access(const std::string& host, int port, bool loopback, bool wildcard);

/// Answers the guide page's requests. Thread-safe: one request plans at a time (another
/// is answered 409), the others read the state as last saved.
class GuideApi {
 public:
  /// `session` and `page_html` outlive the API; the session is saved into `dir` after
  /// every input. `quiet`: nothing printed per input.
  GuideApi(run::GuidedSession& session, std::filesystem::path dir, GuideAccess access, const char* page_html, bool quiet);

  /// The answer to one request: 403 for a foreign Host or Origin or a state-changing
  /// request without the token, 404/405 for unknown routes, 400/409/415 with a reason.
  HttpResponse respond(const HttpRequest& request);

  /// Saves the session's files (guidance.yaml, result.json, and plan.html once finished).
  void save();

  /// Waits for a request that is planning, then saves. Returns the state JSON.
  std::string finish_and_save();

 private:
  HttpResponse guide(const HttpRequest& request);
  HttpResponse finish(const HttpRequest& request);
  HttpResponse replay();
  HttpResponse publish(const run::GuidedSession::Outcome& out, bool finishing);
  bool allowed_host(const std::string& host_and_port) const;

  run::GuidedSession& session_;
  std::filesystem::path dir_;
  GuideAccess access_;
  const char* page_html_;
  bool quiet_;
  std::mutex planning_, shown_;
  std::string state_;  ///< as last published; guarded by shown_
};

}  // namespace cluttertamp::cli
