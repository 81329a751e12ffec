#pragma once

#include <cstdio>
#include <string>

#include <Eigen/Core>

#include "cluttertamp/robot/robot_model.hpp"

namespace cluttertamp::io {

/// "'joint' at 4.2 outside [-3.14159, 3.14159]; ..." for each variable of `q` beyond
/// its joint's limits (as RobotModel::within_limits judges); empty when none is.
inline std::string outside_limits(const robot::RobotModel& model, const Eigen::VectorXd& q) {
  std::string text;
  for (std::size_t v = 0; v < model.variable_count() && v < static_cast<std::size_t>(q.size()); ++v) {
    const robot::Joint& j = model.joints()[static_cast<std::size_t>(model.variables()[v])];
    const double x = q[static_cast<Eigen::Index>(v)];
    if (x >= j.lower - 1e-9 && x <= j.upper + 1e-9) continue;
    char entry[256];
    std::snprintf(entry, sizeof entry, "%s'%s' at %.6g outside [%.6g, %.6g]%s", text.empty() ? "" : "; ", j.name.c_str(), x, j.lower,
                  j.upper, j.continuous ? " (a continuous joint: one turn)" : "");
    text += entry;
  }
  return text;
}

}  // namespace cluttertamp::io
