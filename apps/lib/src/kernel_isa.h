#pragma once
// The placement kernels' instruction set (losmimo/placement/isa.h), checked where an app checks
// its input: a LOSMIMO_ISA that names no instruction set, or one this CPU cannot run, is the
// user's to fix (InputError: kExitBadInput, before any work or file), not a failure mid-run.
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/isa.h"

namespace losmimo::apps {

// "sse2", "avx2" or "avx512".
inline std::string kernel_isa_name() {
  try {
    return placement::to_string(placement::active_isa());
  } catch (const std::invalid_argument& e) {
    throw common::InputError(e.what());
  }
}

}  // namespace losmimo::apps
