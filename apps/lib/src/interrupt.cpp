#include "losmimo/apps/lib/interrupt.h"

#include <csignal>
#include <cstring>

#include <unistd.h>

namespace losmimo::apps {

namespace {

// Written by the handler: set once, before the handlers are installed, never changed after.
std::string& interrupt_message() {
  static std::string message;
  return message;
}

extern "C" void write_message_and_exit(int signal) {
  const std::string& m = interrupt_message();
  // write(2) and _exit(2) are async-signal-safe; nothing else runs here.
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, m.data(), m.size());
  ::_exit(128 + signal);
}

std::string shell_quoted(const std::string& a) {
  if (!a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@%") ==
                        std::string::npos)
    return a;
  std::string q = "'";
  for (const char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string experiment_resume_command(const std::vector<std::string>& args, const std::string& dir) {
  std::string cmd;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (i > 0 && (a == "--out" || a == "--resume")) {
      ++i;  // and its value
      continue;
    }
    if (i > 0 && (a == "--replace" || a.rfind("--out=", 0) == 0 || a.rfind("--resume=", 0) == 0)) continue;
    cmd += (cmd.empty() ? "" : " ") + shell_quoted(a);
  }
  return cmd + " --resume " + shell_quoted(dir);
}

std::string experiment_interrupt_message(const std::vector<std::string>& args, const std::string& dir) {
  return "\nlosmimo-experiment: interrupted; the trials finished so far are kept in " + dir +
         ".partial. Continue the run with:\n  " + experiment_resume_command(args, dir) + "\n";
}

void install_interrupt_message(const std::string& message) {
  interrupt_message() = message;
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = write_message_and_exit;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace losmimo::apps
