#pragma once
// --version for every app: "losmimo <version> (<isa> kernels)", e.g. "losmimo 0.1.0 (avx512
// kernels)": the project's version (LOSMIMO_VERSION, set by losmimo_add_app) and the instruction
// set the placement kernels run on here (losmimo/placement/isa.h; LOSMIMO_ISA forces one), named
// as the experiment's report names it. A LOSMIMO_ISA this CPU cannot run is shown, not an error.
#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

#include "losmimo/placement/isa.h"

#ifndef LOSMIMO_VERSION
#error "LOSMIMO_VERSION is set by losmimo_add_app (cmake/LosmimoHelpers.cmake)"
#endif

namespace losmimo::apps {

inline std::string version_line() {
  std::string kernels;
  try {
    kernels = placement::to_string(placement::active_isa()) + " kernels";
  } catch (const std::invalid_argument& e) {
    kernels = std::string("no kernels: ") + e.what();
  }
  return std::string("losmimo ") + LOSMIMO_VERSION + " (" + kernels + ")";
}

inline void add_version_flag(CLI::App& app) {
  app.set_version_flag("--version", [] { return version_line(); });
}

}  // namespace losmimo::apps
