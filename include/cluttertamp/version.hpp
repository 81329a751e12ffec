#pragma once

#include <string_view>

#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// The version of libcluttertamp this program runs against ("MAJOR.MINOR.PATCH").
CLUTTERTAMP_API std::string_view version();

}  // namespace cluttertamp
