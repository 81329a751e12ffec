#pragma once
// Summary statistics and number formats the bench commands print: one definition of each.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace cluttertamp::bench {

/// `v` with `digits` decimals, for tables.
inline std::string fixed(double v, int digits = 2) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

/// `text` as one CSV field (RFC 4180): quoted, inner quotes doubled.
inline std::string csv_field(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// The middle value (the mean of the two middle values for an even count); 0 when empty.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  if (v.size() % 2) return v[h];
  const double upper = v[h];
  return (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h)) + upper) / 2;
}

/// The `p`-th percentile (0 to 100), linearly interpolated between the closest ranks;
/// 0 when empty.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(rank);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (rank - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// The arithmetic mean; 0 when empty.
inline double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

/// The sample standard deviation (n − 1); 0 for fewer than two values.
inline double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double sum = 0.0;
  for (double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / double(v.size() - 1));
}

/// Half the width of the 95 % confidence interval of the mean (Student's t, n − 1
/// degrees of freedom); 0 for fewer than two values.
inline double ci95_half_width(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  // t quantiles (0.975) for 1..30 degrees of freedom; beyond, the normal's.
  static constexpr double t[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  const std::size_t df = v.size() - 1;
  const double q = df <= 30 ? t[df - 1] : 1.960;
  return q * stddev(v) / std::sqrt(double(v.size()));
}

/// Fisher's exact test, two-sided: the probability, with the margins fixed, of a 2x2
/// table at most as likely as `a` successes of `n1` against `b` of `n2`. Preconditions:
/// a <= n1, b <= n2.
inline double fisher_exact_p(std::size_t a, std::size_t n1, std::size_t b, std::size_t n2) {
  assert(a <= n1 && b <= n2);
  const auto log_choose = [](double n, double k) { return std::lgamma(n + 1) - std::lgamma(k + 1) - std::lgamma(n - k + 1); };
  const std::size_t k = a + b, lo = k > n2 ? k - n2 : 0, hi = std::min(k, n1);
  const auto log_p = [&](std::size_t x) {
    return log_choose(double(n1), double(x)) + log_choose(double(n2), double(k - x)) - log_choose(double(n1 + n2), double(k));
  };
  const double observed = log_p(a);
  double p = 0.0;
  for (std::size_t x = lo; x <= hi; ++x) {
    const double l = log_p(x);
    if (l <= observed + 1e-7) p += std::exp(l);  // relative tolerance for ties
  }
  return std::min(1.0, p);
}

}  // namespace cluttertamp::bench
