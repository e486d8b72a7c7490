// Deterministic input mutations (tests/fuzz/mutator.h).
#include "tests/fuzz/mutator.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>

namespace iblx::fuzz {

namespace {

// Values that sit on the edges readers must check: sizes of 0, 1 and 2^31 - 1, negative counts, the top
// bit, and (as 64-bit patterns) NaN, +-Inf, -1.0 and the largest double.
constexpr std::array<std::uint8_t, 6> kInterestingBytes = {0x00, 0x01, 0x7f, 0x80, 0xff, 0x0a};
constexpr std::array<std::uint32_t, 10> kInteresting32 = {
    0, 1, 2, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0x0000ffffu, 0x00010000u, 4096, 0x3f800000u /* 1.0f */};
constexpr std::array<std::uint64_t, 8> kInteresting64 = {
    0,
    ~0ull,
    0x7ff8000000000000ull,  // NaN
    0x7ff0000000000000ull,  // +Inf
    0xfff0000000000000ull,  // -Inf
    0xbff0000000000000ull,  // -1.0
    0x7fefffffffffffffull,  // the largest double
    0x4000000000000000ull,  // 2^62 as an integer, 2.0 as a double
};
// Replacements for a number in text: extremes of every type a parser may convert to.
constexpr std::array<std::string_view, 14> kInterestingNumbers = {
    "0",      "-1",     "nan",        "inf",         "-inf",       "1e309",
    "-1e309", "1e-320", "4294967296", "-2147483649", "2147483647", "99999999999999999999",
    "0x1p4",  "1.#QNAN"};

void putLittleEndian(Bytes& bytes, std::size_t at, std::uint64_t value, std::size_t width) {
  for (std::size_t i = 0; i < width && at + i < bytes.size(); ++i)
    bytes[at + i] = std::uint8_t(value >> (8 * i));
}

// The extent [begin, end) of a run of number characters around `at`, or an empty range.
std::pair<std::size_t, std::size_t> numberAround(const Bytes& bytes, std::size_t at) {
  auto isNumberChar = [](std::uint8_t c) {
    return std::isdigit(c) || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
  };
  // Search forward from `at` for a digit, then extend both ways.
  std::size_t digit = at;
  while (digit < bytes.size() && !std::isdigit(bytes[digit])) ++digit;
  if (digit == bytes.size()) return {0, 0};
  std::size_t begin = digit, end = digit;
  while (begin > 0 && isNumberChar(bytes[begin - 1])) --begin;
  while (end < bytes.size() && isNumberChar(bytes[end])) ++end;
  return {begin, end};
}

// Start offsets of the lines of a text input.
std::vector<std::size_t> lineStarts(const Bytes& bytes) {
  std::vector<std::size_t> starts = {0};
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
    if (bytes[i] == '\n') starts.push_back(i + 1);
  return starts;
}

void mutateOnce(Bytes& bytes, std::span<const Bytes> corpus, SplitMix64& rng) {
  const std::size_t size = bytes.size();
  switch (rng.below(12)) {
    case 0:  // truncate
      if (size > 0) bytes.resize(rng.below(size));
      break;
    case 1:  // flip 1 to 8 bits
      if (size > 0)
        for (std::size_t k = 1 + rng.below(8); k > 0; --k)
          bytes[rng.below(size)] ^= std::uint8_t(1u << rng.below(8));
      break;
    case 2:  // a byte set to an extreme
      if (size > 0) bytes[rng.below(size)] = kInterestingBytes[rng.below(kInterestingBytes.size())];
      break;
    case 3: {  // a 32-bit length or count field set to an extreme (aligned: headers are)
      if (size < 4) break;
      const std::size_t at = rng.below(size - 3) & ~std::size_t(3);
      std::uint32_t value = kInteresting32[rng.below(kInteresting32.size())];
      if (rng.chance(4)) value = std::uint32_t(size + rng.below(9) - 4);  // near the input's own size
      putLittleEndian(bytes, at, value, 4);
      break;
    }
    case 4: {  // a 64-bit field (a size, an offset, a double) set to an extreme
      if (size < 8) break;
      const std::size_t at = rng.below(size - 7) & ~std::size_t(rng.chance(2) ? 7 : 3);
      putLittleEndian(bytes, at, kInteresting64[rng.below(kInteresting64.size())], 8);
      break;
    }
    case 5: {  // a number in text set to an extreme
      if (size == 0) break;
      const auto [begin, end] = numberAround(bytes, rng.below(size));
      if (begin == end) break;
      const std::string_view number = kInterestingNumbers[rng.below(kInterestingNumbers.size())];
      bytes.erase(bytes.begin() + std::ptrdiff_t(begin), bytes.begin() + std::ptrdiff_t(end));
      bytes.insert(bytes.begin() + std::ptrdiff_t(begin), number.begin(), number.end());
      break;
    }
    case 6: {  // delete a range
      if (size == 0) break;
      const std::size_t at = rng.below(size), count = 1 + rng.below(std::min<std::size_t>(size - at, 64));
      bytes.erase(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + count));
      break;
    }
    case 7: {  // duplicate a range in place
      if (size == 0) break;
      const std::size_t at = rng.below(size), count = 1 + rng.below(std::min<std::size_t>(size - at, 256));
      const Bytes chunk(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + count));
      bytes.insert(bytes.begin() + std::ptrdiff_t(at + count), chunk.begin(), chunk.end());
      break;
    }
    case 8: {  // insert random bytes
      const std::size_t at = size == 0 ? 0 : rng.below(size + 1), count = 1 + rng.below(16);
      Bytes chunk(count);
      for (auto& b : chunk) b = std::uint8_t(rng.next());
      bytes.insert(bytes.begin() + std::ptrdiff_t(at), chunk.begin(), chunk.end());
      break;
    }
    case 9: {  // splice: the head of this input and the tail of another
      const Bytes& other = corpus[rng.below(corpus.size())];
      if (other.empty()) break;
      const std::size_t cut = size == 0 ? 0 : rng.below(size + 1), from = rng.below(other.size());
      bytes.resize(cut);
      bytes.insert(bytes.end(), other.begin() + std::ptrdiff_t(from), other.end());
      break;
    }
    case 10: {  // splice: a chunk of another input inserted
      const Bytes& other = corpus[rng.below(corpus.size())];
      if (other.empty()) break;
      const std::size_t from = rng.below(other.size()),
                        count = 1 + rng.below(std::min<std::size_t>(other.size() - from, 128));
      const std::size_t at = size == 0 ? 0 : rng.below(size + 1);
      bytes.insert(bytes.begin() + std::ptrdiff_t(at), other.begin() + std::ptrdiff_t(from),
                   other.begin() + std::ptrdiff_t(from + count));
      break;
    }
    default: {  // text: a line deleted, duplicated or moved
      const std::vector<std::size_t> starts = lineStarts(bytes);
      if (starts.size() < 2) break;
      const std::size_t line = rng.below(starts.size() - 1);
      const Bytes text(bytes.begin() + std::ptrdiff_t(starts[line]),
                       bytes.begin() + std::ptrdiff_t(starts[line + 1]));
      const std::size_t op = rng.below(3);
      if (op != 1)
        bytes.erase(bytes.begin() + std::ptrdiff_t(starts[line]),
                    bytes.begin() + std::ptrdiff_t(starts[line + 1]));
      if (op != 0) {
        const std::vector<std::size_t> now = lineStarts(bytes);
        const std::size_t to = now[rng.below(now.size())];
        bytes.insert(bytes.begin() + std::ptrdiff_t(to), text.begin(), text.end());
      }
      break;
    }
  }
}

}  // namespace

Bytes mutate(const Bytes& input, std::span<const Bytes> corpus, SplitMix64& rng, std::size_t maxBytes) {
  Bytes bytes = input;
  for (std::size_t k = 1 + rng.below(4); k > 0; --k) mutateOnce(bytes, corpus, rng);
  if (bytes.size() > maxBytes) bytes.resize(maxBytes);
  return bytes;
}

}  // namespace iblx::fuzz
