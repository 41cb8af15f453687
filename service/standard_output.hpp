#pragma once
// How a command that writes its result to standard output ends: the output flushed and
// checked, so a full disk or a failed pipe is exit 73, not a silent 0. A reader that closed the
// pipe early (`| head`) wanted no more: that is a normal end.
namespace headingd::app {

// 0 (kExitOk) when everything reached standard output or its reader closed it; otherwise
// says so on standard error and returns kExitCantCreate (73).
int finish_standard_output();

}  // namespace headingd::app
