#pragma once
// Removes the Fast DDS shared-memory files that a killed process left behind (SIGKILL, OOM,
// power loss of a container), so they do not pile up in /dev/shm across restarts:
//  - transport segments fastrtps_<id> come with a lock file fastrtps_<id>_el that their owner
//    holds locked (flock) while it lives: a lock we can take means the owner is gone;
//  - data-sharing segments fast_datasharing_<GUID prefix>_<entity> name their owner's process
//    (GUID prefix bytes 4-5 hold the low 16 bits of its pid): when no process with those bits
//    runs, the owner is gone.
// Only files of our own user are touched, and only through these names, never by following a
// link. Run at start when shared memory is in use.
#include <cstddef>
#include <string>

namespace headingd::app {

// Returns how many files were removed from `directory` (normally /dev/shm).
std::size_t remove_stale_fastdds_files(const std::string& directory);

}  // namespace headingd::app
