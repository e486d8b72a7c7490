// BigBuffer: large blocks on 2 MiB boundaries (where huge pages can back them), contents kept across growth,
// explicit fill values honoured.
#include "engine/core/big_buffer.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <numeric>

using namespace iblx;

TEST_CASE("BigBuffer aligns large blocks to 2 MiB and keeps small ones ordinary") {
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
  BigBuffer<float> large;
  large.resize(3 << 20);  // 12 MiB
  CHECK(reinterpret_cast<std::uintptr_t>(large.data()) % kHugePage == 0);
  BigBuffer<double> small(100, 1.5);
  CHECK(small.size() == 100);
  CHECK(small[99] == 1.5);
}

TEST_CASE("BigBuffer keeps its contents when it grows and fills with an explicit value") {
  BigBuffer<double> values(1000);
  std::iota(values.begin(), values.end(), 0.0);
  values.resize(std::size_t(1) << 20);  // reallocates onto a 2 MiB-aligned block
  for (std::size_t i = 0; i < 1000; ++i) REQUIRE(values[i] == double(i));
  values.resize(values.size() + 10, -2.0);
  for (std::size_t i = values.size() - 10; i < values.size(); ++i) CHECK(values[i] == -2.0);
}
