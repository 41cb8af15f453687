#pragma once
// What a CSV beside the recordings is when it is not one: the files headingd itself writes or
// reads next to them (a simulation's truth, estimates, a score's error series, a batch table),
// and an EuRoC/ASL dataset's files other than imu0's (ground truth, cameras' lists, the tracker).
// A directory replayed as a fleet holds them too (`simulate` writes imu.csv beside truth.csv);
// they are told apart by their header, so that a recording whose header is damaged still
// counts, and fails with its own error, rather than being left out.
#include <optional>
#include <string>

namespace headingd::drivers {

// "a truth file", "an estimates file", … when the header is one of those and names none of a
// recording's rate columns; nothing otherwise (a recording, or a file that cannot be read:
// the replay then says what is wrong with it).
std::optional<std::string> companion_kind(const std::string& path);

}  // namespace headingd::drivers
