// The RGL-EPFL tensor_file container: reader and writer (tensor_file.h).
#include "engine/io/tensor_file.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"

#include <bit>
#include <cstring>
#include <fstream>

namespace iblx {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
// Bounds far above any real file (the database's files hold about a dozen fields of at most 5 dimensions)
// that keep a corrupt header from driving huge loops or allocations.
constexpr std::uint32_t kMaxFields = 1024;
constexpr std::uint16_t kMaxNameLength = 1024;
constexpr std::uint16_t kMaxDimensions = 16;

std::size_t elementSize(TensorType type) {
  switch (type) {
    case TensorType::UInt8:
    case TensorType::Int8:
      return 1;
    case TensorType::UInt16:
    case TensorType::Int16:
    case TensorType::Float16:
      return 2;
    case TensorType::UInt32:
    case TensorType::Int32:
    case TensorType::Float32:
      return 4;
    case TensorType::UInt64:
    case TensorType::Int64:
    case TensorType::Float64:
      return 8;
  }
  return 0;
}

// Reads the header's integers, each one failing with the field it belongs to when the file ends.
class HeaderReader {
 public:
  HeaderReader(const std::vector<unsigned char>& bytes, const std::string& name)
      : bytes_(bytes), name_(name) {}
  std::uint64_t read(std::size_t size, const std::string& what) {
    if (bytes_.size() - at_ < size)
      throw Error(name_ + ": truncated tensor file: it ends inside the header, at " + what);
    std::uint64_t v = 0;
    for (std::size_t b = 0; b < size; ++b) v |= std::uint64_t(bytes_[at_ + b]) << (8 * b);
    at_ += size;
    return v;
  }
  std::string readString(std::size_t size, const std::string& what) {
    if (bytes_.size() - at_ < size)
      throw Error(name_ + ": truncated tensor file: it ends inside the header, at " + what);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), size);
    at_ += size;
    return s;
  }
  std::size_t position() const { return at_; }

 private:
  const std::vector<unsigned char>& bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

void put(std::vector<unsigned char>& out, std::uint64_t v, std::size_t size) {
  for (std::size_t b = 0; b < size; ++b) out.push_back(static_cast<unsigned char>(v >> (8 * b)));
}

}  // namespace

std::uint64_t TensorField::elements() const {
  std::uint64_t n = 1;
  for (std::uint64_t extent : shape) n *= extent;
  return n;
}

std::string tensorTypeName(TensorType type) {
  static const char* names[] = {"u8", "i8", "u16", "i16", "u32", "i32", "u64", "i64", "f16", "f32", "f64"};
  const int k = int(type);
  return k >= 1 && k <= 11 ? names[k - 1] : "dtype " + std::to_string(k);
}

bool looksLikeTensorFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof(kMagic)];
  return in.read(magic, sizeof(magic)) && std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
}

