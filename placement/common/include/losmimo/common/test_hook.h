#pragma once
// Test-only pause points: the interruption tests stop a real app binary at a named moment and
// then send it a real signal (SIGTERM, SIGKILL), instead of racing a poller against the run.
//
// With the environment variable LOSMIMO_TEST_PAUSE="<point>" or "<point>#<n>" set, the n-th
// (default: first) call of test_pause_point(<point>) creates the file named by
// LOSMIMO_TEST_PAUSE_MARK (if set), then waits for a signal and never returns. Without the
// variable (every normal run) the call does nothing but one getenv. Points are named
// "<app>.<moment>", e.g. "experiment.point_done", "staged.before_rename".

namespace losmimo::common {

void test_pause_point(const char* point);

}  // namespace losmimo::common
