#include "cluttertamp/io/shape_json.hpp"

#include <variant>

#include <nlohmann/json.hpp>

namespace cluttertamp::io {

nlohmann::ordered_json shape_json(const Shape& shape) {
  if (const auto* b = std::get_if<Box>(&shape)) return {{"box", {b->size.x(), b->size.y(), b->size.z()}}};
  if (const auto* c = std::get_if<Cylinder>(&shape)) return {{"cylinder", {c->radius, c->height}}};
  return {{"sphere", std::get<Sphere>(shape).radius}};
}

}  // namespace cluttertamp::io
