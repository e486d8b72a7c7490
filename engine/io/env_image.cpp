// Loading lat-long environment maps (.exr through OpenEXR, Radiance .hdr through our own decoder) and the
// sanitation that guarantees every texel handed to the samplers is finite and >= 0 (docs/DESIGN.md §5).
#include "engine/io/env_image.h"

#include "engine/core/error.h"
#include "engine/core/join.h"
#include "engine/core/file_io.h"
#include "engine/core/file_names.h"
#include "engine/core/log.h"

#include <ImfArray.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfRgbaFile.h>
#include <ImfStdIO.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <new>
#include <span>
#include <sstream>
#include <string>

namespace iblx {
namespace {

namespace fs = std::filesystem;

// Per-side limit on image dimensions: far above any real lat-long map (2^24 texels is 8192 x 2048), low
// enough that a corrupt header cannot request an absurd allocation.
constexpr long kMaxDimension = 1L << 20;

[[noreturn]] void throwCannotOpen(const fs::path& path, const std::string& reason) {
  throw Error("cannot open " + path.string() + ": " + reason);
}

// Bytes of the float RGB image a header promises, checked against the memory budget before it is allocated.
void checkImageBudget(const std::string& file, long width, long height) {
  checkMemoryBudget(file + ": the " + std::to_string(width) + "x" + std::to_string(height) + " image",
                    std::uint64_t(width) * std::uint64_t(height) * 3 * sizeof(float));
}

// -----------------------------------------------------------------------------------------------------------
// Radiance .hdr (RGBE). stb_image's loader is not used: on truncated input it returns zero-filled scanlines
// for flat files and loops forever on run-length-encoded ones (stb 2.x as shipped by Debian 12), while a map
// that is silently partly black would bias every estimator. The format is small enough to decode with every
// read bounds-checked. Reference: Greg Ward, "Real Pixels", Graphics Gems II (1991), and Radiance's color.c.

class HdrDecoder {
 public:
  HdrDecoder(std::span<const unsigned char> bytes, std::string file)
      : bytes_(bytes), file_(std::move(file)) {}

  EnvImage decode() {
    // Header: a "#?" signature line, variable lines up to an empty line, then the resolution line.
    const std::string signature = readLine();
    if (signature.rfind("#?", 0) != 0)
      throw Error("not a Radiance .hdr file " + file_ + ": it does not begin with the \"#?\" signature");
    for (;;) {
      if (pos_ >= bytes_.size()) throw corrupt("the header has no end (no empty line before the resolution)");
      const std::string line = readLine();
      if (line.empty()) break;
      // EXPOSURE and PRIMARIES lines are ignored, like stb_image, pbrt and most renderers do: pixel values
      // are taken as the radiance the file stores.
      if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe")
        throw Error(file_ + ": unsupported Radiance pixel format '" + line.substr(7) +
                    "' (only 32-bit_rle_rgbe is supported; convert XYZE files to RGBE)");
    }
    parseResolution(readLine());

    const std::size_t width = std::size_t(width_), height = std::size_t(height_);
    // New-style run-length encoding is only defined for widths in [8, 32767]; other widths are always flat.
    const bool rleWidth = width >= 8 && width <= 0x7fff;
    // Smallest possible scanline: the 4-byte RLE header plus one 2-byte run per 127 pixels of each of the 4
    // components; flat scanlines take 4 bytes per pixel. Checking it first rejects most truncated files with
    // a clear message and keeps a corrupt header from allocating gigabytes for a tiny file.
    const std::size_t minScanline = rleWidth ? 4 + 8 * ((width + 126) / 127) : 4 * width;
    if (remaining() / minScanline < height)
      throw corrupt("the file is too short for a " + std::to_string(width) + "x" + std::to_string(height) +
                    " image (" + std::to_string(remaining()) + " bytes of pixel data)");

    checkImageBudget(file_, width_, height_);
    EnvImage image;
    image.width = width_;
    image.height = height_;
    image.rgb.resize(3 * image.texelCount());
    std::vector<unsigned char> scanline(4 * width);
    for (std::size_t y = 0; y < height; ++y) {
      if (rleWidth && remaining() >= 4 && bytes_[pos_] == 2 && bytes_[pos_ + 1] == 2 &&
          !(bytes_[pos_ + 2] & 0x80))
        readRleScanline(y, scanline);
      else
        readFlatScanline(y, scanline);
      // The resolution line says where scanline y goes: "-Y" is top-down (the usual), "+Y" bottom-up; "-X"
      // mirrors.
      const std::size_t row = topDown_ ? y : height - 1 - y;
      for (std::size_t x = 0; x < width; ++x) {
        const std::size_t column = leftToRight_ ? x : width - 1 - x;
        rgbeToFloat(&scanline[4 * x], &image.rgb[3 * (row * width + column)]);
      }
    }
    return image;
  }

