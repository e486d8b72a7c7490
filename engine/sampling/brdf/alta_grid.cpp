// ALTA data on a grid: detection, resampling of scattered samples, lookup and the writer's grids
// (alta_grid.h).
#include "engine/sampling/brdf/alta_grid.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <memory>
#include <optional>
#include <span>

#include <nanoflann.hpp>

namespace iblx {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kNeighbours = 8;

double angle(double cosine) {
  return std::acos(std::clamp(cosine, -1.0, 1.0));
}

glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

double positiveMod(double x, double period) {
  const double r = std::fmod(x, period);
  return r < 0.0 ? r + period : r;
}

double fold(double x, AltaFold rule, double axisMin) {
  switch (rule) {
    case AltaFold::Clamp:
      return x;
    case AltaFold::Turn:
      return axisMin + positiveMod(x - axisMin, 2.0 * kPi);
    case AltaFold::Reciprocity:
      return positiveMod(x, kPi);
    case AltaFold::Mirror: {
      const double t = positiveMod(x, 2.0 * kPi);
      return t > kPi ? 2.0 * kPi - t : t;
    }
    case AltaFold::ReciprocityMirror: {
      const double t = positiveMod(x, kPi);
      return t > 0.5 * kPi ? kPi - t : t;
    }
  }
  return x;
}

AltaFold foldFor(AltaParam param, int dim, double lo, double hi) {
  // The azimuths and their symmetries are the parametrisation's (altaAngleKind, engine/io/alta_params.h).
  const AltaAngle angle = altaAngleKind(param, dim);
  if (angle == AltaAngle::NotAngle) return AltaFold::Clamp;
  if (hi - lo >= 2.0 * kPi - 0.1) return AltaFold::Turn;
  if (angle != AltaAngle::Turn && lo >= -0.01 && hi <= kPi + 0.01) {
    const bool quarter = hi <= 0.5 * kPi + 0.01;
    if (angle == AltaAngle::Reciprocity) return quarter ? AltaFold::ReciprocityMirror : AltaFold::Reciprocity;
    return AltaFold::Mirror;
  }
  return AltaFold::Turn;
}

// The distinct values of one coordinate, merged within a tolerance.
std::vector<double> distinct(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const double tolerance = 1e-6 * std::max(1.0, v.back() - v.front());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > tolerance) out.push_back(x);
  return out;
}

std::size_t nearestIndex(const std::vector<double>& axis, double x) {
  const auto it = std::lower_bound(axis.begin(), axis.end(), x);
  if (it == axis.end()) return axis.size() - 1;
  if (it == axis.begin()) return 0;
  return (x - *(it - 1) < *it - x) ? std::size_t(it - axis.begin()) - 1 : std::size_t(it - axis.begin());
}

// The samples' coordinates in the grid's parametrisation: the file's own, or converted through a direction
// pair with the file's coordinates (altaDirections).
std::vector<double> gridCoordinates(const AltaData& data, AltaParam gridParam, const std::string& name) {
  if (data.param == gridParam) return data.x;
  const auto in = std::size_t(altaParamDimension(data.param)),
             out = std::size_t(altaParamDimension(gridParam));
  std::vector<double> x;
  x.reserve(data.samples * out);
  for (std::size_t i = 0; i < data.samples; ++i) {
    const auto pair = altaDirections(data.param, std::span(data.x).subspan(i * in, in));
    if (!pair)
      throw Error(name + ": sample " + std::to_string(i) + " has " + altaParamName(data.param) +
                  " coordinates that no pair of directions has");
    const auto k = altaRawCoordinates(gridParam, pair->first, pair->second);
    x.insert(x.end(), k.begin(), k.begin() + std::ptrdiff_t(out));
  }
  return x;
}

