#include "bench/prose.hpp"

#include <sstream>

namespace cluttertamp::bench {
namespace {

std::size_t columns(const std::string& text) {
  std::size_t n = 0;
  for (unsigned char c : text) n += (c & 0xC0) != 0x80;
  return n;
}

void wrap_line(const std::string& line, std::size_t width, std::string& out) {
  std::istringstream words(line);
  std::string word, current;
  while (words >> word) {
    if (!current.empty() && columns(current) + 1 + columns(word) > width) {
      out += current + "\n";
      current.clear();
    }
    current += (current.empty() ? "" : " ") + word;
  }
  out += current + "\n";
}

}  // namespace

std::string wrapped(const std::string& text, std::size_t width) {
  std::string out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) wrap_line(line, width, out);
  return out;
}

}  // namespace cluttertamp::bench
