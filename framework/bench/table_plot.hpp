#pragma once
// The plot of a table of planning runs beside a paper's (Tables II, III and IV): per
// table, three panels side by side — success rates as bars, |O_r| and planning times of
// the solved runs as box plots — with the paper's success as hatched bars, its means as
// diamonds and each column's unsolved runs as a red cross with their count.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cluttertamp::bench {

/// One setting's runs in a group (one bar and two boxes).
struct PlotColumn {
  std::string colour;
  double success = 0;            ///< percent of its runs solved
  std::vector<double> removed;   ///< |O_r| of each solved run
  std::vector<double> seconds;   ///< planning time of each solved run, s
  int unsolved = 0;
  std::optional<double> paper_success, paper_removed, paper_seconds;
  std::string paper_seconds_note;  ///< beside the paper's time diamond, e.g. "> 120" when drawn at a bound
};

/// Columns side by side over one x label (a problem, an object count, a strategy).
struct PlotGroup {
  std::string label;
  std::vector<PlotColumn> columns;
};

/// One table: its title, the |O_r| panel's title, its groups, and the names of the
/// column colours for a legend (empty when a group has one column and its label says it).
struct TablePlot {
  std::string title;
  std::string removed_title = "|O_r|, solved runs";
  std::vector<PlotGroup> groups;
  std::vector<std::pair<std::string, std::string>> series;  ///< (colour, name)
};

/// Draws `tables` one under the other into `file` (the time axis logarithmic where the
/// times span more than a decade). Throws InputError naming the file when it cannot be
/// written.
void write_table_svg(const std::filesystem::path& file, const std::vector<TablePlot>& tables);

}  // namespace cluttertamp::bench