// Scattered samples with their coordinates scaled to [0, 1] per axis, exact repeats merged into one point
// with their mean value (repeated measurements; also what keeps the tree below from visiting every copy of a
// point at the same distance), indexed by a k-d tree (nanoflann, Debian's libnanoflann-dev) so that a query
// costs about log(points) + k whatever the samples' clustering.
class ScatteredSamples {
 public:
  ScatteredSamples(const std::vector<double>& unit, const std::vector<double>& rgb, int dims) : dims_(dims) {
    const std::size_t n = rgb.size() / 3, d = std::size_t(dims);
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
    const auto coordinates = [&](std::uint32_t i) { return std::span(unit).subspan(i * d, d); };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return std::ranges::lexicographical_compare(coordinates(a), coordinates(b));
    });
    for (std::size_t k = 0; k < n;) {
      std::size_t end = k + 1;
      while (end < n && std::ranges::equal(coordinates(order[k]), coordinates(order[end]))) ++end;
      glm::dvec3 sum(0.0);
      for (std::size_t j = k; j < end; ++j)
        sum += glm::dvec3(rgb[3 * order[j]], rgb[3 * order[j] + 1], rgb[3 * order[j] + 2]);
      const auto c = coordinates(order[k]);
      points_.insert(points_.end(), c.begin(), c.end());
      values_.push_back(sum / double(end - k));
      k = end;
    }
    tree_ = std::make_unique<Tree>(dims_, *this, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree_->buildIndex();
  }
  std::size_t size() const { return values_.size(); }
  const double* point(std::size_t i) const { return points_.data() + i * std::size_t(dims_); }

  // Shepard's inverse-distance-weighted mean (power 2) of the kNeighbours nearest points to p (an exact hit
  // takes that point's value), leaving out point `skip` (leave-one-out), if any. No allocation: it runs once
  // per grid node and once per sample.
  glm::dvec3 interpolate(const double* p, std::optional<std::size_t> skip = {}) const {
    const std::size_t wanted = std::min(size(), std::size_t(kNeighbours) + (skip ? 1 : 0));
    std::array<std::uint32_t, kNeighbours + 1> indices{};
    std::array<double, kNeighbours + 1> d2{};
    const std::size_t found = tree_->knnSearch(p, wanted, indices.data(), d2.data());
    glm::dvec3 sum(0.0);
    double weights = 0.0;
    for (std::size_t j = 0; j < found; ++j) {
      if (skip && indices[j] == *skip) continue;
      const double w = d2[j] < 1e-24 ? 1e24 : 1.0 / d2[j];
      sum += w * values_[indices[j]];
      weights += w;
    }
    return weights > 0.0 ? sum / weights : glm::dvec3(0.0);
  }
  const glm::dvec3& value(std::size_t i) const { return values_[i]; }

  // nanoflann's dataset interface.
  std::size_t kdtree_get_point_count() const { return size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return points_[i * std::size_t(dims_) + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }

 private:
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, ScatteredSamples>,
                                                   ScatteredSamples, -1, std::uint32_t>;
  int dims_;
  std::vector<double> points_;      // size() x dims, in [0, 1]
  std::vector<glm::dvec3> values_;  // per point
  std::unique_ptr<Tree> tree_;
};

}  // namespace

std::string leaveOneOutText(const AltaGrid& grid) {
  if (!grid.leaveOneOutError) return {};
  char text[96];
  std::snprintf(text, sizeof text, " (leave-one-out error %.3g %% over %zu distinct samples)",
                100.0 * *grid.leaveOneOutError, grid.distinctSamples);
  return text;
}

