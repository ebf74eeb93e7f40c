#pragma once
// How the apps print a failure: "<app>: <message>" with the message made printable (long values
// shortened, invisible bytes escaped: message.h), and for an output that is in the way
// what the user can do about it.
#include <exception>
#include <ostream>
#include <string>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/message.h"
#include "losmimo/apps/lib/staged_output.h"

namespace losmimo::apps {

inline void print_error(std::ostream& err, const std::string& app, const std::string& message) {
  err << app << ": " << printable_message(message) << "\n";
}

// `option` names the output option ("--out"); the hint depends on whether --replace would help.
inline void print_output_exists(std::ostream& err, const std::string& app, const OutputExistsError& e,
                                const std::string& option) {
  std::string hint = e.replaceable() ? "; choose another " + option + " or pass --replace to replace it whole"
                                     : "; choose another " + option;
  if (!e.resume_dir().empty()) {
    hint = "; continue it with --resume " + e.resume_dir() + " (and the same options), choose another " + option +
           ", or pass --replace to start it again";
  }
  print_error(err, app, std::string(option) + ": " + e.what() + hint);
}

// Called inside a catch (...): prints the exception being handled and returns the app's exit code.
// An output in the way (named as `output_option`) and bad input are the user's to fix
// (kExitBadInput); any other error is "<app>: error: <what>", kExitFailure.
inline int report_current_exception(std::ostream& err, const std::string& app,
                                    const std::string& output_option = "--out") {
  try {
    throw;
  } catch (const OutputExistsError& e) {
    print_output_exists(err, app, e, output_option);
    return kExitBadInput;
  } catch (const common::InputError& e) {
    print_error(err, app, e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error(err, app, std::string("error: ") + e.what());
    return kExitFailure;
  }
}

}  // namespace losmimo::apps
