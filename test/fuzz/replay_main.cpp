// Runs a fuzz target over its seed corpus and deterministic mutations of it, so that
// the tests exercise it without a fuzzing engine (the libFuzzer build is separate:
// docs/development.md, "Fuzzing"). Usage: <name>_fuzz_replay MUTATIONS FILE_OR_DIR...
#include <algorithm>
#include <cstdlib>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {
// With FUZZ_REPLAY_LAST=FILE, each input is written there before it runs: after a
// crash, FILE holds the input that caused it.
void run(const std::string& input) {
  if (const char* last = std::getenv("FUZZ_REPLAY_LAST")) std::ofstream(last, std::ios::binary) << input;
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  // PDDL, YAML, XML, JSON and HTTP pieces: each target's grammar gets some of its own.
  static const std::string tokens[] = {"(", ")", " ", "?x", "-", ":", "(and", "(not", "(forall (?v)", "(either a b)",
                                       "\n;;;;\n", "object", "(= ?a ?b)", ":derived", "\"", "\t", "999999999999",
                                       "{", "}", "[", "]", ",", "\n  ", "- ", "&a ", "*a", "nan", "-1e308", "1e400", "~",
                                       "<", ">", "/>", "</link>", "<joint ", "=\"", "\"0 0\"", "null", "true",
                                       "\r\n", "Content-Length: 99999999\r\n", "Host: evil\r\n", "%00", "\xff\xfe"};
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = s.empty() ? 0 : rng() % (s.size() + 1);
    switch (rng() % 4) {
      case 0: if (!s.empty()) s.erase(std::min(at, s.size() - 1), 1 + rng() % 8); break;
      case 1: s.insert(at, tokens[rng() % (sizeof tokens / sizeof tokens[0])]); break;
      case 2: if (!s.empty()) s[std::min(at, s.size() - 1)] = static_cast<char>(rng() % 256); break;
      default: if (s.size() > 2) { const std::size_t a = rng() % s.size(), b = rng() % s.size(); s.insert(at, s.substr(std::min(a, b), std::min<std::size_t>(40, (a > b ? a - b : b - a)))); }
    }
  }
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: " << argv[0] << " MUTATIONS FILE_OR_DIR...\n";
    return 2;
  }
  const int mutations = std::stoi(argv[1]);
  std::vector<std::string> seeds;
  if (mutations < 0) {
    std::cerr << argv[0] << ": MUTATIONS must be at least 0\n";
    return 2;
  }
  for (int i = 2; i < argc; ++i) {
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(argv[i])) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(argv[i])) {
        if (e.is_regular_file()) files.push_back(e.path());
      }
    } else {
      files.emplace_back(argv[i]);
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      seeds.push_back(text.str());
    }
  }
  if (seeds.empty()) {
    std::cerr << argv[0] << ": no seed files found: the corpus is missing\n";
    return 2;
  }
  std::mt19937_64 rng(12345);
  std::size_t runs = 0;
  for (const std::string& seed : seeds) {
    run(seed);
    ++runs;
    for (int m = 0; m < mutations; ++m, ++runs) run(mutate(seed, rng));
  }
  const std::string name = std::filesystem::path(argv[0]).filename().string();
  std::cout << name << ": " << runs << " inputs (" << seeds.size() << " seeds), no crash\n";
  return 0;
}
