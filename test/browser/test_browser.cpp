// The browser side in a real browser: headless Chromium, driven through ChromeDriver,
// uses the guidance page of `cluttertamp guide` and loads the replay pages of
// `cluttertamp plan --html`. Screenshots are kept in build/test-artifacts/.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <future>
#include <regex>

#include "webdriver.hpp"

namespace fs = std::filesystem;
using browser_test::Child;
using browser_test::Json;
using browser_test::WebDriver;

namespace {

const std::string kCli = CLUTTERTAMP_CLI;
const fs::path kSource = CLUTTERTAMP_SOURCE_DIR;
const fs::path kArtifacts = CLUTTERTAMP_TEST_ARTIFACTS;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = kArtifacts / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Json read_json(const fs::path& file) {
  std::ifstream in(file);
  return Json::parse(in);
}

// Starts `cluttertamp guide` on a free port; the URL it serves, with the session token.
std::string start_guide(Child& server) {
  const std::string line = server.line();
  std::smatch m;
  if (!std::regex_search(line, m, std::regex("http://127\\.0\\.0\\.1:([0-9]+)/\\?token=[0-9a-f]{32}"))) {
    throw std::runtime_error("guide did not say where it serves: '" + line + "'");
  }
  return m[0];
}

int port_of(const std::string& url) { return std::stoi(url.substr(url.rfind(':') + 1)); }

// A client of the guide server that carries the session token, as the page does.
std::unique_ptr<httplib::Client> guide_client(const std::string& url) {
  auto client = std::make_unique<httplib::Client>("127.0.0.1", port_of(url));
  client->set_read_timeout(60, 0);
  client->set_default_headers({{"X-Guide-Token", url.substr(url.find("token=") + 6)}});
  return client;
}

std::vector<std::string> guide_command(const fs::path& dir, const std::string& time_limit) {
  return {kCli, "guide", (kSource / "problems/push/shelf10/p01.yaml").string(), "--port", "0", "--output", dir.string(),
          "--time-limit", time_limit};
}

}  // namespace