 private:
  Error corrupt(const std::string& why) const {
    return Error("corrupt or truncated .hdr file " + file_ + ": " + why);
  }
  Error truncated(std::size_t y) const {
    return corrupt("the data ends inside scanline " + std::to_string(y) + " of " + std::to_string(height_));
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }

  // One header line without its '\n'. Lines are capped so a binary file cannot be taken for a huge header.
  std::string readLine() {
    std::string line;
    while (pos_ < bytes_.size() && bytes_[pos_] != '\n') {
      if (line.size() >= 4096) throw corrupt("header line longer than 4096 bytes");
      line.push_back(char(bytes_[pos_++]));
    }
    if (pos_ >= bytes_.size()) throw corrupt("the file ends inside the header");
    ++pos_;  // the '\n'
    // Files written on Windows end header lines with "\r\n"; the '\r' is not part of the line.
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }

  void parseResolution(const std::string& line) {
    std::istringstream in(line);
    std::string axis0, axis1;
    long n0 = 0, n1 = 0;
    if (!(in >> axis0 >> n0 >> axis1 >> n1)) throw corrupt("unreadable resolution line '" + line + "'");
    if (axis0 == "-X" || axis0 == "+X")
      throw Error(file_ + ": column-major .hdr orientation '" + line +
                  "' is not supported (expected -Y H +X W)");
    if ((axis0 != "-Y" && axis0 != "+Y") || (axis1 != "+X" && axis1 != "-X"))
      throw corrupt("unreadable resolution line '" + line + "'");
    if (n0 <= 0 || n1 <= 0 || n0 > kMaxDimension || n1 > kMaxDimension)
      throw corrupt("invalid image size in resolution line '" + line + "'");
    topDown_ = axis0 == "-Y";
    leftToRight_ = axis1 == "+X";
    height_ = int(n0);
    width_ = int(n1);
  }

  // New-style RLE: each of the 4 components separately, as runs (count > 128: repeat the next byte count-128
  // times) and literals (count <= 128: copy the next count bytes).
  void readRleScanline(std::size_t y, std::vector<unsigned char>& scanline) {
    const std::size_t width = std::size_t(width_);
    const std::size_t length = std::size_t(bytes_[pos_ + 2]) << 8 | bytes_[pos_ + 3];
    if (length != width)
      throw corrupt("scanline " + std::to_string(y) + " has length " + std::to_string(length) +
                    ", expected " + std::to_string(width));
    pos_ += 4;
    for (std::size_t k = 0; k < 4; ++k) {
      for (std::size_t x = 0; x < width;) {
        if (remaining() < 1) throw truncated(y);
        std::size_t count = bytes_[pos_++];
        const bool run = count > 128;
        if (run) count -= 128;
        if (count > width - x) throw corrupt("a run overflows scanline " + std::to_string(y));
        if (run) {
          if (remaining() < 1) throw truncated(y);
          const unsigned char value = bytes_[pos_++];
          for (std::size_t i = 0; i < count; ++i) scanline[4 * x++ + k] = value;
        } else {
          if (remaining() < count) throw truncated(y);
          for (std::size_t i = 0; i < count; ++i) scanline[4 * x++ + k] = bytes_[pos_++];
        }
      }
    }
  }

  void readFlatScanline(std::size_t y, std::vector<unsigned char>& scanline) {
    const std::size_t width = std::size_t(width_);
    if (remaining() < 4 * width) throw truncated(y);
    std::copy_n(bytes_.begin() + std::ptrdiff_t(pos_), 4 * width, scanline.begin());
    pos_ += 4 * width;
    // (1, 1, 1, n) is a repeat marker of Radiance's pre-1991 encoding; no normalizing writer produces it as a
    // pixel (the largest mantissa is always >= 128), so report it rather than decode it as a dim texel.
    for (std::size_t x = 0; x < width; ++x)
      if (scanline[4 * x] == 1 && scanline[4 * x + 1] == 1 && scanline[4 * x + 2] == 1)
        throw Error(file_ + ": old-style (pre-1991) Radiance run-length encoding is not supported");
  }

  // RGBE -> float as stb_image and Radiance's writers round-trip it: mantissa * 2^(e - 136), e = 0 is black.
  // (No +0.5 mantissa offset, so that exactly-zero components stay zero.)
  static void rgbeToFloat(const unsigned char* rgbe, float* rgb) {
    if (rgbe[3] == 0) {
      rgb[0] = rgb[1] = rgb[2] = 0.0f;
      return;
    }
    const float scale = std::ldexp(1.0f, int(rgbe[3]) - (128 + 8));
    for (int c = 0; c < 3; ++c) rgb[c] = float(rgbe[c]) * scale;
  }