AltaGrid makeAltaGrid(const AltaData& data, const std::string& name) {
  AltaGrid grid;
  grid.param = altaTableParam(data.param);
  grid.cosineFactor = data.output == AltaOutput::InvSteradianCosine;
  const int dims = altaParamDimension(grid.param);
  const std::vector<double> x = gridCoordinates(data, grid.param, name);
  const std::size_t n = data.samples;

  // A regular grid: as many samples as the product of the distinct values per axis, each node once.
  bool regular = data.param != AltaParam::Cartesian;
  std::size_t nodes = 1;
  if (regular) {
    for (int d = 0; d < dims && regular; ++d) {
      std::vector<double> column(n);
      for (std::size_t i = 0; i < n; ++i) column[i] = x[i * std::size_t(dims) + std::size_t(d)];
      grid.axes.push_back(distinct(std::move(column)));
      nodes *= grid.axes.back().size();
      regular = nodes <= n;
    }
    regular = regular && nodes == n;
  }
  if (regular) {
    grid.rgb.assign(3 * n, -1.0f);
    for (std::size_t i = 0; i < n && regular; ++i) {
      std::size_t index = 0;
      for (int d = 0; d < dims; ++d)
        index = index * grid.axes[std::size_t(d)].size() +
                nearestIndex(grid.axes[std::size_t(d)], x[i * std::size_t(dims) + std::size_t(d)]);
      if (grid.rgb[index] >= 0.0f) regular = false;  // a node twice: not a grid
      for (int c = 0; c < 3; ++c)
        grid.rgb[std::size_t(c) * n + index] = float(data.rgb[3 * i + std::size_t(c)]);
    }
  }
  if (!regular) {
    // Resampling onto an even grid spanning the samples.
    const int perAxis = dims <= 2 ? 64 : dims == 3 ? 32 : 16;
    grid.axes.assign(std::size_t(dims), {});
    const auto dimCount = std::size_t(dims);
    std::vector<double> lo(dimCount), hi(dimCount);
    for (int d = 0; d < dims; ++d) {
      lo[std::size_t(d)] = hi[std::size_t(d)] = x[std::size_t(d)];
      for (std::size_t i = 0; i < n; ++i) {
        const double v = x[i * std::size_t(dims) + std::size_t(d)];
        lo[std::size_t(d)] = std::min(lo[std::size_t(d)], v),
        hi[std::size_t(d)] = std::max(hi[std::size_t(d)], v);
      }
      const int count = hi[std::size_t(d)] > lo[std::size_t(d)] ? perAxis : 1;
      for (int k = 0; k < count; ++k)
        grid.axes[std::size_t(d)].push_back(
            count == 1 ? lo[std::size_t(d)]
                       : lo[std::size_t(d)] + (hi[std::size_t(d)] - lo[std::size_t(d)]) * k / (count - 1.0));
    }
    nodes = 1;
    for (const auto& axis : grid.axes) nodes *= axis.size();
    checkMemoryBudget(name + ": the resampled grid", nodes * 3 * sizeof(float));
    std::vector<double> unit(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      const std::size_t d = i % std::size_t(dims);
      unit[i] = hi[d] > lo[d] ? (x[i] - lo[d]) / (hi[d] - lo[d]) : 0.0;
    }
    // The tree's points and values, the sort order and the scaled coordinates.
    checkMemoryBudget(name + ": resampling " + std::to_string(n) + " samples",
                      std::uint64_t(n) * (3 * dimCount * sizeof(double) + sizeof(glm::dvec3) + 16));
    const ScatteredSamples samples(unit, data.rgb, dims);
    grid.rgb.assign(3 * nodes, 0.0f);
    std::vector<double> p(dimCount);
    for (std::size_t node = 0; node < nodes; ++node) {
      std::size_t rest = node;
      for (int d = dims - 1; d >= 0; --d) {
        const std::size_t count = grid.axes[std::size_t(d)].size();
        p[std::size_t(d)] = count > 1 ? double(rest % count) / double(count - 1) : 0.0;
        rest /= count;
      }
      const glm::dvec3 value = samples.interpolate(p.data());
      for (int c = 0; c < 3; ++c) grid.rgb[std::size_t(c) * nodes + node] = float(value[c]);
    }
    // How well the resampling predicts the measurements: each distinct sample from its 8 nearest others, as
    // the relative RMS error of the mean of the three channels.
    if (samples.size() > std::size_t(kNeighbours)) {
      double squared = 0.0, reference = 0.0;
      for (std::size_t i = 0; i < samples.size(); ++i) {
        const glm::dvec3 predicted = samples.interpolate(samples.point(i), i);
        const double y = (samples.value(i).x + samples.value(i).y + samples.value(i).z) / 3.0;
        const double e = (predicted.x + predicted.y + predicted.z) / 3.0 - y;
        squared += e * e;
        reference += y * y;
      }
      grid.leaveOneOutError = reference > 0.0 ? std::sqrt(squared / reference) : 0.0;
    }
    grid.distinctSamples = samples.size();
    grid.resampledFrom = n;
    std::string shape;
    for (const auto& axis : grid.axes)
      shape.append(shape.empty() ? "" : " x ").append(std::to_string(axis.size()));
    const std::string converted =
        data.param == grid.param ? "" : ", read as " + altaParamName(grid.param) + " coordinates,";
    warn(name + ": the " + std::to_string(n) + " " + altaParamName(data.param) + " samples" + converted +
         (data.param == AltaParam::Cartesian ? std::string(" are directions")
                                             : std::string(" do not lie on a regular grid")) +
         "; resampled onto a " + shape + " " + altaParamName(grid.param) +
         " grid by inverse-distance weighting of the 8 nearest samples" + leaveOneOutText(grid));
  }
  for (int d = 0; d < dims; ++d)
    grid.folds.push_back(
        foldFor(grid.param, d, grid.axes[std::size_t(d)].front(), grid.axes[std::size_t(d)].back()));
  return grid;
}

