// The guide page's HTTP server and API under hostile clients: bounded requests, slow
// clients that cannot keep others out, a port that is not shared, and only this
// server's own address with the session token changing the session.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/guide_api.hpp"
#include "cli/http_server.hpp"
#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/guided_session.hpp"

namespace cluttertamp {
namespace {

namespace fs = std::filesystem;
using cli::HttpRequest;
using cli::HttpResponse;
using cli::HttpServer;
using cli::ServerLimits;

// A connected socket to 127.0.0.1:port whose reads give up after 30 s (a bound for a
// broken server, never reached by a working one).
int connect_to(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return -1;
  }
  timeval timeout{30, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  return fd;
}

bool send_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// Everything the server sends until it closes the connection.
std::string read_to_end(int fd) {
  std::string out;
  char buffer[4096];
  ssize_t n;
  while ((n = recv(fd, buffer, sizeof buffer, 0)) > 0) out.append(buffer, static_cast<std::size_t>(n));
  return out;
}

// Sends one request with Connection: close; the whole response.
std::string http_exchange(int port, const std::string& request) {
  const int fd = connect_to(port);
  if (fd < 0) return "no connection";
  send_all(fd, request);
  std::string response = read_to_end(fd);
  close(fd);
  return response;
}

int status_of(const std::string& response) {
  return response.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(response.substr(9, 3)) : -1;
}

std::string get(const std::string& path, int port) {
  return "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n\r\n";
}

// A server answering "hello" to everything, run on two threads for the test's life.
class Served {
 public:
  explicit Served(ServerLimits limits)
      : server_("127.0.0.1", 0, limits, [](const HttpRequest& r) { return HttpResponse{200, "text/plain", "hello " + r.path()}; }),
        thread_([this] { server_.run(2); }) {}
  ~Served() {
    server_.stop();
    thread_.join();
  }
  int port() const { return server_.port(); }

 private:
  HttpServer server_;
  std::thread thread_;
};

TEST(GuideServer, AnswersRequestsAndRefusesOversizedAndMalformedOnes) {
  ServerLimits limits;
  limits.max_body_bytes = 1000;
  limits.max_header_bytes = 2000;
  const Served served(limits);
  const int port = served.port();
  const std::string ok = http_exchange(port, get("/a", port));
  EXPECT_EQ(status_of(ok), 200) << ok;
  EXPECT_NE(ok.find("hello /a"), std::string::npos) << ok;
  const std::string body(5000, 'x');
  const std::string big = http_exchange(port, "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 5000\r\n\r\n" + body);
  EXPECT_EQ(status_of(big), 413) << big;
  const std::string header = http_exchange(port, "GET / HTTP/1.1\r\nHost: h\r\nX-Long: " + std::string(5000, 'y') + "\r\n\r\n");
  EXPECT_EQ(status_of(header), 431) << header;
  const std::string garbage = http_exchange(port, "\x01\x02 nonsense\r\n\r\n");
  EXPECT_EQ(status_of(garbage), 400) << garbage;
  EXPECT_EQ(status_of(http_exchange(port, get("/still-here", port))), 200);
}

// Slowloris: more connections than the bound, each sending headers without end. A
// client that sends its request at once is still answered: it takes the place of the
// connection that has waited longest.
TEST(GuideServer, ClientsHoldingConnectionsWithoutSendingDoNotKeepOthersOut) {
  ServerLimits limits;
  limits.max_connections = 16;
  limits.request_timeout = std::chrono::seconds(600);  // only the bound protects here
  const Served served(limits);
  const int port = served.port();
  std::vector<int> slow;
  for (int i = 0; i < 40; ++i) {
    const int fd = connect_to(port);
    ASSERT_GE(fd, 0);
    send_all(fd, "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ");
    slow.push_back(fd);
  }
  for (int k = 0; k < 3; ++k) {
    const std::string answer = http_exchange(port, get("/me", port));
    EXPECT_EQ(status_of(answer), 200) << answer;
  }
  for (const int fd : slow) close(fd);
}

// A request must arrive whole within the deadline; a connection that sends part of one
// is closed without an answer.
TEST(GuideServer, AConnectionThatDoesNotSendItsRequestInTimeIsClosed) {
  ServerLimits limits;
  limits.request_timeout = std::chrono::milliseconds(200);
  const Served served(limits);
  const int fd = connect_to(served.port());
  ASSERT_GE(fd, 0);
  send_all(fd, "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n");
  char byte;
  errno = 0;
  const ssize_t n = recv(fd, &byte, 1, 0);
  EXPECT_EQ(n, 0) << "closed by the server (not the test's 30 s bound: errno " << errno << ")";
  close(fd);
}

// A port another server listens on is refused, not shared (no SO_REUSEPORT).
TEST(GuideServer, APortInUseIsRefused) {
  const Served first(ServerLimits{});
  try {
    HttpServer second("127.0.0.1", first.port(), ServerLimits{}, [](const HttpRequest&) { return HttpResponse{}; });
    FAIL() << "a second server listens on port " << first.port();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Address already in use"), std::string::npos) << e.what();
  }
  EXPECT_THROW(HttpServer("attacker.example", 0, ServerLimits{}, [](const HttpRequest&) { return HttpResponse{}; }),
               InputError);
}

TEST(GuideServer, TheFuzzEntryAnswersAsTheServerDoes) {
  ServerLimits limits;
  limits.max_body_bytes = 10;
  const cli::HttpHandler echo = [](const HttpRequest& r) { return HttpResponse{200, "text/plain", r.method + " " + r.body}; };
  EXPECT_EQ(cli::respond_to_bytes("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\n\r\nabc", limits, echo).body, "POST abc");
  EXPECT_EQ(cli::respond_to_bytes("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 30\r\n\r\nabc", limits, echo).status, 413);
  EXPECT_EQ(cli::respond_to_bytes("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 5\r\n\r\nabc", limits, echo).status, 400);
  EXPECT_EQ(cli::respond_to_bytes("GET / HTTP/1.1\r\nHost", limits, echo).status, 400);
  EXPECT_EQ(cli::respond_to_bytes("", limits, echo).status, 400);
}

class GuideApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / "cluttertamp_guide_api";
    fs::remove_all(dir_);
    Problem problem = io::load_problem(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p01.yaml");
    session_ = std::make_unique<run::GuidedSession>(problem, registry_);
    access_ = cli::guide_access("127.0.0.1", 8080, true, false);
    api_ = std::make_unique<cli::GuideApi>(*session_, dir_, access_, "<html>page</html>", true);
  }
  void TearDown() override { fs::remove_all(dir_); }

