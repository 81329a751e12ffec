#pragma once
// What `bench occlusion` and `bench mobile` report per column, as Tian et al.'s Tables
// II and III do: objects moved (target included), planning time, iterations and
// success rate, beside the paper's figures.
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/statistics.hpp"

namespace cluttertamp::bench {

/// A column of the paper's table (means; success in %).
struct PaperMeasures {
  double removed, seconds, iterations, success;
};

/// The runs of one column: every run counts for the success rate, solved runs for the rest.
struct Measures {
  int runs = 0, solved = 0;
  std::vector<double> removed, seconds, iterations;
  /// Occlusion: the objects of the final removal sequence (target included) per solved
  /// run, where `removed` counts every object moved; empty: not measured.
  std::vector<double> final_sequence;

  void add(bool ok, double removed_count, double time_s, double iteration_count) {
    ++runs;
    if (!ok) return;
    ++solved;
    removed.push_back(removed_count);
    seconds.push_back(time_s);
    iterations.push_back(iteration_count);
  }
  double success() const { return runs ? 100.0 * solved / runs : 0.0; }
  static double mean_of(const std::vector<double>& v) { return v.empty() ? 0.0 : mean(v); }
  double time_median() const { return seconds.empty() ? 0.0 : median(seconds); }

  /// |O_r|, mean time, median time, iterations, success: ours with the paper's in brackets.
  std::vector<std::string> cells(const std::optional<PaperMeasures>& paper) const {
    auto cell = [&](double ours, std::optional<double> theirs, int digits) {
      std::ostringstream out;
      out << std::fixed << std::setprecision(digits) << ours;
      if (theirs) out << " (" << *theirs << ")";
      return out.str();
    };
    auto p = [&](double PaperMeasures::*m) { return paper ? std::optional<double>((*paper).*m) : std::nullopt; };
    if (!final_sequence.empty()) {
      return {cell(mean_of(removed), std::nullopt, 2), cell(mean_of(final_sequence), p(&PaperMeasures::removed), 2),
              cell(mean_of(seconds), p(&PaperMeasures::seconds), 2), cell(time_median(), std::nullopt, 2),
              cell(mean_of(iterations), p(&PaperMeasures::iterations), 2), cell(success(), p(&PaperMeasures::success), 0)};
    }
    return {cell(mean_of(removed), p(&PaperMeasures::removed), 2), cell(mean_of(seconds), p(&PaperMeasures::seconds), 2),
            cell(time_median(), std::nullopt, 2), cell(mean_of(iterations), p(&PaperMeasures::iterations), 2),
            cell(success(), p(&PaperMeasures::success), 0)};
  }

  nlohmann::ordered_json json(const std::optional<PaperMeasures>& paper) const {
    nlohmann::ordered_json out{{"runs", runs},
                               {"solved", solved},
                               {"success_rate", success() / 100},
                               {"removed_mean", mean_of(removed)},
                               {"final_sequence_mean", final_sequence.empty() ? nlohmann::ordered_json(nullptr)
                                                                              : nlohmann::ordered_json(mean_of(final_sequence))},
                               {"time_mean_s", mean_of(seconds)},
                               {"time_median_s", time_median()},
                               {"iterations_mean", mean_of(iterations)}};
    out["paper"] = paper ? nlohmann::ordered_json{{"removed", paper->removed}, {"time_s", paper->seconds},
                                                  {"iterations", paper->iterations}, {"success_rate", paper->success / 100}}
                         : nlohmann::ordered_json(nullptr);
    return out;
  }
};

/// The table: a row per measure, a column per entry of `columns` (Measures::cells).
inline void print_measures(std::ostream& to, const std::vector<std::string>& headers,
                           const std::vector<std::vector<std::string>>& columns, int width = 26) {
  std::ostringstream out;  // lines without the last column's padding (within 100 columns for three columns)
  const auto end_line = [&] {
    std::string line = out.str();
    line.erase(line.find_last_not_of(' ') + 1);
    to << line << "\n";
    out.str("");
  };
  out << std::left << std::setw(26) << "measure";
  for (const std::string& h : headers) out << std::setw(width) << h;
  end_line();
  const bool both = !columns.empty() && columns.front().size() == 6;  // moved in total and final sequence
  std::vector<std::string> labels{"|O_r| (target included)", "time, mean (s)", "time, median (s)", "# iteration", "success rate (%)"};
  if (both) {
    labels[0] = "|O_r| moved in total";
    labels.insert(labels.begin() + 1, "|O_r| final sequence");
  }
  for (std::size_t k = 0; k < labels.size(); ++k) {
    out << std::left << std::setw(26) << labels[k];
    for (const auto& c : columns) out << std::setw(width) << c[k];
    end_line();
  }
  to << "\nMeasures other than the success rate are over solved runs; the paper gives means only.\n";
}

}  // namespace cluttertamp::bench
