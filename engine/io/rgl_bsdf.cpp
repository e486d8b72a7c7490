// RGL-EPFL .bsdf tables: reading with every check, spectral conversion, writing (rgl_bsdf.h).
#include "engine/io/rgl_bsdf.h"

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/io/tensor_file.h"

#include <bit>
#include <cmath>
#include <numbers>

namespace iblx {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxRglValue = 1e15;  // the float headroom of kMaxEnvRadiance (engine/io/env_image.h)
constexpr double kPi = std::numbers::pi;

std::string shapeText(const std::vector<std::uint64_t>& shape) {
  std::string s = "[";
  for (std::size_t k = 0; k < shape.size(); ++k) s.append(k ? ", " : "").append(std::to_string(shape[k]));
  return s + "]";
}

// The fields of one file, each fetched with its dtype and shape checked.
class FieldReader {
 public:
  FieldReader(const TensorFile& file, std::string name) : file_(file), name_(std::move(name)) {}
  bool has(const std::string& field) const { return file_.fields.count(field) != 0; }
  const TensorField& get(const std::string& field, TensorType type, std::size_t dims) const {
    const auto it = file_.fields.find(field);
    if (it == file_.fields.end())
      throw Error(name_ + ": not an RGL-EPFL material: the tensor file has no field '" + field + "'");
    const TensorField& f = it->second;
    if (f.type != type)
      throw Error(name_ + ": field '" + field + "' holds " + tensorTypeName(f.type) + " values, expected " +
                  tensorTypeName(type));
    if (f.shape.size() != dims)
      throw Error(name_ + ": field '" + field + "' has shape " + shapeText(f.shape) + ", expected " +
                  std::to_string(dims) + " dimensions");
    return f;
  }
  // Float values, each finite and at most 1e15 (and non-negative unless negatives are allowed).
  std::vector<float> floats(const std::string& field, std::size_t dims, bool allowNegative) const {
    const TensorField& f = get(field, TensorType::Float32, dims);
    std::vector<float> v(f.elements());
    for (std::size_t k = 0; k < v.size(); ++k) {
      std::uint32_t bits = 0;
      for (int b = 0; b < 4; ++b) bits |= std::uint32_t(f.bytes[4 * k + std::size_t(b)]) << (8 * b);
      v[k] = std::bit_cast<float>(bits);
      const std::string where = "field '" + field + "' entry " + std::to_string(k);
      if (!std::isfinite(v[k])) throw Error(name_ + ": " + where + " is not a finite number");
      if (std::abs(double(v[k])) > kMaxRglValue)
        throw Error(name_ + ": " + where + " holds " + std::to_string(v[k]) +
                    ", above the largest value iblx accepts (1e15)");
      if (!allowNegative && v[k] < 0.0f)
        throw Error(name_ + ": " + where + " is negative (" + std::to_string(v[k]) +
                    "); a density cannot be");
    }
    return v;
  }
  void expectShape(const std::string& field, const std::vector<std::uint64_t>& expected) const {
    const TensorField& f = file_.fields.at(field);
    if (f.shape != expected)
      throw Error(name_ + ": field '" + field + "' has shape " + shapeText(f.shape) + ", expected " +
                  shapeText(expected) + " from the other fields");
  }
  const std::string& name() const { return name_; }

 private:
  const TensorFile& file_;
  std::string name_;
};

void checkIncreasing(const std::vector<float>& v, const std::string& field, const std::string& name) {
  for (std::size_t k = 1; k < v.size(); ++k)
    if (!(v[k] > v[k - 1]))
      throw Error(name + ": field '" + field + "' must increase, but entry " + std::to_string(k) + " is " +
                  std::to_string(v[k]) + " after " + std::to_string(v[k - 1]));
}

// A warp's density must be positive somewhere in every slice (one view of the material) to be sampled.
void checkSlicesPositive(const RglGrid& g, const std::string& field, const std::string& name) {
  const std::size_t size = std::size_t(g.width) * g.height;
  for (std::size_t slice = 0; slice * size < g.values.size(); ++slice) {
    double sum = 0.0;
    for (std::size_t k = 0; k < size; ++k) sum += g.values[slice * size + k];
    if (!(sum > 0.0))
      throw Error(name + ": field '" + field + "' is 0 everywhere in slice " + std::to_string(slice) +
                  " (one view), which cannot be sampled");
  }
}

RglGrid grid(const TensorField& field, std::vector<float> values) {
  const std::size_t n = field.shape.size();
  return {std::uint32_t(field.shape[n - 1]), std::uint32_t(field.shape[n - 2]), std::move(values)};
}

// CIE 1931 2-degree colour matching functions, the multi-lobe Gaussian fit of Wyman, Sloan & Shirley 2013
// (JCGT 2(2), eq. 2-4).
double lobe(double lambda, double mu, double sigmaBelow, double sigmaAbove) {
  const double t = (lambda - mu) / (lambda < mu ? sigmaBelow : sigmaAbove);
  return std::exp(-0.5 * t * t);
}
void cieXyz(double lambda, double xyz[3]) {
  xyz[0] = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7) -
           0.065 * lobe(lambda, 501.1, 20.4, 26.2);
  xyz[1] = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
  xyz[2] = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
}

}  // namespace

