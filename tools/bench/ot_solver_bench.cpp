// Benchmark of the OT map solver (engine/ot/solver.h): iterations, time, L2 / L1 / Linf mass errors
// and folded quads for n = 128, 256, 512, 1024 on synthetic densities and on any .exr/.hdr given; with --lu,
// the grid LU alone (engine/ot/grid_lu.h): symbolic phase, factorisation and solve times.
//   build/iblx_ot_bench [--sizes 128,256] [--cases smooth,sun1e5] [--threads T] [--no-coarse] [--no-curved]
//                       [--coarse-target L2] [--levels] [--max-iter N] [FILE.exr ...]
//   build/iblx_ot_bench --lu [--sizes 256,512,1024] [--threads T]
#include "engine/core/error.h"
#include "engine/io/env_image.h"
#include "engine/ot/grid_lu.h"
#include "engine/ot/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace iblx;

namespace {

struct Case {
  std::string name;
  std::function<std::vector<double>(int)> density;  // n -> n x n density
};

// Lat-long grid density from a radiance function of (u, v), times sin(theta) at the cell centre.
std::vector<double> fromRadiance(int n, const std::function<double(double, double)>& radiance) {
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = (i + 0.5) / n, v = (j + 0.5) / n;
      d[std::size_t(j) * n + i] = radiance(u, v) * std::sin(std::numbers::pi * v);
    }
  return d;
}

// A sky with a sun of `peak` x the sky over a Gaussian of sigma = 1 cell (a few cells), centred on a cell
// centre.
std::vector<double> sun(int n, double peak) {
  const int ci = n / 3, cj = n / 4;
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r2 = double(i - ci) * (i - ci) + double(j - cj) * (j - cj);
      d[std::size_t(j) * n + i] = 1.0 + peak * std::exp(-0.5 * r2);
    }
  return d;
}

