#pragma once
// The benches' sentences around their tables, fitted to a 100-column terminal.

#include <cstddef>
#include <string>

namespace cluttertamp::bench {

/// `text` broken at spaces into lines of at most `width` columns (a UTF-8 character is
/// one column; a word longer than a line stands alone), its own line breaks kept; every
/// line ends in '\n'.
std::string wrapped(const std::string& text, std::size_t width = 100);

}  // namespace cluttertamp::bench
