// The recorder's CSI generator seed (rawlog/recorder.h): a log's CSI bytes depend on it, so it
// must stay the mission seed XOR the stream tag the shipped logs were recorded with.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "losmimo/placement/common/seed.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"

namespace losmimo::rawlog {
namespace {

TEST(RecorderCsiSeed, EqualsTheMissionSeedXorTheRecordedLogsTag) {
  // The tag as the shipped logs were recorded with it, written out by hand.
  constexpr std::uint64_t kRecordedTag = 0x5EED'C51C'0000'0006ULL;
  for (const std::uint64_t seed :
       {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{42}, std::uint64_t{20250101},
        std::uint64_t{0x5EED'C51C'0000'0006ULL}, std::uint64_t{1} << 63, std::numeric_limits<std::uint64_t>::max()}) {
    EXPECT_EQ(recorder_csi_seed(seed), seed ^ kRecordedTag) << "seed " << seed;
  }
  // Negative control: the mixed derivation (derive_seed) with the same tag is another stream.
  EXPECT_NE(recorder_csi_seed(42), common::derive_seed(42, {kRecordedTag}));
}

}  // namespace
}  // namespace losmimo::rawlog