// The seed's operator loop (Section V-B): click an object, click where it goes, see the
// push; a click off the shelf is refused; then the robot finishes in the time left.
TEST(Browser, AnOperatorPushesAnObjectFromTheGuidePageAndTheRobotFinishes) {
  const fs::path dir = fresh_dir("guide-session");
  Child server(guide_command(dir / "out", "90"), (dir / "server.log").string());
  const std::string url = start_guide(server);
  WebDriver browser(dir.string());
  browser.go(url);
  ASSERT_TRUE(browser.wait_for("window.guideReady", 30));
  browser.screenshot((dir / "1-start.png").string());

  browser.click("#object-o3");
  const Json goal = browser.execute("return window.guide.toClient(arguments[0], arguments[1]);", Json::array({0.78, 0.06}));
  browser.click_at(goal["x"].get<double>(), goal["y"].get<double>());
  ASSERT_TRUE(browser.wait_for("window.guide.state.inputs.length === 1 && !window.guide.busy", 60));
  const Json state = browser.execute("return window.guide.state;");
  ASSERT_TRUE(state["inputs"][0]["satisfied"].get<bool>()) << state["inputs"][0]["reason"];
  for (const Json& o : state["objects"]) {
    if (o["id"] == "o3") EXPECT_LT(std::hypot(o["pose"][0].get<double>() - 0.78, o["pose"][1].get<double>() - 0.06), 0.05 + 1e-6);
  }
  EXPECT_NE(browser.execute("return document.getElementById('status').textContent;").get<std::string>().find("pushed o3"),
            std::string::npos);
  browser.screenshot((dir / "2-pushed.png").string());

  // Off the shelf: refused, shown, and not an input of the record.
  browser.click("#object-o1");
  const Json off = browser.execute("return window.guide.toClient(arguments[0], arguments[1]);", Json::array({0.45, 0.0}));
  browser.click_at(off["x"].get<double>(), off["y"].get<double>());
  ASSERT_TRUE(browser.wait_for("document.getElementById('status').textContent.includes('does not lie on the shelf')", 10));
  EXPECT_EQ(browser.execute("return window.guide.state.inputs.length;").get<int>(), 1);

  browser.click("#finish");
  ASSERT_TRUE(browser.wait_for("window.guide.state.finished && !window.guide.busy", 120));
  browser.screenshot((dir / "3-finished.png").string());
  const bool solved = browser.execute("return window.guide.state.solved;").get<bool>();
  EXPECT_TRUE(solved) << browser.execute("return window.guide.state.reason;");
  EXPECT_EQ(browser.execute("return window.guideErrors;"), Json::array());

  // The session's files: the guidance grtc can read, the result with its record.
  const Json result = read_json(dir / "out/result.json");
  EXPECT_EQ(result["solved"].get<bool>(), solved);
  EXPECT_EQ(result["human_guidance"]["successful_inputs"], 1);
  EXPECT_EQ(result["human_guidance"]["failed_inputs"], 0);
  EXPECT_GE(result["human_guidance"]["interaction_time"].get<double>(), 0.0);
  EXPECT_EQ(result["plan"][0]["objects"][0], "o3");
  std::ifstream guidance(dir / "out/guidance.yaml");
  const std::string text((std::istreambuf_iterator<char>(guidance)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("object: \"o3\""), std::string::npos) << text;
  if (solved) {
    EXPECT_TRUE(fs::exists(dir / "out/plan.html"));
    EXPECT_EQ(server.stop(), 0);
  }
}

// Several tabs and bad requests: each answered with a reason, none stops the server.
TEST(Browser, TheGuideServerAnswersBadRequestsAndManyTabsWithoutStopping) {
  const fs::path dir = fresh_dir("guide-bad-requests");
  Child server(guide_command(dir / "out", "30"), (dir / "server.log").string());
  const std::string url = start_guide(server);
  const auto client = guide_client(url);
  httplib::Client& http = *client;
  // Without the session token of the printed address, nothing changes the session.
  httplib::Client stranger("127.0.0.1", port_of(url));
  const auto refused = stranger.Post("/api/finish", "{}", "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 403) << refused->body;
  const std::vector<std::pair<std::string, std::string>> bad{
      {"{not json", "not a JSON object"},
      {"[1, 2]", "not a JSON object"},
      {R"({"object": "nothing", "x": 0.8, "y": 0.0})", "no object 'nothing'"},
      {R"({"object": "o3", "x": 2.0, "y": 0.0})", "does not lie on the shelf"},
      {R"({"object": "o3", "x": "far", "y": 0.0})", "must be numbers"},
      {R"({"object": "o3", "x": 0.8, "y": 0.0, "diameter": -1})", "positive diameter"},
      {R"({"object": "cabinet_back", "x": 0.8, "y": 0.0})", "no object 'cabinet_back'"}};
  for (const auto& [body, reason] : bad) {
    const auto r = http.Post("/api/guide", body, "application/json");
    ASSERT_TRUE(r) << body;
    EXPECT_EQ(r->status, 400) << body;
    EXPECT_NE(r->body.find(reason), std::string::npos) << body << " -> " << r->body;
  }
  // Another site's page may post to localhost, but not as JSON without asking first.
  const auto plain = http.Post("/api/finish", "{}", "text/plain");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->status, 415);
  const auto missing = http.Get("/no/such/page");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  const auto early = http.Get("/replay");
  ASSERT_TRUE(early);
  EXPECT_EQ(early->status, 404);

  // Four tabs at once: one pushes while the others read the state.
  std::vector<std::future<int>> tabs;
  tabs.push_back(std::async(std::launch::async, [&] {
    const auto c = guide_client(url);
    const auto r = c->Post("/api/guide", R"({"object": "o3", "x": 0.78, "y": 0.06})", "application/json");
    return r ? r->status : -1;
  }));
  for (int i = 0; i < 3; ++i) {
    tabs.push_back(std::async(std::launch::async, [&] {
      const auto c = guide_client(url);
      int last = 0;
      for (int k = 0; k < 5; ++k) last = c->Get("/api/state") ? 200 : -1;
      return last;
    }));
  }
  for (auto& t : tabs) EXPECT_EQ(t.get(), 200);
  const auto state = http.Get("/api/state");
  ASSERT_TRUE(state);
  EXPECT_EQ(Json::parse(state->body)["inputs"].size(), 1u);
}

// Every replay page loads from disk without a JavaScript error, with WebGL, and
// plays to its end.
TEST(Browser, ReplayPagesOfRetrievalAndPushingPlansLoadWithoutErrors) {
  const fs::path dir = fresh_dir("replay");
  WebDriver browser(dir.string());
  for (const std::string problem : {"problems/default.yaml", "problems/push/retrieve-push.yaml", "problems/push/easy.yaml"}) {
    const std::string name = fs::path(problem).stem().string();
    const fs::path out = dir / name;
    const std::string command = kCli + " plan " + (kSource / problem).string() + " --html -q -o " + out.string();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    ASSERT_TRUE(fs::exists(out / "plan.html"));
    const Json result = read_json(out / "result.json");
    browser.go("file://" + (out / "plan.html").string());
    ASSERT_TRUE(browser.wait_for("window.viewerReady", 30)) << name;
    EXPECT_EQ(browser.execute("return window.viewerErrors;"), Json::array()) << name;
    EXPECT_EQ(browser.execute("return window.viewerRenderer;"), "webgl") << name;
    EXPECT_EQ(browser.execute("return window.viewer.steps;").get<std::size_t>(), result["plan"].size()) << name;
    EXPECT_GT(browser.execute("return window.viewer.frames;").get<int>(), 1) << name;
    const std::size_t drawings = fs::exists(out / "drawings.json") ? read_json(out / "drawings.json")["drawings"].size() : 0;
    EXPECT_EQ(browser.execute("return document.querySelectorAll('#drawings svg').length;").get<std::size_t>(), drawings) << name;
    browser.execute("window.viewer.seek(window.viewer.duration / 2);");
    browser.screenshot((dir / (name + ".png")).string());
    EXPECT_EQ(browser.execute("return window.viewerErrors;"), Json::array()) << name;
  }
}

// The benches' plots render: each SVG, drawn by Chromium into a canvas, is mostly
// white but well inked (axes, boxes, bars, text), and its screenshot is kept.
TEST(Browser, BenchPlotsRenderAsDrawings) {
  const fs::path dir = fresh_dir("plots");
  const std::string retrieval = kCli + " bench retrieval -q --sizes 12 --scenes 2 --runs 2 --table I --table VI --time-limit 600 --svg " +
                                (dir / "retrieval.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(retrieval.c_str()), 0) << retrieval;
  fs::create_directories(dir / "shelves");
  for (const std::string file : {"p01.yaml", "p01-scene.yaml", "p01-guidance.yaml", "p02.yaml", "p02-scene.yaml", "p02-guidance.yaml"}) {
    std::ifstream in(kSource / "problems/push/shelf10" / file);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t robots = text.find("../../../domains/");  // the robot, from the copy's place
    if (robots != std::string::npos) text.replace(robots, 17, (kSource / "domains").string() + "/");
    std::ofstream(dir / "shelves" / file) << text;
  }
  const std::string push = kCli + " bench push -q --runs 1 --time-limit 5 --push-scenes " + (dir / "shelves").string() + " --svg " +
                           (dir / "push.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(push.c_str()), 0) << push;
  const std::string occlusion = kCli + " bench occlusion -q --sizes 8 --sizes 12 --scenes 2 --runs 1 --time-limit 600 --svg " +
                                (dir / "occlusion.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(occlusion.c_str()), 0) << occlusion;
  const std::string mobile = kCli + " bench mobile -q --seed 0 --scenes 2 --runs 1 --mobile-tables random --time-limit 3000 --svg " +
                             (dir / "mobile.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(mobile.c_str()), 0) << mobile;
  const std::string pddl = kCli + " bench pddl -q --per-domain 2 --runs 1 --parse-objects 0 --svg " + (dir / "pddl.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(pddl.c_str()), 0) << pddl;
  const std::string compare = kCli + " compare -q " + (kSource / "problems/stacked/stacked4.yaml").string() +
                              " --runs 2 --time-limit 600 --svg " + (dir / "compare.svg").string() + " > /dev/null";
  ASSERT_EQ(std::system(compare.c_str()), 0) << compare;
  for (const std::string timed : {"collision --samples 1000", "samplers --samples 2000", "physics"}) {
    const std::string name = timed.substr(0, timed.find(' '));
    const std::string command = kCli + " bench " + timed + " -q --svg " + (dir / (name + ".svg")).string() + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  WebDriver browser(dir.string());
  for (const std::string name : {"retrieval", "push", "occlusion", "mobile", "pddl", "compare", "collision", "samplers", "physics"}) {
    browser.go("file://" + (dir / (name + ".svg")).string());
    browser.execute(
        "const svg = document.documentElement; const w = svg.width.baseVal.value, h = svg.height.baseVal.value;"
        "const image = new Image(); window.ink = undefined;"
        "image.onload = () => { try { const c = document.createElementNS('http://www.w3.org/1999/xhtml', 'canvas'); c.width = w; c.height = h;"
        "  const g = c.getContext('2d'); g.fillStyle = 'white'; g.fillRect(0, 0, w, h); g.drawImage(image, 0, 0);"
        "  const d = g.getImageData(0, 0, w, h).data; let inked = 0;"
        "  for (let i = 0; i < d.length; i += 4) if (d[i] < 200 || d[i + 1] < 200 || d[i + 2] < 200) ++inked;"
        "  window.ink = inked / (w * h); } catch (e) { window.ink = -2; } };"
        "image.onerror = () => { window.ink = -1; };"
        "image.src = 'data:image/svg+xml;base64,' + btoa(unescape(encodeURIComponent(new XMLSerializer().serializeToString(svg))));");
    ASSERT_TRUE(browser.wait_for("window.ink !== undefined", 30)) << name;
    const double ink = browser.execute("return window.ink;").get<double>();
    EXPECT_GT(ink, 0.01) << name << ": almost blank";
    EXPECT_LT(ink, 0.6) << name << ": almost filled";
    const int labels = name == "physics" ? 8 : name == "samplers" || name == "collision" ? 10 : 20;  // one box each
    EXPECT_GT(browser.execute("return document.querySelectorAll('text').length;").get<int>(), labels) << name;
    browser.screenshot((dir / (name + ".png")).string());
  }
}
