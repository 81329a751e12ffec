#include "cli/guide_api.hpp"

#include <arpa/inet.h>

#include <iostream>
#include <optional>
#include <random>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/viewer/plan_html.hpp"

namespace cluttertamp::cli {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

HttpResponse reply(int status, const Json& body) {
  return {status, "application/json", body.dump(-1, ' ', false, Json::error_handler_t::replace)};
}

HttpResponse error(int status, const std::string& message) { return reply(status, {{"error", message}}); }

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

bool ip_literal(const std::string& host) {
  unsigned char address[16];
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    return inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), address) == 1;
  }
  return inet_pton(AF_INET, host.c_str(), address) == 1;
}

// Equal in time independent of where they first differ: the token is a secret.
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

}  // namespace

GuideAccess guide_access(const std::string& host, int port, bool loopback, bool wildcard) {
  GuideAccess access;
  access.port = port;
  if (loopback) access.hosts = {"127.0.0.1", "localhost", "[::1]"};
  if (wildcard) {
    access.any_ip = true;
    access.hosts.push_back("localhost");
  }
  const bool v6 = host.find(':') != std::string::npos;
  access.hosts.push_back(v6 ? "[" + host + "]" : host);
  // A secret, not a planning decision: the seed and the work counters stay the only inputs of planning.
  std::random_device device;
  static constexpr char kHex[] = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) access.token += kHex[device() % 16];
  return access;
}

GuideApi::GuideApi(run::GuidedSession& session, fs::path dir, GuideAccess access, const char* page_html, bool quiet)
    : session_(session), dir_(std::move(dir)), access_(std::move(access)), page_html_(page_html), quiet_(quiet),
      state_(session.state_json()) {}

bool GuideApi::allowed_host(const std::string& host_and_port) const {
  const std::size_t colon = host_and_port.rfind(':');
  if (colon == std::string::npos || host_and_port.find(']', colon) != std::string::npos) return false;
  const std::string host = host_and_port.substr(0, colon), port = host_and_port.substr(colon + 1);
  if (port != std::to_string(access_.port)) return false;
  for (const std::string& h : access_.hosts) {
    if (h == host) return true;
  }
  return access_.any_ip && ip_literal(host);
}

HttpResponse GuideApi::respond(const HttpRequest& request) {
  // DNS rebinding: a page of another site, its name pointed at this machine, sends its
  // own name as Host. Only this server's own addresses are answered.
  if (!allowed_host(request.header("host"))) {
    return error(403, "this server answers only requests to its own address (Host: 127.0.0.1:" +
                          std::to_string(access_.port) + " or localhost:" + std::to_string(access_.port) + ")");
  }
  const std::string origin = request.header("origin");
  if (!origin.empty() && !(origin.rfind("http://", 0) == 0 && allowed_host(origin.substr(7)))) {
    return error(403, "requests from pages of other origins are refused (Origin: " + origin + ")");
  }
  const std::string path = request.path();
  const bool get = request.method == "GET";
  if (path == "/" || path == "/index.html") {
    if (!get) return error(405, "use GET");
    return {200, "text/html; charset=utf-8", page_html_};
  }
  if (path == "/api/state") {
    if (!get) return error(405, "use GET");
    const std::lock_guard lock(shown_);
    return {200, "application/json", state_};
  }
  if (path == "/replay") {
    if (!get) return error(405, "use GET");
    return replay();
  }
  if (path != "/api/guide" && path != "/api/finish") return error(404, "no such page: " + path);
  if (request.method != "POST") return error(405, "use POST");
  // What changes the session carries the token of the address guide printed, which
  // another page cannot know; and is JSON, which another page cannot send unasked.
  if (!same_secret(request.header("x-guide-token"), access_.token)) {
    return error(403, "missing or wrong session token: open the address `guide` printed (it ends in ?token=...)");
  }
  if (request.header("content-type").rfind("application/json", 0) != 0) {
    return error(415, "send the request as Content-Type: application/json");
  }
  return path == "/api/guide" ? guide(request) : finish(request);
}

HttpResponse GuideApi::guide(const HttpRequest& request) {
  std::string object;
  Eigen::Vector2d centre;
  std::optional<double> diameter;
  if (const auto bad = read_guide(request.body, object, centre, diameter)) return error(400, *bad);
  std::unique_lock lock(planning_, std::try_to_lock);
  if (!lock) return error(409, "busy: another request is being planned");
  const run::GuidedSession::Outcome out = session_.guide(object, centre, diameter);
  if (!out.planned) return error(session_.finished() ? 409 : 400, out.message);
  return publish(out, false);
}

HttpResponse GuideApi::finish(const HttpRequest&) {
  std::unique_lock lock(planning_, std::try_to_lock);
  if (!lock) return error(409, "busy: another request is being planned");
  const run::GuidedSession::Outcome out = session_.finish();
  if (!out.planned) return error(409, out.message);
  return publish(out, true);
}

// Saves, then shows the new state to readers (the files exist before the state says so).
HttpResponse GuideApi::publish(const run::GuidedSession::Outcome& out, bool finishing) {
  save();
  std::string text = session_.state_json();
  Json now = Json::parse(text);
  {
    const std::lock_guard lock(shown_);
    state_ = std::move(text);
  }
  if (!quiet_) {
    if (finishing) std::cout << (out.ok ? "  SOLVED " : "  NOT SOLVED ") << out.message << "\n  saved " << dir_.string() << std::endl;
    else std::cout << (out.ok ? "  ok     " : "  failed ") << out.message << std::endl;
  }
  return reply(200, {{"ok", out.ok}, {"message", out.message}, {"state", std::move(now)}});
}

HttpResponse GuideApi::replay() {
  const fs::path page = dir_ / "plan.html";
  const std::lock_guard lock(shown_);  // the page is written before the state says finished
  if (!Json::parse(state_)["finished"].get<bool>() || !fs::exists(page)) {
    return error(404, "the replay exists once the robot has finished");
  }
  return {200, "text/html; charset=utf-8", io::read_text_file(page, "replay page")};
}

// The session's files, rewritten after every input so that nothing is lost when the
// server is stopped. The replay page is a view: failing to write it is only reported.
void GuideApi::save() {
  io::write_text_file(dir_ / "guidance.yaml", session_.guidance_yaml(), "session file");
  const std::string result = session_.result_json();
  io::write_text_file(dir_ / "result.json", result, "session file");
  if (!session_.finished()) return;
  try {
    viewer::write_plan_html(dir_ / "plan.html", session_.problem(), {result, "", (dir_ / "result.json").string()});
  } catch (const io::WriteError& e) {
    std::cerr << "warning: no replay page: " << e.what() << "\n";
  }
}

std::string GuideApi::finish_and_save() {
  const std::lock_guard lock(planning_);
  save();
  return session_.state_json();
}

}  // namespace cluttertamp::cli
