#pragma once
// How the apps print a failure: "<app>: <message>" with the message made printable (long values
// shortened, invisible bytes escaped: common/message.h), and for an output that is in the way
// what the user can do about it.
#include <exception>
#include <ostream>
#include <string>

#include "losmimo/common/message.h"
#include "losmimo/common/staged_output.h"

namespace losmimo::apps {

inline void print_error(std::ostream& err, const std::string& app, const std::string& message) {
  err << app << ": " << common::printable_message(message) << "\n";
}

// `option` names the output option ("--out"); the hint depends on whether --replace would help.
inline void print_output_exists(std::ostream& err, const std::string& app, const common::OutputExistsError& e,
                                const std::string& option) {
  print_error(err, app,
              std::string(option) + ": " + e.what() +
                  (e.replaceable() ? "; choose another " + option + " or pass --replace to replace it whole"
                                   : "; choose another " + option));
}

}  // namespace losmimo::apps