TensorFile readTensorFile(const fs::path& path) {
  const std::string name = path.string();
  const std::uint64_t size = checkInputFile(path);
  checkMemoryBudget(name, size);
  const std::vector<unsigned char> bytes = readInputFile(path, size);
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    throw Error(name + ": not a tensor file (an RGL-EPFL .bsdf starts with \"tensor_file\")");
  HeaderReader header(bytes, name);
  header.readString(sizeof(kMagic), "the magic");
  const auto major = header.read(1, "the version"), minor = header.read(1, "the version");
  if (major != 1 || minor != 0)
    throw Error(name + ": tensor file version " + std::to_string(major) + "." + std::to_string(minor) +
                " is not supported (iblx reads 1.0)");
  const auto count = std::uint32_t(header.read(4, "the field count"));
  if (count == 0 || count > kMaxFields)
    throw Error(name + ": the tensor file declares " + std::to_string(count) + " fields, expected 1 to " +
                std::to_string(kMaxFields));
  TensorFile file;
  // The fields' data together: each field stores its own bytes, so they fit the file (a wrong dtype may
  // double one field's claim: its own message follows). Fields that all point at one blob would otherwise
  // copy it once each (1,000 aliases of a large blob reached 6 GB).
  std::uint64_t allFields = 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::string which = "field " + std::to_string(k);
    const auto nameLength = std::uint16_t(header.read(2, which + "'s name length"));
    if (nameLength == 0 || nameLength > kMaxNameLength)
      throw Error(name + ": " + which + " has a name of " + std::to_string(nameLength) +
                  " bytes, expected 1 to " + std::to_string(kMaxNameLength));
    const std::string fieldName = header.readString(nameLength, which + "'s name");
    const std::string quoted = "field '" + fieldName + "'";
    const auto dims = std::uint16_t(header.read(2, quoted + "'s dimension count"));
    if (dims == 0 || dims > kMaxDimensions)
      throw Error(name + ": " + quoted + " has " + std::to_string(dims) + " dimensions, expected 1 to " +
                  std::to_string(kMaxDimensions));
    const auto dtype = std::uint8_t(header.read(1, quoted + "'s dtype"));
    if (dtype < 1 || dtype > 11)
      throw Error(name + ": " + quoted + " has dtype " + std::to_string(dtype) +
                  ", which is none of the tensor file's types (1 to 11)");
    TensorField field;
    field.type = TensorType(dtype);
    const std::uint64_t offset = header.read(8, quoted + "'s offset");
    std::uint64_t elements = 1;
    for (std::uint16_t d = 0; d < dims; ++d) {
      const std::uint64_t extent = header.read(8, quoted + "'s shape");
      if (extent == 0 || extent > size || elements > size / extent)
        throw Error(name + ": " + quoted + "'s shape has extent " + std::to_string(extent) + ", which its " +
                    std::to_string(size) + "-byte file cannot hold");
      elements *= extent;
      field.shape.push_back(extent);
    }
    const std::uint64_t fieldBytes = elements * elementSize(field.type);
    if (offset > size || fieldBytes > size - offset)
      throw Error(name + ": " + quoted + "'s data (" + std::to_string(fieldBytes) + " bytes at offset " +
                  std::to_string(offset) + ") lies outside the " + std::to_string(size) + "-byte file");
    allFields += fieldBytes;
    if (allFields > 2 * size)
      throw Error(name + ": the fields up to " + quoted + " claim " + std::to_string(allFields) +
                  " bytes of data in a " + std::to_string(size) +
                  "-byte file: their data overlap (each field stores its own)");
    field.bytes.assign(bytes.begin() + std::ptrdiff_t(offset),
                       bytes.begin() + std::ptrdiff_t(offset + fieldBytes));
    if (!file.fields.emplace(fieldName, std::move(field)).second)
      throw Error(name + ": " + quoted + " appears twice");
  }
  return file;
}

TensorField float32Field(std::vector<std::uint64_t> shape, std::span<const float> values) {
  TensorField field{TensorType::Float32, std::move(shape), {}};
  field.bytes.reserve(values.size() * 4);
  for (float v : values) put(field.bytes, std::bit_cast<std::uint32_t>(v), 4);
  return field;
}

TensorField uint8Field(std::vector<std::uint64_t> shape, std::span<const std::uint8_t> values) {
  return {TensorType::UInt8, std::move(shape), std::vector<unsigned char>(values.begin(), values.end())};
}

void writeTensorFile(const fs::path& path, const TensorFile& file) {
  std::vector<unsigned char> out(kMagic, kMagic + sizeof(kMagic));
  put(out, 1, 1);
  put(out, 0, 1);
  put(out, file.fields.size(), 4);
  std::size_t headerBytes = out.size();
  for (const auto& [fieldName, field] : file.fields)
    headerBytes += 2 + fieldName.size() + 2 + 1 + 8 + 8 * field.shape.size();
  std::uint64_t offset = headerBytes;
  for (const auto& [fieldName, field] : file.fields) {
    put(out, fieldName.size(), 2);
    out.insert(out.end(), fieldName.begin(), fieldName.end());
    put(out, field.shape.size(), 2);
    put(out, std::uint64_t(field.type), 1);
    put(out, offset, 8);
    for (std::uint64_t extent : field.shape) put(out, extent, 8);
    offset += field.bytes.size();
  }
  for (const auto& entry : file.fields)
    out.insert(out.end(), entry.second.bytes.begin(), entry.second.bytes.end());
  writeFileAtomically(path, out);
}

}  // namespace iblx