  HttpResponse ask(const std::string& method, const std::string& target, std::map<std::string, std::string> headers,
                   const std::string& body = "") {
    HttpRequest r{method, target, std::move(headers), body};
    return api_->respond(r);
  }

  fs::path dir_;
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
  std::unique_ptr<run::GuidedSession> session_;
  cli::GuideAccess access_;
  std::unique_ptr<cli::GuideApi> api_;
};

// DNS rebinding and cross-site requests: only this server's own address, from its own
// page, with the session token, changes the session.
TEST_F(GuideApiTest, OnlyItsOwnAddressWithTheTokenChangesTheSession) {
  const std::string token = access_.token;
  ASSERT_EQ(token.size(), 32u);
  EXPECT_NE(cli::guide_access("127.0.0.1", 8080, true, false).token, token) << "a fresh token per session";
  EXPECT_EQ(ask("GET", "/", {{"host", "127.0.0.1:8080"}}).status, 200);
  EXPECT_EQ(ask("GET", "/api/state", {{"host", "localhost:8080"}}).status, 200);
  const HttpResponse rebound = ask("GET", "/api/state", {{"host", "attacker.example:8080"}});
  EXPECT_EQ(rebound.status, 403);
  EXPECT_NE(rebound.body.find("only requests to its own address"), std::string::npos) << rebound.body;
  EXPECT_EQ(ask("GET", "/api/state", {{"host", "127.0.0.1:9999"}}).status, 403) << "another port";
  EXPECT_EQ(ask("GET", "/api/state", {}).status, 403) << "no Host";
  const std::map<std::string, std::string> own{{"host", "127.0.0.1:8080"}, {"content-type", "application/json"},
                                               {"x-guide-token", token}};
  auto with = [&](std::map<std::string, std::string> h, const std::string& key, const std::string& value) {
    h[key] = value;
    return h;
  };
  EXPECT_EQ(ask("POST", "/api/finish", with(own, "origin", "http://attacker.example:8080"), "{}").status, 403);
  EXPECT_EQ(ask("POST", "/api/finish", with(own, "origin", "null"), "{}").status, 403);
  EXPECT_EQ(ask("POST", "/api/finish", with(own, "x-guide-token", ""), "{}").status, 403);
  EXPECT_EQ(ask("POST", "/api/finish", with(own, "x-guide-token", std::string(32, '0')), "{}").status, 403);
  EXPECT_EQ(ask("POST", "/api/guide", with(own, "content-type", "text/plain"), "{}").status, 415);
  const HttpResponse unknown =
      ask("POST", "/api/guide", with(own, "origin", "http://127.0.0.1:8080"), R"({"object": "ghost", "x": 0.8, "y": 0})");
  EXPECT_EQ(unknown.status, 400) << "past every check, the session answers: " << unknown.body;
  EXPECT_NE(unknown.body.find("no object 'ghost'"), std::string::npos) << unknown.body;
  EXPECT_EQ(ask("GET", "/api/guide", own).status, 405);
  EXPECT_EQ(ask("POST", "/api/state", own).status, 405);
  EXPECT_EQ(ask("GET", "/nothing", own).status, 404);
  EXPECT_EQ(ask("GET", "/replay", own).status, 404) << "not finished";
  EXPECT_FALSE(session_->finished());
}

}  // namespace
}  // namespace cluttertamp
