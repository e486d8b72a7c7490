// A minimal, independent OpenEXR encoder for tests: single-part scanline files without compression, with any
// channel names, HALF/FLOAT/UINT channels, subsampling and any data window. It produces the inputs the
// engine's writer never does (half RGBA, luminance-only, offset windows) and checks the loader against the
// file format itself rather than against OpenEXR's own writer. (The test executable links OpenEXR only
// through iblx_io, without its headers, so the bytes are laid out here: see "The OpenEXR File Layout",
// openexr.com.)
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace iblx::test {

enum class ExrPixelType : std::int32_t { Uint = 0, Half = 1, Float = 2 };

struct ExrChannelData {
  std::string name;
  ExrPixelType type = ExrPixelType::Float;
  std::vector<float> values;  // one per sampled pixel of the data window, row-major, top row first
  int xSampling = 1,
      ySampling = 1;  // subsampled channels hold only pixels with x % xSampling == 0 (same for y)
};

// float -> IEEE half for values that a half holds exactly (zero, +-Inf, NaN and normal halves); anything else
// throws, so a test never depends on a rounding mode.
inline std::uint16_t floatToHalfExact(float f) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  const std::uint32_t sign = (bits >> 16) & 0x8000u, exponent = (bits >> 23) & 0xffu,
                      mantissa = bits & 0x7fffffu;
  if (exponent == 0xff) return std::uint16_t(sign | 0x7c00u | (mantissa ? 0x200u : 0u));
  if (exponent == 0 && mantissa == 0) return std::uint16_t(sign);
  const int halfExponent = int(exponent) - 127 + 15;
  if (halfExponent <= 0 || halfExponent >= 31 || (mantissa & 0x1fffu))
    throw std::invalid_argument("value not exactly representable as a normal half: " + std::to_string(f));
  return std::uint16_t(sign | std::uint32_t(halfExponent) << 10 | mantissa >> 13);
}

class ExrEncoder {
 public:
  std::vector<unsigned char> encode(int xMin, int yMin, int width, int height,
                                    std::vector<ExrChannelData> channels) {
    // Channels are stored sorted by name, in the header and within each scanline.
    std::sort(channels.begin(), channels.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    for (const auto& c : channels)
      if (c.values.size() !=
          std::size_t(sampled(xMin, width, c.xSampling)) * sampled(yMin, height, c.ySampling))
        throw std::invalid_argument("channel " + c.name + " has the wrong number of values");
    out_.clear();
    put32(20000630);  // magic
    put32(2);         // version 2, single-part scanline, short names

    std::vector<unsigned char> list;
    for (const auto& c : channels) {
      list.insert(list.end(), c.name.begin(), c.name.end());
      list.push_back(0);
      append32(list, std::int32_t(c.type));
      append32(list, 0);  // pLinear + 3 reserved bytes
      append32(list, c.xSampling);
      append32(list, c.ySampling);
    }
    list.push_back(0);
    attribute("channels", "chlist", list);
    attribute("compression", "compression", {0});  // NO_COMPRESSION: one scanline per chunk
    std::vector<unsigned char> box;
    for (int v : {xMin, yMin, xMin + width - 1, yMin + height - 1}) append32(box, v);
    attribute("dataWindow", "box2i", box);
    attribute("displayWindow", "box2i", box);
    attribute("lineOrder", "lineOrder", {0});  // INCREASING_Y
    attribute("pixelAspectRatio", "float", floatBytes(1.0f));
    std::vector<unsigned char> center = floatBytes(0.0f), zero = floatBytes(0.0f);
    center.insert(center.end(), zero.begin(), zero.end());
    attribute("screenWindowCenter", "v2f", center);
    attribute("screenWindowWidth", "float", floatBytes(1.0f));
    out_.push_back(0);  // end of header

    // Offset table, then one chunk per scanline: y, byte count, each channel's values for the whole line.
    tableStart_ = out_.size();
    const std::size_t tableStart = tableStart_;
    out_.resize(tableStart + 8 * std::size_t(height));
    for (int y = 0; y < height; ++y) {
      const std::uint64_t offset = out_.size();
      for (int b = 0; b < 8; ++b) out_[tableStart + 8 * std::size_t(y) + b] = (offset >> (8 * b)) & 0xff;
      std::vector<unsigned char> line;
      for (const auto& c : channels) {
        if ((yMin + y) % c.ySampling != 0) continue;
        const int rowLength = sampled(xMin, width, c.xSampling);
        const std::size_t row = std::size_t(sampled(yMin, y, c.ySampling));  // sampled rows above this one
        for (int x = 0; x < rowLength; ++x) {
          const float v = c.values[row * std::size_t(rowLength) + std::size_t(x)];
          if (c.type == ExrPixelType::Half) {
            const std::uint16_t h = floatToHalfExact(v);
            line.push_back(h & 0xff);
            line.push_back(h >> 8);
          } else if (c.type == ExrPixelType::Float) {
            append32(line, std::bit_cast<std::int32_t>(v));
          } else {
            append32(line, std::int32_t(std::uint32_t(v)));
          }
        }
      }
      put32(yMin + y);
      put32(std::int32_t(line.size()));
      out_.insert(out_.end(), line.begin(), line.end());
    }
    return out_;
  }

  // Where the last encode() put the scanline offset table (8 bytes per scanline): tests zero it to mimic a
  // writer that died before finishing the file.
  std::size_t offsetTableStart() const { return tableStart_; }

 private:
  // How many of the coordinates start, start+1, ..., start+count-1 are multiples of sampling (start >= 0).
  static int sampled(int start, int count, int sampling) {
    return (start + count + sampling - 1) / sampling - (start + sampling - 1) / sampling;
  }
  static void append32(std::vector<unsigned char>& v, std::int32_t x) {
    const auto u = std::uint32_t(x);
    for (int b = 0; b < 4; ++b) v.push_back((u >> (8 * b)) & 0xff);
  }
  static std::vector<unsigned char> floatBytes(float f) {
    std::vector<unsigned char> v;
    append32(v, std::bit_cast<std::int32_t>(f));
    return v;
  }
  void put32(std::int32_t x) { append32(out_, x); }
  void attribute(const std::string& name, const std::string& type, const std::vector<unsigned char>& value) {
    out_.insert(out_.end(), name.begin(), name.end());
    out_.push_back(0);
    out_.insert(out_.end(), type.begin(), type.end());
    out_.push_back(0);
    put32(std::int32_t(value.size()));
    out_.insert(out_.end(), value.begin(), value.end());
  }

  std::vector<unsigned char> out_;
  std::size_t tableStart_ = 0;
};

}  // namespace iblx::test
