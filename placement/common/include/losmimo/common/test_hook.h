#pragma once
// Test-only pause points: the interruption tests stop a real app binary at a named moment and
// then send it a real signal (SIGTERM, SIGKILL), instead of racing a poller against the run.
//
// With the environment variable LOSMIMO_TEST_PAUSE="<point>" or "<point>#<n>" set, the n-th
// (default: first) call of test_pause_point(<point>) creates the file named by
// LOSMIMO_TEST_PAUSE_MARK (if set), then waits for a signal and never returns. Without the
// variable (every normal run) the call does nothing but one getenv. With "<point>:spin" it
// burns CPU instead of waiting (to test CPU limits). Points are named
// "<app>.<moment>", e.g. "experiment.point_done", "staged.before_rename", "sandbox.parsing".

namespace losmimo::common {

void test_pause_point(const char* point);

}  // namespace losmimo::common
