// Only whole pages inside the range are handed back; the bytes around them
// keep their values, and the array stays usable.

#include "engine/core/page_release.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <vector>

namespace granflow {
namespace {

TEST(PageRelease, ReleasesWholePagesInsideTheRangeOnly) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  std::vector<std::uint8_t> bytes(16 * page, 7);
  // From the middle of one page to the middle of another: the partial pages keep their bytes.
  const std::size_t from = 3 * page / 2, to = 9 * page + page / 2;
  release_pages(bytes.data() + from, to - from);
  const auto address = [&](std::size_t k) { return reinterpret_cast<std::uintptr_t>(bytes.data() + k); };
  std::size_t released = 0;
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    const bool whole_page_inside = address(k) / page * page >= address(from) &&
                                   (address(k) / page + 1) * page <= address(to);
    if (!whole_page_inside) {
      ASSERT_EQ(bytes[k], 7) << "byte " << k << " outside the released pages changed";
    } else {
#if defined(__linux__)
      ASSERT_EQ(bytes[k], 0) << "byte " << k << " of a released page still holds its value";
#endif
      ++released;
    }
  }
  EXPECT_GE(released, 7 * page);
  bytes[from + page] = 3;  // writable again
  EXPECT_EQ(bytes[from + page], 3);
}

TEST(PageRelease, ARangeShorterThanAPageIsLeftAlone) {
  std::vector<double> values(64, 1.5);
  release_pages(values);
  for (double v : values) EXPECT_EQ(v, 1.5);
}

}  // namespace
}  // namespace granflow