int RglTables::reduction() const {
  if (isotropic()) return 1;
  return int(std::lrint(2.0 * kPi / (double(phiI.back()) - double(phiI.front()))));
}

SpectrumToRgb::SpectrumToRgb(const std::vector<float>& wavelengths) {
  const std::size_t n = wavelengths.size();
  // XYZ to linear sRGB (IEC 61966-2-1).
  const double m[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                          {-0.9692660, 1.8760108, 0.0415560},
                          {0.0556434, -0.2040259, 1.0572252}};
  double white[3] = {0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    // Trapezoid weights over possibly uneven wavelengths (one wavelength: weight 1).
    const double left = k > 0 ? double(wavelengths[k]) - wavelengths[k - 1] : 0.0;
    const double right = k + 1 < n ? double(wavelengths[k + 1]) - wavelengths[k] : 0.0;
    const double w = n == 1 ? 1.0 : 0.5 * (left + right);
    double xyz[3];
    cieXyz(wavelengths[k], xyz);
    double rgb[3];
    for (int c = 0; c < 3; ++c) rgb[c] = w * (m[c][0] * xyz[0] + m[c][1] * xyz[1] + m[c][2] * xyz[2]);
    weightR_.push_back(rgb[0]), weightG_.push_back(rgb[1]), weightB_.push_back(rgb[2]);
    for (int c = 0; c < 3; ++c) white[c] += rgb[c];
  }
  for (std::size_t k = 0; k < n; ++k)
    weightR_[k] /= white[0], weightG_[k] /= white[1], weightB_[k] /= white[2];
}

void SpectrumToRgb::convert(const float* spectrum, std::size_t stride, double rgb[3]) const {
  rgb[0] = rgb[1] = rgb[2] = 0.0;
  for (std::size_t k = 0; k < weightR_.size(); ++k) {
    const double s = spectrum[k * stride];
    rgb[0] += weightR_[k] * s, rgb[1] += weightG_[k] * s, rgb[2] += weightB_[k] * s;
  }
}

bool looksLikeRglBsdf(const fs::path& path) {
  return looksLikeTensorFile(path);
}

