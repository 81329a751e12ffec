#include "cli/http_server.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <list>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::cli {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

std::string HttpRequest::header(const std::string& lower_case_name) const {
  const auto it = headers.find(lower_case_name);
  return it == headers.end() ? std::string() : it->second;
}

std::string HttpRequest::path() const { return target.substr(0, target.find('?')); }

namespace {

using Parser = http::request_parser<http::string_body>;

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

HttpResponse error_response(int status, const std::string& message) {
  std::string body = "{\"error\": \"";
  for (const char c : message) {
    if (c == '"' || c == '\\') body += '\\';
    body += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
  }
  return {status, "application/json", body + "\"}"};
}

void configure(Parser& parser, const ServerLimits& limits) {
  parser.header_limit(static_cast<std::uint32_t>(std::min<std::size_t>(limits.max_header_bytes, UINT32_MAX)));
  parser.body_limit(limits.max_body_bytes);
}

// The answer to a request the parser refused, or nothing when the connection should
// just close (the client went away, or was too slow).
std::optional<HttpResponse> refusal(const beast::error_code& ec) {
  if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == net::error::operation_aborted ||
      ec == net::error::connection_reset || ec == net::error::eof) {
    return std::nullopt;
  }
  if (ec == http::error::body_limit) return error_response(413, "the request body is too large");
  if (ec == http::error::header_limit) return error_response(431, "the request headers are too large");
  return error_response(400, "malformed HTTP request: " + ec.message());
}

HttpRequest to_request(const http::request<http::string_body>& message) {
  HttpRequest request;
  request.method = std::string(message.method_string());
  request.target = std::string(message.target());
  for (const auto& field : message) {
    const auto name = field.name_string();
    std::string& value = request.headers[lower(std::string_view(name.data(), name.size()))];
    // A repeated header keeps every value, so that a check comparing it whole fails.
    if (!value.empty()) value += ",";
    value += std::string(field.value());
  }
  request.body = message.body();
  return request;
}

HttpResponse call(const HttpHandler& handler, const HttpRequest& request) {
  try {
    return handler(request);
  } catch (const std::exception& e) {
    return error_response(500, std::string("internal error: ") + e.what());
  } catch (...) {
    return error_response(500, "internal error");
  }
}

class Connection;

struct Shared {
  ServerLimits limits;
  HttpHandler handler;
  std::atomic<std::size_t> open{0};
  // Connections waiting for their request, longest waiting first: at the bound, a new
  // connection takes the place of the first of them, so that clients that hold
  // connections open without sending cannot keep out those that send.
  std::mutex waiting_mutex;
  std::list<std::weak_ptr<Connection>> waiting;
};

// One client connection: read a request within the deadline, answer it, repeat while
// the client keeps the connection alive.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket&& socket, std::shared_ptr<Shared> shared) : stream_(std::move(socket)), shared_(std::move(shared)) {
    ++shared_->open;
  }
  ~Connection() {
    stop_waiting();
    --shared_->open;
  }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  void start() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] { self->read(); });
  }

  // Called with waiting_mutex held, when the server took it off the waiting list.
  void forget_waiting() { waiting_.reset(); }

  // Closes the connection on its own strand (from another thread).
  void evict() {
    net::post(stream_.get_executor(), [self = shared_from_this()] { self->close(); });
  }

 private:
  void read() {
    start_waiting();
    parser_.emplace();
    configure(*parser_, shared_->limits);
    stream_.expires_after(shared_->limits.request_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(const beast::error_code& ec) {
    stop_waiting();
    if (ec) {
      if (const std::optional<HttpResponse> answer = refusal(ec)) return send(*answer, false);
      return close();
    }
    const http::request<http::string_body>& message = parser_->get();
    send(call(shared_->handler, to_request(message)), message.keep_alive());
  }

  void send(const HttpResponse& answer, bool keep_alive) {
    auto response = std::make_shared<http::response<http::string_body>>(static_cast<http::status>(answer.status), 11);
    response->set(http::field::content_type, answer.content_type);
    response->set(http::field::cache_control, "no-store");
    response->keep_alive(keep_alive);
    response->body() = answer.body;
    response->prepare_payload();
    stream_.expires_after(shared_->limits.request_timeout);
    http::async_write(stream_, *response, [self = shared_from_this(), response, keep_alive](beast::error_code ec, std::size_t) {
      if (ec || !keep_alive) return self->close();
      self->read();
    });
  }

  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_.socket().close(ignored);
  }

  void start_waiting() {
    const std::lock_guard lock(shared_->waiting_mutex);
    waiting_ = shared_->waiting.insert(shared_->waiting.end(), weak_from_this());
  }
  void stop_waiting() {
    const std::lock_guard lock(shared_->waiting_mutex);
    if (waiting_) shared_->waiting.erase(*waiting_);
    waiting_.reset();
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<std::list<std::weak_ptr<Connection>>::iterator> waiting_;  // guarded by waiting_mutex
  std::optional<Parser> parser_;
  std::shared_ptr<Shared> shared_;
};

constexpr std::string_view kBusy =
    "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nContent-Length: 44\r\nConnection: close\r\n\r\n"
    "{\"error\": \"too many connections, try again\"}";

}  // namespace

