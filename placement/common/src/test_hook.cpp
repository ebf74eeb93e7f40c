#include "losmimo/placement/common/test_hook.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <string>

namespace losmimo::common {

bool test_hooks_compiled_in() { return LOSMIMO_TEST_HOOKS != 0; }

#if LOSMIMO_TEST_HOOKS
inline namespace test_hooks_on {

void test_pause_point(const char* point) {
  const char* spec = std::getenv("LOSMIMO_TEST_PAUSE");
  if (spec == nullptr) return;
  std::string s(spec);
  const bool spin = s.size() > 5 && s.compare(s.size() - 5, 5, ":spin") == 0;
  if (spin) s.resize(s.size() - 5);
  const std::size_t hash = s.find('#');
  if (s.substr(0, hash) != point) return;
  const long nth = hash == std::string::npos ? 1 : std::atol(s.c_str() + hash + 1);
  static std::atomic<long> passes{0};  // one point per process is paused, so one counter does
  if (++passes != nth) return;
  if (const char* mark = std::getenv("LOSMIMO_TEST_PAUSE_MARK")) {
    const int fd = ::open(mark, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) ::close(fd);
  }
  volatile unsigned long burn = 0;
  while (spin) burn = burn + 1;
  while (true) ::pause();
}

}  // namespace test_hooks_on
#endif

}  // namespace losmimo::common