RglTables loadRglBsdf(const fs::path& path) {
  const std::string name = path.string();
  const TensorFile file = readTensorFile(path);
  const FieldReader fields(file, name);
  RglTables t;
  if (fields.has("description")) {
    const TensorField& d = fields.get("description", TensorType::UInt8, 1);
    t.description.assign(d.bytes.begin(), d.bytes.end());
    while (!t.description.empty() && t.description.back() == '\0') t.description.pop_back();
  }
  if (fields.has("jacobian")) {
    const TensorField& j = fields.get("jacobian", TensorType::UInt8, 1);
    if (j.elements() != 1)
      throw Error(name + ": field 'jacobian' has " + std::to_string(j.elements()) + " entries, expected 1");
    t.jacobian = j.bytes[0] != 0;
  }
  t.thetaI = fields.floats("theta_i", 1, false);
  t.phiI = fields.floats("phi_i", 1, true);
  checkIncreasing(t.thetaI, "theta_i", name);
  checkIncreasing(t.phiI, "phi_i", name);
  if (t.thetaI.back() > kPi / 2 + 1e-4)
    throw Error(name + ": field 'theta_i' reaches " + std::to_string(t.thetaI.back()) +
                " rad, beyond the horizon (pi / 2)");
  if (!t.isotropic()) {
    const int r = t.reduction();
    const double span = double(t.phiI.back()) - t.phiI.front();
    if ((r != 1 && r != 2 && r != 4) || std::abs(span * r - 2.0 * kPi) > 1e-2)
      throw Error(name + ": field 'phi_i' spans " + std::to_string(span) +
                  " rad; an anisotropic material covers a whole, half or quarter turn");
  }
  const std::uint64_t np = t.phiI.size(), nt = t.thetaI.size();

  const auto planar = [&](const std::string& field) {
    const TensorField& f = fields.get(field, TensorType::Float32, 2);
    if (f.shape[0] < 2 || f.shape[1] < 2)
      throw Error(name + ": field '" + field + "' has shape " + shapeText(f.shape) +
                  ", expected at least 2 x 2");
    return grid(f, fields.floats(field, 2, false));
  };
  t.ndf = planar("ndf");
  t.sigma = planar("sigma");
  for (float s : t.sigma.values)
    if (!(s > 0.0f))
      throw Error(name + ": field 'sigma' (the projected area) holds 0, which evaluation divides by");

  const TensorField& vndf = fields.get("vndf", TensorType::Float32, 4);
  fields.expectShape("vndf", {np, nt, vndf.shape[2], vndf.shape[3]});
  if (vndf.shape[2] < 2 || vndf.shape[3] < 2)
    throw Error(name + ": field 'vndf' has shape " + shapeText(vndf.shape) +
                ", expected a grid of at least 2 x 2");
  t.vndf = grid(vndf, fields.floats("vndf", 4, false));
  checkSlicesPositive(t.vndf, "vndf", name);

  const TensorField& luminance = fields.get("luminance", TensorType::Float32, 4);
  const std::uint64_t n = luminance.shape[3];
  fields.expectShape("luminance", {np, nt, n, n});
  if (n < 2)
    throw Error(name + ": field 'luminance' has shape " + shapeText(luminance.shape) +
                ", expected a grid of at least 2 x 2");
  t.luminance = grid(luminance, fields.floats("luminance", 4, false));
  checkSlicesPositive(t.luminance, "luminance", name);

  std::vector<float> rgb;
  if (fields.has("rgb")) {
    fields.get("rgb", TensorType::Float32, 5);
    fields.expectShape("rgb", {np, nt, 3, n, n});
    rgb = fields.floats("rgb", 5, true);
  } else if (fields.has("spectra")) {
    fields.get("spectra", TensorType::Float32, 5);
    const std::vector<float> wavelengths = fields.floats("wavelengths", 1, false);
    checkIncreasing(wavelengths, "wavelengths", name);
    // Outside the visible range the colour-matching functions are nearly 0: such a material would render
    // black, or as the noise of dividing by its tiny white.
    if (!(wavelengths.back() >= 360.0f && wavelengths.front() <= 830.0f))
      throw Error(name + ": its wavelengths (" + std::to_string(int(wavelengths.front())) + " to " +
                  std::to_string(int(wavelengths.back())) +
                  " nm) lie outside the visible range (360 to 830 nm): it has no colour to render");
    fields.expectShape("spectra", {np, nt, wavelengths.size(), n, n});
    const std::vector<float> values = fields.floats("spectra", 5, true);
    const SpectrumToRgb toRgb(wavelengths);
    const std::size_t cells = std::size_t(n * n), bands = wavelengths.size();
    rgb.resize(std::size_t(np * nt) * 3 * cells);
    for (std::size_t slice = 0; slice < np * nt; ++slice)
      for (std::size_t cell = 0; cell < cells; ++cell) {
        double c[3];
        toRgb.convert(values.data() + slice * bands * cells + cell, cells, c);
        for (int k = 0; k < 3; ++k) rgb[(slice * 3 + std::size_t(k)) * cells + cell] = float(c[k]);
      }
    t.spectralBands = bands;
  } else {
    throw Error(name +
                ": not an RGL-EPFL material: the tensor file has neither an 'rgb' nor a 'spectra' field");
  }
  for (float& v : rgb)
    if (v < 0.0f) v = 0.0f, ++t.negativeEntries;
  if (t.negativeEntries > 0)
    warn(name + ": " + std::to_string(t.negativeEntries) + " of " + std::to_string(rgb.size()) +
         " colour entries are negative; they are treated as 0");
  t.rgb = {std::uint32_t(n), std::uint32_t(n), std::move(rgb)};
  return t;
}

void writeRglBsdf(const fs::path& path, const RglTables& t) {
  const std::uint64_t np = t.phiI.size(), nt = t.thetaI.size(), n = t.rgb.width;
  TensorFile file;
  const std::vector<std::uint8_t> description(t.description.begin(), t.description.end());
  file.fields["description"] = uint8Field({description.size()}, description);
  const std::uint8_t jacobian = t.jacobian ? 1 : 0;
  file.fields["jacobian"] = uint8Field({1}, std::span(&jacobian, 1));
  file.fields["theta_i"] = float32Field({nt}, t.thetaI);
  file.fields["phi_i"] = float32Field({np}, t.phiI);
  file.fields["ndf"] = float32Field({t.ndf.height, t.ndf.width}, t.ndf.values);
  file.fields["sigma"] = float32Field({t.sigma.height, t.sigma.width}, t.sigma.values);
  file.fields["vndf"] = float32Field({np, nt, t.vndf.height, t.vndf.width}, t.vndf.values);
  file.fields["luminance"] = float32Field({np, nt, n, n}, t.luminance.values);
  file.fields["rgb"] = float32Field({np, nt, 3, n, n}, t.rgb.values);
  writeTensorFile(path, file);
}

}  // namespace iblx
