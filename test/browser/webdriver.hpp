#pragma once
// Just enough of the W3C WebDriver protocol to drive headless Chromium through
// ChromeDriver from a test, and child processes the tests start and always stop.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <netinet/in.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen's headers after it.
#include <httplib.h>

extern char** environ;

namespace browser_test {

using Json = nlohmann::json;

/// A free TCP port on 127.0.0.1 (free when asked; taken by whoever binds it first).
inline int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    if (fd >= 0) close(fd);
    throw std::runtime_error("no free port on 127.0.0.1");
  }
  close(fd);
  return ntohs(address.sin_port);
}

/// A child process, stopped (SIGTERM, then SIGKILL) when this goes out of scope. Its
/// standard output can be read line by line; its standard error goes to `log`.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const std::string& log) {
    if (access(argv.at(0).c_str(), X_OK) != 0) {
      throw std::runtime_error(argv[0] + " is not installed: run scripts/install-deps.sh --browser");
    }
    int out[2];
    if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int error = posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    if (error != 0) {
      close(out[0]);
      throw std::runtime_error("cannot start " + argv[0] + " (log " + log + "): " + std::strerror(error));
    }
    output_ = fdopen(out[0], "r");
  }
  ~Child() { stop(); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  /// The next line of standard output; empty at its end.
  std::string line() {
    char buffer[4096];
    return output_ && std::fgets(buffer, sizeof buffer, output_) ? std::string(buffer) : std::string();
  }

  /// Stops the child (SIGTERM, SIGKILL after `grace`); its exit status, or -1 when killed.
  int stop(std::chrono::milliseconds grace = std::chrono::milliseconds(10000)) {
    if (pid_ <= 0) return status_;
    kill(pid_, SIGTERM);
    const auto until = std::chrono::steady_clock::now() + grace;
    int status = 0;
    pid_t done = 0;
    while ((done = waitpid(pid_, &status, WNOHANG)) == 0) {
      if (std::chrono::steady_clock::now() > until) {
        kill(pid_, SIGKILL);
        done = waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    pid_ = 0;
    if (output_) std::fclose(output_);
    output_ = nullptr;
    status_ = done > 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return status_;
  }

 private:
  pid_t pid_ = 0;
  FILE* output_ = nullptr;
  int status_ = -1;
};

inline std::string base64_decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::string out;
  int bits = 0, buffer = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;
    buffer = (buffer << 6) | v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xff));
    }
  }
  return out;
}

/// One headless Chromium session through a ChromeDriver started for it.
class WebDriver {
 public:
  explicit WebDriver(const std::string& log_dir)
      : port_(free_port()),
        driver_({"/usr/bin/chromedriver", "--port=" + std::to_string(port_)}, log_dir + "/chromedriver.log"),
        http_("127.0.0.1", port_) {
    http_.set_read_timeout(120, 0);
    for (int i = 0; i < 100 && !http_.Get("/status"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const Json options{{"binary", "/usr/bin/chromium"},
                       {"args", {"--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1280,860",
                                 "--use-angle=swiftshader", "--enable-unsafe-swiftshader"}}};
    const Json session = call("POST", "/session", {{"capabilities", {{"alwaysMatch", {{"goog:chromeOptions", options}}}}}});
    id_ = session.at("sessionId").get<std::string>();
  }
  ~WebDriver() {
    if (!id_.empty()) http_.Delete("/session/" + id_);
  }

  void go(const std::string& url) { call("POST", path("/url"), {{"url", url}}); }

  /// Runs `script` (a function body; `arguments` holds `args`) in the page; its return value.
  Json execute(const std::string& script, const Json& args = Json::array()) {
    return call("POST", path("/execute/sync"), {{"script", script}, {"args", args}});
  }

  /// Waits up to `seconds` for `condition` (a JavaScript expression) to be true.
  bool wait_for(const std::string& condition, double seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until) {
      if (execute("return !!(" + condition + ");").get<bool>()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

  /// Clicks the element `css` selects, as a person would (in its centre).
  void click(const std::string& css) {
    const Json element = call("POST", path("/element"), {{"using", "css selector"}, {"value", css}});
    call("POST", path("/element/" + element.begin().value().get<std::string>() + "/click"), Json::object());
  }

  /// A real pointer click at client coordinates (x, y) in pixels.
  void click_at(double x, double y) {
    const Json pointer{{"type", "pointer"},
                       {"id", "mouse"},
                       {"parameters", {{"pointerType", "mouse"}}},
                       {"actions",
                        {{{"type", "pointerMove"}, {"duration", 0}, {"origin", "viewport"}, {"x", int(x)}, {"y", int(y)}},
                         {{"type", "pointerDown"}, {"button", 0}},
                         {{"type", "pointerUp"}, {"button", 0}}}}};
    call("POST", path("/actions"), {{"actions", {pointer}}});
  }

  void screenshot(const std::string& file) {
    std::ofstream(file, std::ios::binary) << base64_decode(call("GET", path("/screenshot")).get<std::string>());
  }

 private:
  std::string path(const std::string& rest) const { return "/session/" + id_ + rest; }

  Json call(const std::string& method, const std::string& where, const Json& body = nullptr) {
    const std::string text = body.is_null() ? "" : body.dump();
    const httplib::Result r = method == "GET" ? http_.Get(where) : http_.Post(where, text, "application/json");
    if (!r) throw std::runtime_error("ChromeDriver did not answer " + method + " " + where);
    const Json reply = Json::parse(r->body, nullptr, false);
    if (r->status != 200 || reply.is_discarded()) throw std::runtime_error("WebDriver " + where + ": " + r->body.substr(0, 600));
    return reply.at("value");
  }

  int port_;
  Child driver_;
  httplib::Client http_;
  std::string id_;
};

}  // namespace browser_test