// Handlers of the server's own (accepting, stopping) hold a plain pointer: they run
// only inside run(), within the server's life, and a shared one would keep the server
// alive from inside its own io_context.
struct HttpServer::Impl {
  net::io_context context;
  tcp::acceptor acceptor{context};
  std::shared_ptr<Shared> shared = std::make_shared<Shared>();
  bool loopback = false, wildcard = false;

  // Closes the connection that has waited longest for its request; false when every
  // open connection is being answered.
  bool evict_longest_waiting() {
    std::shared_ptr<Connection> longest;
    {
      const std::lock_guard lock(shared->waiting_mutex);
      // An expired entry belongs to a connection being destroyed: its destructor,
      // waiting for this lock, erases it.
      for (auto it = shared->waiting.begin(); it != shared->waiting.end(); ++it) {
        if ((longest = it->lock())) {
          shared->waiting.erase(it);
          longest->forget_waiting();
          break;
        }
      }
    }
    if (!longest) return false;
    longest->evict();
    return true;
  }

  void accept() {
    acceptor.async_accept(net::make_strand(context), [self = this](beast::error_code ec, tcp::socket socket) {
      if (ec == net::error::operation_aborted || !self->acceptor.is_open()) return;
      if (!ec) {
        if (self->shared->open.load() >= self->shared->limits.max_connections && !self->evict_longest_waiting()) {
          beast::error_code ignored;
          net::write(socket, net::buffer(kBusy.data(), kBusy.size()), ignored);
          socket.shutdown(tcp::socket::shutdown_both, ignored);
        } else {
          std::make_shared<Connection>(std::move(socket), self->shared)->start();
        }
      }
      self->accept();
    });
  }
};

HttpServer::HttpServer(const std::string& host, int port, ServerLimits limits, HttpHandler handler)
    : impl_(std::make_unique<Impl>()) {
  impl_->shared->limits = limits;
  impl_->shared->handler = std::move(handler);
  beast::error_code ec;
  net::ip::address address = net::ip::make_address(host == "localhost" ? "127.0.0.1" : host, ec);
  if (ec) throw InputError({"--host", 0, 0}, "'" + host + "' is not an IP address (127.0.0.1, ::1, 0.0.0.0, ...) or localhost");
  impl_->loopback = address.is_loopback();
  impl_->wildcard = address.is_unspecified();
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(port));
  const std::string where = host + ":" + std::to_string(port);
  tcp::acceptor& acceptor = impl_->acceptor;
  acceptor.open(endpoint.protocol(), ec);
  // SO_REUSEADDR only (a restarted server need not wait out TIME_WAIT); never
  // SO_REUSEPORT, which would let a second server share the port and split the requests.
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    const std::string hint = ec == net::error::address_in_use ? " (another server listens on it; try --port 0 for any free port)" : "";
    throw InputError({"--port", 0, 0}, "cannot listen on " + where + ": " + ec.message() + hint);
  }
}

HttpServer::~HttpServer() { stop(); }

int HttpServer::port() const {
  beast::error_code ec;
  const tcp::endpoint local = impl_->acceptor.local_endpoint(ec);
  return ec ? -1 : local.port();
}

bool HttpServer::loopback() const { return impl_->loopback; }
bool HttpServer::wildcard() const { return impl_->wildcard; }

void HttpServer::run(int threads) {
  impl_->accept();
  std::vector<std::thread> others;
  for (int i = 1; i < threads; ++i) others.emplace_back([this] { impl_->context.run(); });
  impl_->context.run();
  for (std::thread& t : others) t.join();
}

void HttpServer::stop() {
  net::post(impl_->context, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
  });
  impl_->context.stop();
}

HttpResponse respond_to_bytes(std::string_view raw, const ServerLimits& limits, const HttpHandler& handler) {
  Parser parser;
  configure(parser, limits);
  parser.eager(true);
  beast::error_code ec;
  std::size_t used = 0;
  // All the bytes there will ever be are here: "need more" ends the loop, and the end
  // of input is then said to the parser, as a closed connection would.
  while (!parser.is_done() && used < raw.size()) {
    const std::size_t n = parser.put(net::buffer(raw.data() + used, raw.size() - used), ec);
    used += n;
    if (ec == http::error::need_more) ec = {};
    if (ec || n == 0) break;
  }
  if (!ec && !parser.is_done() && parser.got_some()) parser.put_eof(ec);
  if (ec) {
    if (const std::optional<HttpResponse> answer = refusal(ec)) return *answer;
  }
  if (ec || !parser.is_done()) return error_response(400, "incomplete HTTP request");
  return call(handler, to_request(parser.get()));
}

}  // namespace cluttertamp::cli
