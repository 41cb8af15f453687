#pragma once
// Pictures drawn by gnuplot without ever handing it a string of the user's: the data go into
// files with fixed names in a private directory (mkdtemp), the script is our own text, and the
// picture gnuplot draws there is then written to the user's path by us (atomically, no links
// followed). Shared by `allan --plot` and `plot`.
#include <optional>
#include <string>
#include <vector>

namespace headingd::app {

struct PlotFile {
  const char* name;  // a fixed name of ours, e.g. "heading.dat"
  std::string text;
};

// Runs gnuplot on `script`, which must `set output` to `picture` (a fixed name); empty when the
// picture was written to `output`, else why not.
std::optional<std::string> draw_with_gnuplot(const std::vector<PlotFile>& data, const std::string& script,
                                             const char* picture, const std::string& output);

}  // namespace headingd::app
