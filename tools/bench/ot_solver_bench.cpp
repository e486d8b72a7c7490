// Benchmark of the OT map solver (engine/sampling/ot_solver.h): iterations, time, L2 / L1 / Linf mass errors
// and folded quads for n = 128, 256, 512, 1024 on synthetic densities and on any .exr/.hdr given.
//   build/iblx_ot_bench [--sizes 128,256] [--cases smooth,sun1e5] [--threads T] [--no-coarse] [--no-curved]
//                       [--coarse-target L2] [--levels] [--max-iter N] [FILE.exr ...]
#include "engine/core/error.h"
#include "engine/io/env_image.h"
#include "engine/sampling/ot_solver.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
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

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<int> sizes{128, 256, 512, 1024};
    std::vector<std::string> caseFilter, files;
    OtSolverOptions options;
    bool printLevels = false;  // one line per coarse-to-fine level under each result
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
        options.foldGuard = g == "none"   ? OtFoldGuard::None
                            : g == "area" ? OtFoldGuard::Area
                                          : OtFoldGuard::Convex;
      } else if (arg == "--merit") {
        const std::string m = value();
        if (m != "l2" && m != "barrier") throw Error("--merit: expected l2 or barrier, got " + m);
        options.merit = m == "l2" ? OtMerit::L2 : OtMerit::Barrier;
      } else if (arg == "--gmres") {
        options.directNewton = false;
      } else if (arg == "--absolute") {
        options.relativeResidual = false;
      } else if (arg == "--krylov-tol") {
        options.krylovTolerance = std::stod(value());
      } else if (arg == "--log-newton") {
        options.logNewton = true;
      } else if (arg == "--floor") {
        options.floorFraction = std::stod(value());
      } else if (arg == "--cj") {
        options.conjugateJacobian = true;
      } else if (arg == "--max-iter") {
        options.maxIterations = std::stoi(value());
      } else if (arg == "--help") {
        std::printf(
            "usage: iblx_ot_bench [--sizes 128,256,...] [--cases smooth,sun1e3,sun1e5,halfzero,skyzero]\n"
            "                     [--threads T] [--no-coarse] [--no-curved] [--coarse-target L2] [--levels]\n"
            "                     [--max-iter N] [FILE.exr|FILE.hdr ...]\n");
        return 0;
      } else if (!arg.empty() && arg[0] == '-') {
        throw Error(arg + ": unknown flag (see --help)");
      } else {
        files.push_back(arg);
      }
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
                "%.2e%s\n",
                l.n, l.iterations, l.stages, l.undoneStages, l.factorisations, l.krylovSteps, l.curvedSteps,
                l.seconds, l.l2,
                l.restarted     ? ("  folded start, restarted at " + std::to_string(l.restartScale)).c_str()
                : l.foldedStart ? "  folded start"
                                : "");
        std::fflush(stdout);
      }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "iblx_ot_bench: %s\n", e.what());
    return 1;
  }
}
