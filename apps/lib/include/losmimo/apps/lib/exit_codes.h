#pragma once
// The exit codes of every losmimo app, declared once: mains, app entry points and their headers
// name these enumerators, never the numbers.

namespace losmimo::apps {

enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,   // a runtime failure (I/O, a damaged log read as far as it goes)
  kExitBadInput = 2,  // bad input: the message names the file, line, key or field and value
  kExitFault = 3,     // a mission ended by a fault (an unresponsive UAV, a numerical fault)
};

}  // namespace losmimo::apps