std::vector<Case> syntheticCases() {
  return {
      {"smooth",
       [](int n) {
         return fromRadiance(n, [](double u, double v) {
           return 0.3 + 0.75 * (1 + std::cos(std::numbers::pi * v)) +
                  0.4 * (1 + std::cos(2 * std::numbers::pi * u));
         });
       }},
      {"sun1e3", [](int n) { return sun(n, 1e3); }},
      {"sun1e5", [](int n) { return sun(n, 1e5); }},
      {"halfzero",
       [](int n) {
         std::vector<double> d(std::size_t(n) * n);
         for (int j = 0; j < n; ++j)
           for (int i = 0; i < n; ++i) d[std::size_t(j) * n + i] = i < n / 2 ? 0.0 : 1.0;
         return d;
       }},
      {"skyzero",
       [](int n) {  // sky over an exactly-black lower hemisphere, with a 1e4 sun
         auto d = fromRadiance(n, [](double u, double v) {
           if (v >= 0.5) return 0.0;
           const double du = u - 0.3, dv = v - 0.2;
           return 1.0 + 1e4 * std::exp(-(du * du + dv * dv) / (2 * 0.004 * 0.004));
         });
         return d;
       }},
  };
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The grid LU on a matrix shaped like the OT Jacobian (the nine-point stencil of an M-matrix with random
// weights, rows summing to 0, row 0 pinned as the solver pins it): the symbolic phase once, then the median
// of 5 factorisations and of 10 solves, and the relative residual of one solve (single-precision factors).
void benchmarkLu(const std::vector<int>& sizes, int threads) {
  std::printf("%6s %10s %10s %10s %10s %10s %12s\n", "n", "symbolic", "factor", "solve", "fill_M", "GFlop",
              "residual");
  for (int n : sizes) {
    StencilMatrix a(n, n);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> weight(0.1, 1.0);
    for (int c = 0; c < n * n; ++c) {
      double sum = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c % n + dx, y = c / n + dy;
          if ((dx == 0 && dy == 0) || x < 0 || x >= n || y < 0 || y >= n) continue;
          sum += a.at(c, dx, dy) = -weight(rng);
        }
      a.at(c, 0, 0) = -sum;
    }
    std::fill_n(a.values.begin(), 9, 0.0);
    a.at(0, 0, 0) = 1.0;
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::time_point from) {
      return std::chrono::duration<double>(Clock::now() - from).count();
    };
    auto start = Clock::now();
    GridLu lu(n, n, threads);
    const double symbolic = seconds(start);
    std::vector<double> factorTimes, solveTimes;
    for (int k = 0; k < 5; ++k) {
      start = Clock::now();
      lu.factor(a);
      factorTimes.push_back(seconds(start));
    }
    std::vector<double> b(std::size_t(n) * n), x, ax(b.size());
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& v : b) v = uniform(rng);
    for (int k = 0; k < 10; ++k) {
      x = b;
      start = Clock::now();
      lu.solve(x);
      solveTimes.push_back(seconds(start));
    }
    a.multiply(x, ax);
    double r2 = 0.0, b2 = 0.0;
    for (std::size_t i = 0; i < b.size(); ++i) r2 += (ax[i] - b[i]) * (ax[i] - b[i]), b2 += b[i] * b[i];
    std::printf("%6d %10.3f %10.3f %10.4f %10.1f %10.2f %12.2e\n", n, symbolic, median(factorTimes),
                median(solveTimes), double(lu.factorEntries()) / 1e6, lu.factorFlops() / 1e9,
                std::sqrt(r2 / b2));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<int> sizes{128, 256, 512, 1024};
    std::vector<std::string> caseFilter, files;
    OtSolverOptions options;
    bool printLevels = false;  // one line per coarse-to-fine level under each result
    bool luOnly = false;
    for (int a = 1; a < argc; ++a) {
      const std::string arg = argv[a];
      const auto value = [&]() -> std::string {
        if (a + 1 >= argc) throw Error(arg + ": missing value");
        return argv[++a];
      };
      if (arg == "--sizes") {
        sizes.clear();
        for (const auto& s : split(value())) sizes.push_back(std::stoi(s));
      } else if (arg == "--cases") {
        caseFilter = split(value());
      } else if (arg == "--threads") {
        options.threads = std::stoi(value());
      } else if (arg == "--coarse-target") {
        options.coarseTargetL2 = std::stod(value());
      } else if (arg == "--lu") {
        luOnly = true;
      } else if (arg == "--levels") {
        printLevels = true;
      } else if (arg == "--no-coarse") {
        options.coarseToFine = false;
      } else if (arg == "--no-curved") {
        options.secondOrderCorrection = false;
      } else if (arg == "--boundary-fraction") {
        options.boundaryFraction = std::stod(value());
      } else if (arg == "--krylov") {
        options.krylovSteps = std::stoi(value());
      } else if (arg == "--guard") {
        const std::string g = value();
        if (g != "none" && g != "area" && g != "convex")
          throw Error("--guard: expected none, area or convex, got " + g);
        options.foldGuard = g == "none"   ? OtFoldGuard::None
                            : g == "area" ? OtFoldGuard::Area
                                          : OtFoldGuard::Convex;
      } else if (arg == "--absolute") {
        options.relativeResidual = false;
      } else if (arg == "--krylov-tol") {
        options.krylovTolerance = std::stod(value());
      } else if (arg == "--floor") {
        options.floorFraction = std::stod(value());
      } else if (arg == "--stage-log-error") {
        options.stageLogError = std::stod(value());
      } else if (arg == "--stage-min-step") {
        options.stageMinStep = std::stod(value());
      } else if (arg == "--homotopy-power") {
        options.homotopyPower = std::stod(value());
      } else if (arg == "--smoothing-passes") {
        options.maxSmoothingPasses = std::stoi(value());
      } else if (arg == "--max-iter") {
        options.maxIterations = std::stoi(value());
      } else if (arg == "--help") {
        std::printf(
            "usage: iblx_ot_bench [--sizes 128,256,...] [--cases smooth,sun1e3,sun1e5,halfzero,skyzero]\n"
            "                     [--threads T] [--levels] [--max-iter N] [FILE.exr|FILE.hdr ...]\n"
            "       iblx_ot_bench --lu [--sizes 256,512,1024] [--threads T]   (the grid LU alone)\n"
            "solver options (OtSolverOptions, for experiments; defaults as the samplers use them):\n"
            "  --floor EPS  --coarse-target L2  --no-coarse  --no-curved  --boundary-fraction F\n"
            "  --stage-log-error E  --stage-min-step S  --homotopy-power P  --krylov M (>= 1)  --krylov-tol "
            "T\n"
            "  --smoothing-passes N (most binomial passes on a folded prolonged start)\n"
            "  --guard none|area|convex  --absolute\n");
        return 0;
      } else if (!arg.empty() && arg[0] == '-') {
        throw Error(arg + ": unknown flag (see --help)");
      } else {
        files.push_back(arg);
      }
    }
    if (luOnly) {
      benchmarkLu(sizes, options.threads);
      return 0;
    }
    std::vector<Case> cases;
    for (Case& c : syntheticCases()) {
      bool keep = caseFilter.empty();
      for (const auto& f : caseFilter) keep = keep || f == c.name;
      if (keep) cases.push_back(std::move(c));
    }
    for (const std::string& file : files) {
      auto image = std::make_shared<EnvImage>(loadEnvImage(file));
      cases.push_back({file, [image](int n) { return otDensityFromEnv(*image, n); }});
    }
    std::printf("%-28s %5s %6s %7s %9s %10s %10s %10s %7s %7s %s\n", "case", "n", "iters", "coarse",
                "seconds", "L2", "L1", "Linf", "nonconv", "negarea", "conv");
    for (const Case& c : cases)
      for (int n : sizes) {
        const std::vector<double> density = c.density(n);
        const OtMap map = solveOtMap(density, n, options);
        std::printf("%-28s %5d %6d %7d %9.3f %10.2e %10.2e %10.2e %7d %7d %s\n", c.name.c_str(), n,
                    map.iterations, map.coarseIterations, map.seconds, map.l2, map.l1, map.linf,
                    map.foldedQuads, map.negativeAreaQuads, map.converged ? "yes" : "no");
        if (printLevels)
          for (const OtLevelStats& l : map.levels)
            std::printf(
                "    level %4d: %4d iters %3d stages (%d undone) %3d LU %5d krylov %3d curved %8.3f s  L2 "
                "%.2e  %s\n",
                l.n, l.iterations, l.stages, l.undoneStages, l.factorisations, l.krylovSteps, l.curvedSteps,
                l.seconds, l.l2, otLevelStartNote(l).c_str());
        std::fflush(stdout);
      }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "iblx_ot_bench: %s\n", e.what());
    return 1;
  }
}
