#pragma once
// What `losmimo-experiment` says when it is interrupted (SIGINT, SIGTERM): the folder that keeps
// the finished trials and the exact command that continues the run, then exit 128 + signal
// (130 for Ctrl-C), as a shell reports a process the signal ended.
#include <string>
#include <vector>

namespace losmimo::apps {

// The command line that continues the run of `args` (argv, program first): every argument kept
// but --out, --replace and --resume (with their values), then `--resume DIR`; each argument
// shell-quoted where it needs it.
std::string experiment_resume_command(const std::vector<std::string>& args, const std::string& dir);

// The message printed on an interrupt of a run into `dir` started as `args`.
std::string experiment_interrupt_message(const std::vector<std::string>& args, const std::string& dir);

// Installs SIGINT and SIGTERM handlers that write `message` to stderr and _exit(128 + signal).
// The checkpoint in <dir>.partial is complete at any instant (staged_output.h), so ending there
// loses no finished trial.
void install_interrupt_message(const std::string& message);

}  // namespace losmimo::apps
