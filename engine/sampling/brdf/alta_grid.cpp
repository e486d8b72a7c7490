// ALTA data on a grid: detection, resampling of scattered samples, lookup and the writer's grids
// (alta_grid.h).
#include "engine/sampling/brdf/alta_grid.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <queue>

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

bool isAzimuth(AltaParam param, int dim) {
  switch (param) {
    case AltaParam::RusinThTdPd:
    case AltaParam::IsotropicTvTlDphi:
      return dim == 2;
    case AltaParam::SphericalTlPlTvPv:
      return dim == 1 || dim == 3;
    default:
      return false;
  }
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
  if (!isAzimuth(param, dim)) return AltaFold::Clamp;
  if (hi - lo >= 2.0 * kPi - 0.1) return AltaFold::Turn;
  const bool isotropic = param != AltaParam::SphericalTlPlTvPv;
  if (isotropic && lo >= -0.01 && hi <= kPi + 0.01) {
    const bool quarter = hi <= 0.5 * kPi + 0.01;
    if (param == AltaParam::RusinThTdPd) return quarter ? AltaFold::ReciprocityMirror : AltaFold::Reciprocity;
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

// The samples' coordinates in the grid's parametrisation (Cartesian samples become spherical ones).
std::vector<double> gridCoordinates(const AltaData& data, AltaParam gridParam) {
  if (data.param != AltaParam::Cartesian) return data.x;
  std::vector<double> x;
  x.reserve(data.samples * 4);
  for (std::size_t i = 0; i < data.samples; ++i) {
    const double* c = data.x.data() + 6 * i;
    const glm::dvec3 v(c[0], c[1], c[2]), l(c[3], c[4], c[5]);
    const auto k = altaRawCoordinates(gridParam, glm::length(l) > 0 ? glm::normalize(l) : l,
                                      glm::length(v) > 0 ? glm::normalize(v) : v);
    x.insert(x.end(), k.begin(), k.begin() + 4);  // SPHERICAL_TL_PL_TV_PV
  }
  return x;
}

// The k nearest samples of a point (normalized coordinates in [0, 1]^dims), found through an even grid of
// buckets, ring by ring.
class NeighbourSearch {
 public:
  NeighbourSearch(const std::vector<double>& points, int dims, int cellsPerAxis)
      : points_(points), dims_(dims), cells_(cellsPerAxis) {
    std::size_t total = 1;
    for (int d = 0; d < dims; ++d) total *= std::size_t(cells_);
    buckets_.assign(total, {});
    for (std::size_t i = 0; i < points.size() / std::size_t(dims); ++i)
      buckets_[cellOf(&points[i * std::size_t(dims)])].push_back(std::uint32_t(i));
  }
  // (distance^2, index) of the k nearest points to p.
  std::vector<std::pair<double, std::uint32_t>> nearest(const double* p, int k) const {
    std::priority_queue<std::pair<double, std::uint32_t>> best;  // the k smallest, largest on top
    int centre[4] = {0, 0, 0, 0};
    for (int d = 0; d < dims_; ++d) centre[d] = std::clamp(int(p[d] * cells_), 0, cells_ - 1);
    for (int r = 0; r <= cells_; ++r) {
      // Every point within the rings searched so far is at least (r - 1) cells away from p in one axis.
      if (int(best.size()) == k && best.top().first <= std::pow(double(std::max(r - 1, 0)) / cells_, 2))
        break;
      visitRing(centre, r, [&](std::size_t bucket) {
        for (std::uint32_t i : buckets_[bucket]) {
          double d2 = 0.0;
          for (int d = 0; d < dims_; ++d) {
            const double t = points_[i * std::size_t(dims_) + std::size_t(d)] - p[d];
            d2 += t * t;
          }
          if (int(best.size()) < k)
            best.emplace(d2, i);
          else if (d2 < best.top().first) {
            best.pop();
            best.emplace(d2, i);
          }
        }
      });
    }
    std::vector<std::pair<double, std::uint32_t>> out;
    for (; !best.empty(); best.pop()) out.push_back(best.top());
    return out;
  }

 private:
  std::size_t cellOf(const double* p) const {
    std::size_t index = 0;
    for (int d = 0; d < dims_; ++d)
      index = index * std::size_t(cells_) + std::size_t(std::clamp(int(p[d] * cells_), 0, cells_ - 1));
    return index;
  }
  // The buckets whose largest offset from the centre is exactly r.
  template <typename Visit>
  void visitRing(const int* centre, int r, Visit visit) const {
    int offset[4] = {-r, -r, -r, -r};
    while (true) {
      int largest = 0;
      bool inside = true;
      std::size_t index = 0;
      for (int d = 0; d < dims_; ++d) {
        largest = std::max(largest, std::abs(offset[d]));
        const int c = centre[d] + offset[d];
        inside = inside && c >= 0 && c < cells_;
        index = index * std::size_t(cells_) + std::size_t(std::clamp(c, 0, cells_ - 1));
      }
      if (inside && largest == r) visit(index);
      int d = 0;
      while (d < dims_ && ++offset[d] > r) offset[d++] = -r;
      if (d == dims_) break;
    }
  }

  const std::vector<double>& points_;
  int dims_, cells_;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

}  // namespace

AltaGrid makeAltaGrid(const AltaData& data, const std::string& name) {
  AltaGrid grid;
  grid.param = data.param == AltaParam::Cartesian ? AltaParam::SphericalTlPlTvPv : data.param;
  grid.cosineFactor = data.output == AltaOutput::InvSteradianCosine;
  const int dims = altaParamDimension(grid.param);
  const std::vector<double> x = gridCoordinates(data, grid.param);
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
    // About kNeighbours samples per bucket on average, so that most searches end in the first rings.
    const int buckets = std::clamp(int(std::pow(double(n) / kNeighbours, 1.0 / dims)), 1, perAxis);
    const NeighbourSearch search(unit, dims, buckets);
    grid.rgb.assign(3 * nodes, 0.0f);
    std::vector<double> p(dimCount);
    for (std::size_t node = 0; node < nodes; ++node) {
      std::size_t rest = node;
      for (int d = dims - 1; d >= 0; --d) {
        const std::size_t count = grid.axes[std::size_t(d)].size();
        p[std::size_t(d)] = count > 1 ? double(rest % count) / double(count - 1) : 0.0;
        rest /= count;
      }
      glm::dvec3 sum(0.0);
      double weights = 0.0;
      for (const auto& [d2, i] : search.nearest(p.data(), kNeighbours)) {
        // An exact hit takes the sample's value; otherwise Shepard's weights 1 / d^2.
        const double w = d2 < 1e-24 ? 1e24 : 1.0 / d2;
        sum += w * glm::dvec3(data.rgb[3 * i], data.rgb[3 * i + 1], data.rgb[3 * i + 2]);
        weights += w;
      }
      for (int c = 0; c < 3; ++c) grid.rgb[std::size_t(c) * nodes + node] = float(sum[c] / weights);
    }
    grid.resampledFrom = n;
    std::string shape;
    for (const auto& axis : grid.axes)
      shape.append(shape.empty() ? "" : " x ").append(std::to_string(axis.size()));
    warn(name + ": the " + std::to_string(n) + " samples " +
         (data.param == AltaParam::Cartesian ? std::string("are CARTESIAN directions")
                                             : std::string("do not lie on a regular grid")) +
         "; resampled onto a " + shape + " " + altaParamName(grid.param) +
         " grid by inverse-distance weighting of the 8 nearest samples");
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
  // shaders/brdf/alta_data.glsl's numbering of the parametrisations.
  const int glslParam = grid.param == AltaParam::RusinThTdPd         ? 0
                        : grid.param == AltaParam::RusinThTd         ? 1
                        : grid.param == AltaParam::IsotropicTvTlDphi ? 2
                                                                     : 3;
  out.define("ALTA_PARAM", std::to_string(glslParam));
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
  if (scattered > 0 || param == AltaParam::Cartesian) {
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