glm::dvec3 evalAltaGrid(const AltaGrid& grid, glm::dvec3 wi, glm::dvec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return glm::dvec3(0.0);
  const std::array<double, 6> k = altaRawCoordinates(grid.param, wi, wo);
  const int dims = int(grid.axes.size());
  std::size_t lower[4] = {0, 0, 0, 0};
  double weight[4] = {0, 0, 0, 0};
  for (int d = 0; d < dims; ++d) {
    const std::vector<double>& axis = grid.axes[std::size_t(d)];
    const double x = std::clamp(fold(k[std::size_t(d)], grid.folds[std::size_t(d)], axis.front()),
                                axis.front(), axis.back());
    if (axis.size() < 2) continue;
    const std::size_t i =
        std::min(std::size_t(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin()), axis.size() - 1) -
        1;
    lower[d] = i;
    weight[d] = (x - axis[i]) / (axis[i + 1] - axis[i]);
  }
  const std::size_t nodes = grid.nodes();
  glm::dvec3 value(0.0);
  for (int corner = 0; corner < (1 << dims); ++corner) {
    double w = 1.0;
    std::size_t index = 0;
    for (int d = 0; d < dims; ++d) {
      const bool upper = (corner >> d) & 1;
      const std::size_t count = grid.axes[std::size_t(d)].size();
      w *= upper ? weight[d] : 1.0 - weight[d];
      index = index * count + std::min(lower[d] + (upper ? 1 : 0), count - 1);
    }
    if (w == 0.0) continue;
    for (int c = 0; c < 3; ++c) value[c] += w * grid.rgb[std::size_t(c) * nodes + index];
  }
  return grid.cosineFactor ? value / wi.z : value;
}

TechniqueData altaGridTechniqueData(const AltaGrid& grid) {
  TechniqueData out;
  std::vector<float> table;
  const int dims = int(grid.axes.size());
  // shaders/lib/alta_params.glsl numbers the parametrisations as AltaParam lists them.
  out.define("ALTA_PARAM_IN", std::to_string(int(grid.param)));
  out.define("ALTA_DIMS", std::to_string(dims));
  for (int d = 0; d < 4; ++d) {
    const std::string k = std::to_string(d);
    const std::size_t n = d < dims ? grid.axes[std::size_t(d)].size() : 1;
    out.define("ALTA_N" + k, std::uint32_t(n));
    out.define("ALTA_STEPS" + k, searchSteps(n));
    out.define("ALTA_FOLD" + k, std::to_string(d < dims ? int(grid.folds[std::size_t(d)]) : 0));
    out.define("ALTA_AT_AXIS" + k, std::uint32_t(table.size()));
    if (d < dims)
      table.insert(table.end(), grid.axes[std::size_t(d)].begin(), grid.axes[std::size_t(d)].end());
    else
      table.push_back(0.0f);
  }
  out.define("ALTA_AT_RGB", std::uint32_t(table.size()));
  out.define("ALTA_NODES", std::uint32_t(grid.nodes()));
  out.define("ALTA_COSINE", grid.cosineFactor ? "1" : "0");
  table.insert(table.end(), grid.rgb.begin(), grid.rgb.end());
  out.add("altaData", table);
  return out;
}

