// Tests of engine/core/hash.h: ContentHash is deterministic, matches FNV-1a and changes with any single byte.
#include "engine/core/hash.h"

#include <doctest/doctest.h>

#include <set>
#include <vector>

using iblx::ContentHash;

TEST_CASE("hash: FNV-1a reference values") {
  // Published FNV-1a 64-bit test vectors (Fowler, Noll, Vo).
  CHECK(ContentHash().value() == 0xcbf29ce484222325ull);
  CHECK(ContentHash().add("a").value() == 0xaf63dc4c8601ec8cull);
  CHECK(ContentHash().add("foobar").value() == 0x85944171f73967e8ull);
}

TEST_CASE("hash: deterministic and chunking-independent") {
  std::vector<float> table(1000);
  for (std::size_t i = 0; i < table.size(); ++i) table[i] = float(i) * 0.25f;
  const std::span<const float> all(table);
  const auto h1 = ContentHash().add("env-cdf").add(all).value();
  const auto h2 = ContentHash().add("env-cdf").add(all).value();
  CHECK(h1 == h2);
  // Feeding the same bytes in two pieces gives the same hash.
  CHECK(ContentHash().add("env-").add("cdf").add(all.first(300)).add(all.subspan(300)).value() == h1);
}

TEST_CASE("hash: sensitive to every single byte") {
  std::vector<unsigned char> bytes(256);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 37 + 11);
  const auto base = ContentHash().addBytes(bytes.data(), bytes.size()).value();
  std::set<std::uint64_t> seen{base};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (const unsigned char flip : {0x01, 0x80}) {
      auto changed = bytes;
      changed[i] ^= flip;
      const auto h = ContentHash().addBytes(changed.data(), changed.size()).value();
      CHECK(h != base);
      seen.insert(h);
    }
  }
  CHECK(seen.size() == 1 + 2 * bytes.size());  // no collisions among the 512 one-bit changes
  // Length matters too: a trailing zero byte changes the hash.
  const unsigned char zero = 0;
  CHECK(ContentHash().addBytes(bytes.data(), bytes.size()).addBytes(&zero, 1).value() != base);
}
