// The "tensor_file" container of the RGL-EPFL material database (Dupuy & Jakob 2018, the layout of their
// reference reader): named n-dimensional arrays in one little-endian file. Reading checks everything a
// hostile file could get wrong (magic, version, counts, names, dtypes, shapes, offsets and sizes inside the
// file) and names the file and the field; writing is for `iblx measured-synth`.
//
// Layout: the 12 bytes "tensor_file\0", a version u8[2] = {1, 0}, a u32 field count, then per field a u16
// name length, the name, a u16 dimension count, a u8 dtype (1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8
// i64, 9 f16, 10 f32, 11 f64), a u64 absolute offset of its data and u64 extents; the data follows the
// header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace iblx {

enum class TensorType : std::uint8_t {
  UInt8 = 1,
  Int8,
  UInt16,
  Int16,
  UInt32,
  Int32,
  UInt64,
  Int64,
  Float16,
  Float32,
  Float64
};

struct TensorField {
  TensorType type = TensorType::Float32;
  std::vector<std::uint64_t> shape;
  std::vector<unsigned char> bytes;  // the raw little-endian data, size = element count x element size
  std::uint64_t elements() const;
};

struct TensorFile {
  std::map<std::string, TensorField> fields;
};

// Whether a file starts with the tensor_file magic.
bool looksLikeTensorFile(const std::filesystem::path& path);

// Throws iblx::Error "FILE: problem" for a file that is not a tensor file or is damaged in any way.
TensorFile readTensorFile(const std::filesystem::path& path);

// Builds fields for the writer.
TensorField float32Field(std::vector<std::uint64_t> shape, std::span<const float> values);
TensorField uint8Field(std::vector<std::uint64_t> shape, std::span<const std::uint8_t> values);
void writeTensorFile(const std::filesystem::path& path, const TensorFile& file);

// "f32", "u8", ...: dtypes in messages.
std::string tensorTypeName(TensorType type);

}  // namespace iblx