AltaSynthPlan planAltaSynth(AltaParam param, AltaOutput output, std::size_t scattered) {
  AltaSynthPlan plan;
  plan.data.param = param;
  plan.data.output = output;
  const double maxTheta = 89.0 * kPi / 180.0;  // grazing nodes stay just above the horizon
  // Grid nodes whose light or view lies below the horizon hold 0, as f cos does there.
  const auto push = [&](const std::vector<double>& x, glm::dvec3 wi, glm::dvec3 wo) {
    plan.data.x.insert(plan.data.x.end(), x.begin(), x.end());
    plan.wi.push_back(wi), plan.wo.push_back(wo);
  };
  const bool hasGrid = altaParamIsTableParam(param);
  if (scattered > 0 || !hasGrid) {
    std::uint64_t state = 0x9e3779b97f4a7c15ull;
    const auto uniform = [&] {  // splitmix64
      std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
      return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    };
    const std::size_t count = scattered > 0 ? scattered : 20000;
    for (std::size_t i = 0; i < count; ++i) {
      const glm::dvec3 wi = direction(angle(uniform()), 2.0 * kPi * uniform());
      const glm::dvec3 wo = direction(angle(uniform()), 2.0 * kPi * uniform());
      if (param == AltaParam::Cartesian) {
        push({wo.x, wo.y, wo.z, wi.x, wi.y, wi.z}, wi, wo);
      } else {
        const auto k = altaRawCoordinates(param, wi, wo);
        push(std::vector<double>(k.begin(), k.begin() + altaParamDimension(param)), wi, wo);
      }
    }
  } else {
    const auto even = [](int n, double lo, double hi) {
      std::vector<double> v;
      for (int k = 0; k < n; ++k) v.push_back(lo + (hi - lo) * k / (n - 1.0));
      return v;
    };
    std::vector<double> halfAngles;  // MERL's theta_h spacing: dense near the pole, where lobes are narrow
    const bool rusin3 = param == AltaParam::RusinThTdPd;
    for (double u : even(rusin3 ? 24 : 48, 0.0, 1.0)) halfAngles.push_back(u * u * maxTheta);
    switch (param) {
      case AltaParam::RusinThTdPd:
        for (double th : halfAngles)
          for (double td : even(24, 0.0, maxTheta))
            for (double pd : even(24, 0.0, kPi)) {
              glm::dvec3 wi, wo;
              altaRusinDirections(th, td, pd, wi, wo);
              push({th, td, pd}, wi, wo);
            }
        break;
      case AltaParam::RusinThTd:
        for (double th : halfAngles)
          for (double td : even(48, 0.0, maxTheta)) {
            glm::dvec3 wi, wo;
            altaRusinDirections(th, td, 0.5 * kPi, wi, wo);
            push({th, td}, wi, wo);
          }
        break;
      case AltaParam::IsotropicTvTlDphi:
        for (double tv : even(24, 0.0, maxTheta))
          for (double tl : even(24, 0.0, maxTheta))
            for (double dphi : even(24, 0.0, kPi))
              push({tv, tl, dphi}, direction(tl, dphi), direction(tv, 0.0));
        break;
      default:
        for (double tl : even(12, 0.0, maxTheta))
          for (double pl : even(24, -kPi, kPi))
            for (double tv : even(12, 0.0, maxTheta))
              for (double pv : even(24, -kPi, kPi))
                push({tl, pl, tv, pv}, direction(tl, pl), direction(tv, pv));
    }
  }
  plan.data.samples = plan.wi.size();
  return plan;
}

AltaData finishAltaSynth(AltaSynthPlan plan, const std::vector<glm::dvec3>& f) {
  AltaData& data = plan.data;
  data.rgb.resize(3 * data.samples);
  for (std::size_t i = 0; i < data.samples; ++i) {
    const bool valid = plan.wi[i].z > 0.0 && plan.wo[i].z > 0.0;
    glm::dvec3 v = valid ? glm::max(f[i], glm::dvec3(0.0)) : glm::dvec3(0.0);
    if (data.output == AltaOutput::InvSteradianCosine) v *= std::max(plan.wi[i].z, 0.0);
    for (int c = 0; c < 3; ++c) data.rgb[3 * i + std::size_t(c)] = v[c];
  }
  return std::move(plan.data);
}

}  // namespace iblx
