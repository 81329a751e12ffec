#pragma once
// A small HTTP/1.1 server for the browser pages (`guide`), built on Boost.Beast so that
// slow or hostile clients cannot starve it: every request must arrive whole within a
// deadline, bodies and headers are bounded, open connections are counted and bounded,
// and waiting for a slow client holds no thread (asynchronous I/O).

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace cluttertamp::cli {

/// What a handler sees of a request. Header names are lower case.
struct HttpRequest {
  std::string method;  ///< "GET", "POST", ...
  std::string target;  ///< path and query, as sent ("/api/state?x=1")
  std::map<std::string, std::string> headers;
  std::string body;

  /// The header's value, empty when absent.
  std::string header(const std::string& lower_case_name) const;
  /// The target without its query.
  std::string path() const;
};

/// A handler's answer.
struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

/// Bounds that keep a server answerable whatever its clients do.
struct ServerLimits {
  std::size_t max_body_bytes = 64 * 1024;    ///< larger bodies: 413, connection closed
  std::size_t max_header_bytes = 16 * 1024;  ///< larger headers: 431, connection closed
  /// A request (headers and body) must arrive whole within this time of the previous
  /// answer (or of the connection); otherwise the connection is closed.
  std::chrono::milliseconds request_timeout{10000};
  /// Connections open at once; one more is answered 503 and closed.
  std::size_t max_connections = 256;
};

using HttpHandler = std::function<HttpResponse(const HttpRequest&)>;

/// Serves `handler` on one address. The handler runs on one of the server's threads and
/// may block (planning); the other threads keep answering. An exception escaping the
/// handler is answered 500 with its message.
class HttpServer {
 public:
  /// Binds and listens on host:port (port 0: any free port). Throws InputError naming
  /// --host or --port when the address is not an IP address (or "localhost") or the port
  /// cannot be had — another process listening on it included (no port sharing).
  HttpServer(const std::string& host, int port, ServerLimits limits, HttpHandler handler);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// The port listened on.
  int port() const;
  /// True when bound to a loopback address; false for a wildcard or another interface.
  bool loopback() const;
  /// True when bound to every interface (0.0.0.0 or ::).
  bool wildcard() const;

  /// Serves on `threads` threads (the caller's among them) until stop().
  void run(int threads);
  /// Stops serving: run() returns once the handlers running now have returned. Safe from
  /// any thread, also before run().
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Parses `raw` as one HTTP request with the server's parser and limits and answers it
/// as the server would (400, 413, 431 for malformed or oversized requests). For fuzzing
/// the request path without sockets.
HttpResponse respond_to_bytes(std::string_view raw, const ServerLimits& limits, const HttpHandler& handler);

}  // namespace cluttertamp::cli
