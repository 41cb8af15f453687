#pragma once
// Writing a whole file we own the way every output should be written: a temporary created
// exclusively next to the target (never through a link planted there), filled, synced, then
// renamed over the target (a link at the target is replaced, never followed).
#include <string>
#include <string_view>

namespace headingd::app {

// Throws OutputError naming the file and what failed.
void write_file_atomically(const std::string& path, std::string_view bytes);

// True when both paths name one file: the same device and inode when both exist (links and
// other spellings included), else the same canonical path. Checked before an output is opened, so it never truncates an
// input.
bool same_file(const std::string& a, const std::string& b);

}  // namespace headingd::app
