#pragma once
#include <optional>
#include <string>

namespace headingd::app {

struct AllanOptions {
  std::string input;
  std::string axis = "all";              // x, y, z or all
  std::optional<std::string> plot_path;  // PNG, drawn with gnuplot
  bool emit_config = false;              // print a TOML fragment for the estimator
  bool still_only = false;               // keep only segments the auto estimator accepts as still
};

// Allan deviation of a recording, its noise terms, and optionally a plot and a config
// fragment. Returns the exit code.
int run_allan(const AllanOptions& options);

}  // namespace headingd::app
