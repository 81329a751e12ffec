#pragma once
// Shapes as the browser pages read them.

#include <nlohmann/json_fwd.hpp>

#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// {"box": [x y z]} | {"cylinder": [radius height]} | {"sphere": radius}, in metres.
/// Callers include <nlohmann/json.hpp> to use the value.
CLUTTERTAMP_API nlohmann::ordered_json shape_json(const Shape& shape);

}  // namespace cluttertamp::io
