#pragma once
// Exit codes follow sysexits.h so scripts can tell bad input from a broken machine.
namespace headingd::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 64;        // wrong command line
inline constexpr int kExitDataError = 65;    // input file malformed
inline constexpr int kExitNoInput = 66;      // input missing or unreadable
inline constexpr int kExitUnavailable = 69;  // echo --count: fewer messages than asked before --timeout
inline constexpr int kExitSoftware = 70;     // internal error
inline constexpr int kExitCantCreate = 73;   // output cannot be written
inline constexpr int kExitIoError = 74;      // the sensor failed for good
inline constexpr int kExitTempFail = 75;     // another instance runs: try again when it is gone
inline constexpr int kExitConfig = 78;       // configuration invalid

}  // namespace headingd::app