  std::span<const unsigned char> bytes_;
  std::string file_;
  std::size_t pos_ = 0;
  int width_ = 0, height_ = 0;
  bool topDown_ = true, leftToRight_ = true;
};

EnvImage readHdr(const fs::path& path) {
  // The largest .hdr the memory budget admits: 4 bytes per texel when stored flat.
  const std::vector<unsigned char> bytes = readInputFile(path, memoryBudgetBytes() / 3);
  if (bytes.empty()) throw Error("corrupt or truncated .hdr file " + path.string() + ": the file is empty");
  return HdrDecoder(bytes, path.string()).decode();
}

// -----------------------------------------------------------------------------------------------------------
// OpenEXR. The general InputFile is used (not RgbaInputFile, which converts to half and would clip a sun
// above 65504 and quantize dim regions): R, G, B are read as FLOAT slices and OpenEXR converts half, float or
// uint channels. Only luminance/chroma files (Y, RY, BY) go through RgbaInputFile, which owns that
// conversion; they are half precision by construction, so nothing is lost.

std::string channelListText(const Imf::ChannelList& channels) {
  std::vector<const char*> names;
  for (auto it = channels.begin(); it != channels.end(); ++it) names.push_back(it.name());
  return names.empty() ? "none" : joinNames(names);
}

EnvImage readExrLuminanceChroma(Imf::IStream& stream, const std::string& fileName) {
  stream.seekg(0);
  Imf::RgbaInputFile file(stream);
  if (!file.isComplete())
    throw Error("corrupt or truncated EXR file " + fileName +
                ": the file is incomplete (unfinished offset table)");
  const Imath::Box2i dataWindow = file.dataWindow();
  const long width = long(dataWindow.max.x) - dataWindow.min.x + 1;
  const long height = long(dataWindow.max.y) - dataWindow.min.y + 1;
  if (width <= 0 || height <= 0 || width > kMaxDimension || height > kMaxDimension)
    throw Error("corrupt or truncated EXR file " + fileName + ": invalid data window");
  checkMemoryBudget(fileName + ": the " + std::to_string(width) + "x" + std::to_string(height) + " image",
                    std::uint64_t(width) * std::uint64_t(height) * (sizeof(Imf::Rgba) + 3 * sizeof(float)));
  Imf::Array2D<Imf::Rgba> pixels(height, width);
  file.setFrameBuffer(&pixels[0][0] - dataWindow.min.x - dataWindow.min.y * width, 1, std::size_t(width));
  file.readPixels(dataWindow.min.y, dataWindow.max.y);
  EnvImage image;
  image.width = int(width);
  image.height = int(height);
  image.rgb.resize(3 * image.texelCount());
  for (long y = 0; y < height; ++y)
    for (long x = 0; x < width; ++x) {
      const Imf::Rgba& p = pixels[y][x];
      float* out = &image.rgb[3 * image.index(int(x), int(y))];
      out[0] = float(p.r);
      out[1] = float(p.g);
      out[2] = float(p.b);
    }
  return image;
}

// OpenEXR allocates each header attribute at the size the file claims before reading it, so a few hundred
// bytes can claim gigabytes. The attributes (name\0 type\0 int32 size, value; an empty name ends a header;
// multi-part files hold several headers, ended by an empty one) are walked here first, and a size larger than
// what remains of the file is refused. OpenEXR file layout: openexr.com, "OpenEXR File Layout".
void checkExrAttributeSizes(std::istream& in, std::uint64_t size, const std::string& fileName) {
  unsigned char version[8];
  // Not an EXR (magic 76 2f 31 01) or too short: left to OpenEXR, which says so itself.
  if (!in.read(reinterpret_cast<char*>(version), 8) || version[0] != 0x76 || version[1] != 0x2f ||
      version[2] != 0x31 || version[3] != 0x01)
    return;
  const bool multipart = (version[5] & 0x10) != 0;
  const auto readName = [&](std::string& name) {
    name.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (name.size() >= 255) return false;  // names are at most 255 bytes (long-name flag)
      name += c;
    }
    return false;
  };
  for (int headers = 0; headers < 1024; ++headers) {
    std::string name, type;
    int attributes = 0;
    for (;; ++attributes) {
      if (!readName(name)) return;  // truncated: left to OpenEXR's own message
      if (name.empty()) break;      // end of this header
      if (!readName(type)) return;
      unsigned char bytes[4];
      if (!in.read(reinterpret_cast<char*>(bytes), 4)) return;
      const std::int32_t length = std::int32_t(std::uint32_t(bytes[0]) | std::uint32_t(bytes[1]) << 8 |
                                               std::uint32_t(bytes[2]) << 16 | std::uint32_t(bytes[3]) << 24);
      const std::uint64_t position = std::uint64_t(in.tellg());
      if (length < 0 || std::uint64_t(length) > size - std::min(size, position))
        throw Error(
            "corrupt or truncated EXR file " + fileName + ": header attribute " +
            (std::all_of(name.begin(), name.end(),
                         [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; })
                 ? "'" + name + "'"
                 : std::string("#") + std::to_string(attributes + 1)) +
            " claims " + std::to_string(length) + " bytes, more than the file holds");
      in.seekg(length, std::ios::cur);
    }
    if (!multipart || attributes == 0) return;
  }
}

// `raw` and `stream` read the same bytes: the attribute check walks `raw`, OpenEXR reads `stream`.
EnvImage readExrChannels(std::istream& raw, std::uint64_t size, Imf::IStream& stream,
                         const std::string& file) {
  checkExrAttributeSizes(raw, size, file);
  raw.clear();  // the check may have read to the end; a file's `raw` is also what `stream` reads through
  raw.seekg(0);
  stream.seekg(0);
  Imf::InputFile input(stream);
  const Imf::Header& header = input.header();
  const Imf::ChannelList& channels = header.channels();
  const bool hasRgb = channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
  const bool hasY = channels.findChannel("Y") != nullptr;
  if (!hasRgb && hasY && (channels.findChannel("RY") || channels.findChannel("BY")))
    return readExrLuminanceChroma(stream, file);
  if (!hasRgb && !hasY)
    throw Error(file + ": no R, G, B (or Y) channels; the file has channels " + channelListText(channels));
  const std::vector<const char*> names =
      hasRgb ? std::vector<const char*>{"R", "G", "B"} : std::vector<const char*>{"Y"};
  for (const char* name : names) {
    const Imf::Channel* channel = channels.findChannel(name);
    if (channel->xSampling != 1 || channel->ySampling != 1)
      throw Error(file + ": subsampled channel " + name + " is not supported");
  }

  // A truncated copy makes readPixels throw (OpenEXR 3.1: "Early end of file"), but a file whose writer died
  // before it wrote the offset table is read by scanning for chunks, and isComplete() is the only sign of it.
  // Such a file is rejected even when every chunk happens to be present: its last chunk cannot be trusted.
  if (!input.isComplete())
    throw Error("corrupt or truncated EXR file " + file +
                ": the file is incomplete (unfinished offset table)");

  // The data window is the stored pixel rectangle and may start anywhere, even at negative coordinates.
  const Imath::Box2i dataWindow = header.dataWindow();
  const long width = long(dataWindow.max.x) - dataWindow.min.x + 1;
  const long height = long(dataWindow.max.y) - dataWindow.min.y + 1;
  if (width <= 0 || height <= 0 || width > kMaxDimension || height > kMaxDimension)
    throw Error("corrupt or truncated EXR file " + file + ": invalid data window");
  if (header.displayWindow() != dataWindow)
    warn(file +
         ": the data window differs from the display window; the data window is used as the lat-long map");

  checkImageBudget(file, width, height);
  // Read in stripes, growing the image as they decode: a small file whose header claims a huge image fails
  // on its first missing chunk instead of first allocating the whole claimed image.
  EnvImage image;
  image.width = int(width);
  image.height = int(height);
  const long stripeRows = std::max(1L, std::min(height, (4L << 20) / (12 * width)));  // 4 MiB stripes
  std::vector<float> stripe;
  const std::size_t xStride = 3 * sizeof(float), yStride = xStride * std::size_t(width);
  for (long row = 0; row < height; row += stripeRows) {
    const long rows = std::min(stripeRows, height - row);
    stripe.assign(3 * std::size_t(width) * std::size_t(rows), 0.0f);
    const Imath::Box2i stripeWindow(Imath::V2i(dataWindow.min.x, int(dataWindow.min.y + row)),
                                    Imath::V2i(dataWindow.max.x, int(dataWindow.min.y + row + rows - 1)));
    Imf::FrameBuffer frameBuffer;
    for (std::size_t c = 0; c < names.size(); ++c)
      frameBuffer.insert(names[c],
                         Imf::Slice::Make(Imf::FLOAT, stripe.data() + c, stripeWindow, xStride, yStride));
    input.setFrameBuffer(frameBuffer);
    input.readPixels(stripeWindow.min.y, stripeWindow.max.y);
    // The whole image once the first stripe has decoded (a file that fails there never allocates it), so the
    // vector does not grow by doubling past the size the budget approved.
    if (row == 0) image.rgb.reserve(3 * std::size_t(width) * std::size_t(height));
    image.rgb.insert(image.rgb.end(), stripe.begin(), stripe.end());
  }

  // A luminance-only map is grey: Y was read into R, copy it to G and B.
  if (!hasRgb)
    for (std::size_t i = 0; i < image.texelCount(); ++i)
      image.rgb[3 * i + 1] = image.rgb[3 * i + 2] = image.rgb[3 * i];
  return image;
}

EnvImage readExrFrom(std::istream& raw, std::uint64_t size, Imf::IStream& stream, const std::string& file) {
  if (size == 0) throw Error("corrupt or truncated EXR file " + file + ": the file is empty");
  try {
    return readExrChannels(raw, size, stream, file);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error("not enough memory to load " + file);
  } catch (const std::exception& e) {
    // OpenEXR reports through Iex exceptions; keep its text, which names the structure that failed.
    throw Error("corrupt or truncated EXR file " + file + ": " + e.what());
  }
}

EnvImage readExr(const fs::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throwCannotOpen(path, std::strerror(errno));
  const std::uint64_t size = fs::file_size(path);
  Imf::StdIFStream stream(in, file.c_str());
  return readExrFrom(in, size, stream, file);
}

}  // namespace

