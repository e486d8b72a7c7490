// --list-methods' text (registry_listing.h).
#include "tools/cli/registry_listing.h"

#include "engine/scene/brdf_params.h"
#include "engine/scene/measured_brdfs.h"

#include <algorithm>
#include <sstream>

namespace iblx {
namespace {

// A registry name padded to the listing's name column (17 wide, so product-warp-ot keeps two spaces).
std::string column(const std::string& name) {
  constexpr std::size_t kWidth = 17;
  return name + std::string(kWidth - std::min(kWidth - 1, name.size()), ' ');
}

}  // namespace

std::string describeRegistry() {
  std::ostringstream s;
  s << "methods (--method):\n";
  for (const auto& m : methodRegistry()) s << "  " << column(m.name) << m.description << "\n";
  // Which methods take a technique of the user's choice, read from their strategies' capabilities.
  const auto methodsWhere = [](bool (*takes)(const StrategyInfo&)) {
    std::string names;
    for (const auto& m : methodRegistry())
      if (takes(m.strategyInfo())) names += (names.empty() ? "" : ", ") + m.name;
    return names;
  };
  s << "env techniques (--env-sampler, used by "
    << methodsWhere([](const StrategyInfo& st) { return st.envTechniqueChosen; })
    << "; each is also a method):\n";
  for (const auto& t : envTechniqueRegistry()) s << "  " << column(t.name) << t.description << "; any BRDF\n";
  s << "BRDF techniques (--brdf-sampler, used by "
    << methodsWhere([](const StrategyInfo& st) { return st.usesBrdfTechnique; }) << "):\n";
  for (const auto& t : brdfTechniqueRegistry()) {
    s << "  " << column(t.name) << t.description << "; " << (t.applies ? "BRDFs: " : "") << t.appliesText
      << "\n";
  }
  s << "sequences (--seq):\n";
  for (const auto& q : sequenceRegistry()) s << "  " << column(q.name) << q.description << "\n";
  s << "BRDFs (--brdf NAME, or " << materialFileKindsText() << ") and parameters (--param NAME=VALUE):\n";
  for (const auto& b : brdfRegistry()) s << describeBrdf(b);
  return s.str();
}

std::string describeBrdf(const BrdfInfo& b) {
  std::ostringstream s;
  s << "  " << column(b.name) << b.description << "; best sampler: " << b.bestSampler << "\n";
  for (const auto& p : b.params) {
    s << "      " << p.name << " ("
      << (p.type == ParamType::Color  ? "color r,g,b"
          : p.type == ParamType::Bool ? "bool"
                                      : "float");
    if (p.type != ParamType::Bool) s << " in [" << p.min << ", " << p.max << "]";
    s << ", default " << formatParamValue(p, p.defaultValue) << ")";
    if (!p.description.empty()) s << ": " << p.description;
    s << "\n";
  }
  return s.str();
}

}  // namespace iblx
