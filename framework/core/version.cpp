#include "cluttertamp/version.hpp"

namespace cluttertamp {

std::string_view version() { return CLUTTERTAMP_VERSION_STRING; }

}  // namespace cluttertamp