SanitizeReport sanitize(EnvImage& image) {
  // +Inf becomes the largest finite value, so a clipped sun stays the brightest thing in the map rather than
  // vanishing (0) or poisoning every sum (Inf).
  float largestFinite = 0.0f;
  for (float v : image.rgb)
    if (std::isfinite(v)) largestFinite = std::max(largestFinite, v);

  SanitizeReport report;
  for (float& v : image.rgb) {
    if (std::isnan(v)) {
      ++report.nanCount;
      v = 0.0f;
    } else if (std::isinf(v)) {
      ++report.infCount;
      v = v > 0.0f ? largestFinite : 0.0f;
    } else if (v < 0.0f) {
      ++report.negativeCount;
      v = 0.0f;
    } else if (v == 0.0f) {
      v = 0.0f;  // -0 -> +0, silently: keeps the bits canonical for content hashes
    }
  }
  return report;
}

EnvImage loadRgbImage(const fs::path& path) {
  const std::string file = path.string();
  const std::string ext = lowerExtension(path);
  if (ext != ".exr" && ext != ".hdr")
    throw Error("cannot load " + file + ": unsupported extension '" + ext +
                "' (supported formats: .exr, .hdr)");
  checkInputFile(path);
  try {
    return ext == ".exr" ? readExr(path) : readHdr(path);
  } catch (const std::bad_alloc&) {
    throw Error("not enough memory to load " + file);
  } catch (const fs::filesystem_error& e) {
    throwCannotOpen(path, e.code().message());
  }
}

