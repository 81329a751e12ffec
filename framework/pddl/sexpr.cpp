#include "cluttertamp/pddl/sexpr.hpp"

#include "cluttertamp/pddl/read_atom.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <string_view>

namespace cluttertamp::pddl {

namespace {
constexpr std::size_t kMaxDepth = 200;

// The characters of a name, ASCII only whatever the locale.
constexpr std::array<bool, 256> kSymbolChars = [] {
  std::array<bool, 256> table{};
  for (int c = '0'; c <= '9'; ++c) table[c] = true;
  for (int c = 'a'; c <= 'z'; ++c) table[c] = table[c - 'a' + 'A'] = true;
  for (unsigned char c : std::string_view("-_?:.=<>+*/@!#$%&^~[]{}|'")) table[c] = true;
  return table;
}();

bool symbol_char(char c) { return kSymbolChars[static_cast<unsigned char>(c)]; }
char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }
}  // namespace

std::string SourceText::excerpt(const SourceLocation& where) const {
  if (where.line == 0) return {};
  std::size_t start = 0;
  for (std::size_t line = 1; line < where.line; ++line) {
    start = text.find('\n', start);
    if (start == std::string::npos) return {};
    ++start;
  }
  std::size_t end = text.find('\n', start);
  std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.size() > 160) line = line.substr(0, 160) + "...";
  for (char& c : line) {
    if (c == '\t') c = ' ';
  }
  const std::size_t column = where.column > 0 ? std::min(where.column - 1, line.size()) : 0;
  return "  " + line + "\n  " + std::string(column, ' ') + "^";
}

std::string SourceText::with_excerpt(const SourceLocation& where, const std::string& message) const {
  const std::string quote = excerpt(where);
  return quote.empty() ? message : message + "\n" + quote;
}

void SourceText::fail(const SourceLocation& where, const std::string& message) const {
  throw InputError(where, with_excerpt(where, message));
}

std::vector<SExpr> read_sexprs(const SourceText& source) {
  const std::string& s = source.text;
  std::size_t i = 0, line = 1, column = 1;
  auto here = [&] { return SourceLocation{source.file, line, column}; };
  auto advance = [&] {
    if (s[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
    ++i;
  };
  std::vector<SExpr> top;
  // Open lists, innermost last; the items read so far of all of them lie one after
  // another in `items`, each list's from its `first_item` on, and move into the list
  // when it closes: one allocation of the right size per list, not one per doubling.
  std::vector<SExpr> stack;
  std::vector<std::size_t> first_item;
  std::vector<SExpr> items;
  while (i < s.size()) {
    const char c = s[i];
    if (c == ';') {
      while (i < s.size() && s[i] != '\n') advance();
    } else if (c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      advance();
    } else if (c == '(') {
      if (stack.size() >= kMaxDepth) source.fail(here(), "expressions nested deeper than 200 levels");
      SExpr list;
      list.is_list = true;
      list.where = here();
      stack.push_back(std::move(list));
      first_item.push_back(items.size());
      advance();
    } else if (c == ')') {
      if (stack.empty()) source.fail(here(), "unmatched ')'");
      SExpr done = std::move(stack.back());
      stack.pop_back();
      const auto first = static_cast<std::ptrdiff_t>(first_item.back());
      first_item.pop_back();
      done.items.assign(std::make_move_iterator(items.begin() + first), std::make_move_iterator(items.end()));
      items.erase(items.begin() + first, items.end());
      (stack.empty() ? top : items).push_back(std::move(done));
      advance();
    } else if (symbol_char(c)) {
      SExpr atom;
      atom.where = here();
      // A '?' always begins a name, as in Fast Downward's reader: "(aircraft?a)" is the
      // predicate aircraft applied to ?a (IPC zenotravel writes it so).
      std::size_t end = i + 1;
      while (end < s.size() && symbol_char(s[end]) && s[end] != '?') ++end;
      atom.text.resize(end - i);
      std::transform(s.begin() + static_cast<std::ptrdiff_t>(i), s.begin() + static_cast<std::ptrdiff_t>(end), atom.text.begin(), lower);
      column += end - i;  // a name holds no line break
      i = end;
      if (stack.empty()) source.fail(atom.where, "'" + atom.text + "' outside any parenthesised expression");
      items.push_back(std::move(atom));
    } else {
      const unsigned char u = static_cast<unsigned char>(c);
      source.fail(here(), u >= 0x20 && u < 0x7f ? std::string("unexpected character '") + c + "'"
                                                 : "unexpected byte " + std::to_string(u) + " (PDDL is ASCII)");
    }
  }
  if (!stack.empty()) source.fail(stack.back().where, "this '(' is never closed");
  return top;
}

std::string lower_name(std::string name) {
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

std::string read_text_file(const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    throw InputError({file.string(), 0, 0}, "cannot be examined: " + ec.message());  // a symbolic link loop, ...
  }
  if (!fs::exists(status)) throw InputError({file.string(), 0, 0}, "no such file");
  if (!fs::is_regular_file(status)) throw InputError({file.string(), 0, 0}, "not a regular file");
  constexpr std::size_t kMaxBytes = 64u << 20;
  const auto too_large = [&] { return InputError({file.string(), 0, 0}, "larger than 64 MiB"); };
  const std::uintmax_t reported = fs::file_size(file, ec);  // (uintmax_t)-1 on an error
  if (reported > kMaxBytes) throw too_large();
  // read(2), not an ifstream: a fresh process's first ifstream costs a tenth of a
  // millisecond, as much as parsing a small PDDL problem.
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError({file.string(), 0, 0}, "cannot be read (no permission?)");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  // Until the end of the file, whatever its size said (files of /proc say 0).
  std::string text(reported + 1, '\0');
  std::size_t size = 0;
  for (;;) {
    if (size == text.size()) {
      if (size > kMaxBytes) throw too_large();
      text.resize(std::min(2 * size, kMaxBytes + 1));
    }
    const ssize_t got = ::read(fd, text.data() + size, text.size() - size);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError({file.string(), 0, 0}, "cannot be read (an I/O error)");
    if (got == 0) break;
    size += static_cast<std::size_t>(got);
  }
  if (size > kMaxBytes) throw too_large();
  text.resize(size);
  return text;
}

std::optional<Atom> read_atom(const SExpr& e, NotAnAtom& why, SourceLocation& where) {
  if (!e.is_list || e.items.empty() || !e.items[0].is_atom() || e.items[0].text[0] == '?' || e.items[0].text[0] == ':') {
    why = NotAnAtom::head;
    where = e.where;
    return std::nullopt;
  }
  Atom a;
  a.predicate = e.items[0].text;
  a.where = e.where;
  a.args.reserve(e.items.size() - 1);
  for (std::size_t i = 1; i < e.items.size(); ++i) {
    const SExpr& arg = e.items[i];
    if (!arg.is_atom()) {
      why = NotAnAtom::argument;
      where = arg.where;
      return std::nullopt;
    }
    a.args.push_back({arg.text, arg.text[0] == '?', arg.where});
  }
  return a;
}

}  // namespace cluttertamp::pddl