EnvImage decodeExr(std::span<const unsigned char> bytes, const std::string& name) {
  const std::string data(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::istringstream raw(data);
  Imf::StdISStream stream;
  stream.str(data);
  return readExrFrom(raw, bytes.size(), stream, name);
}

EnvImage loadEnvImage(const fs::path& path) {
  const std::string file = path.string();
  EnvImage image = loadRgbImage(path);
  if (image.width < 2 || image.height < 1)
    throw Error(file + ": the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                "; an environment map needs at least 2x1 texels");

  const SanitizeReport report = sanitize(image);
  if (report.total() > 0)
    warn(file + ": replaced " + std::to_string(report.nanCount) + " NaN, " + std::to_string(report.infCount) +
         " Inf and " + std::to_string(report.negativeCount) + " negative texel values");
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    if (double(image.rgb[i]) > kMaxEnvRadiance) {
      const std::size_t texel = i / 3;
      char value[32];
      std::snprintf(value, sizeof value, "%.3g", double(image.rgb[i]));
      throw Error(file + ": texel (" + std::to_string(texel % std::size_t(image.width)) + ", " +
                  std::to_string(texel / std::size_t(image.width)) + ") holds " + value +
                  ", above the largest radiance iblx accepts (1e15); scale the map down");
    }
  // Any size is usable (u = x/W, v = y/H), but a map far from 2:1 is probably not lat-long.
  const double aspect = double(image.width) / double(image.height);
  if (std::abs(aspect - 2.0) > 0.1)
    warn(file + ": the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
         ", not 2:1; it is used as a lat-long map anyway");
  return image;
}

}  // namespace iblx
