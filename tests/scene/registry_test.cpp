// The registry's lists, looked up by name, and the methods derived from the env techniques.
#include "engine/scene/methods.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "engine/scene/measured_brdfs.h"
#include "engine/scene/scene.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <set>

namespace iblx {

TEST_CASE("every registry list has unique names and every entry a GLSL part") {
  std::set<std::string> methods;
  for (const MethodInfo& m : methodRegistry()) CHECK(methods.insert(m.name).second);
  for (const EnvTechniqueInfo& t : envTechniqueRegistry()) CHECK_FALSE(t.part.empty());
  for (const BrdfTechniqueInfo& t : brdfTechniqueRegistry()) CHECK_FALSE(t.part.empty());
  for (const SequenceInfo& q : sequenceRegistry()) CHECK_FALSE(q.part.empty());
}

TEST_CASE("every env technique is a method of its own, in the registry's order") {
  const auto techniques = envTechniqueRegistry();
  const auto methods = methodRegistry();
  REQUIRE(methods.size() > techniques.size());
  for (std::size_t i = 0; i < techniques.size(); ++i) {
    CHECK(methods[i].name == techniques[i].name);
    CHECK(methods[i].strategy == Strategy::SingleEnv);
    CHECK(methods[i].envTechnique == techniques[i].name);
  }
}

TEST_CASE("lookups name the kind of thing and list the valid names") {
  CHECK(findMethod("mis").strategy == Strategy::Mis);
  try {
    findEnvTechnique("env-nope");
    FAIL("expected an error");
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.find("env-nope") != std::string::npos);
    CHECK(message.find("env-cdf") != std::string::npos);
    CHECK(message.find("env-hier") != std::string::npos);
  }
  CHECK(findBrdfForArgument("ggx")->name == "ggx");
  CHECK(findBrdfForArgument("material.brdf") == nullptr);
  CHECK(findBrdfForArgument("blue-metallic-paint.binary")->name == "merl");
  CHECK_THROWS_AS(findBrdfForArgument("merl"), Error);
}

TEST_CASE("the techniques that apply to one BRDF only say so") {
  const BrdfInfo& ggx = findBrdf("ggx");
  const BrdfInfo& lambert = findBrdf("lambert");
  CHECK(findBrdfTechnique("ggx-vndf").appliesTo(ggx));
  CHECK_FALSE(findBrdfTechnique("ggx-vndf").appliesTo(lambert));
  CHECK(findBrdfTechnique("cosine").appliesTo(lambert));
  CHECK_FALSE(findBrdfTechnique("isfunc").appliesTo(ggx));
}

TEST_CASE("every strategy is a registry entry whose part exists, and every method's strategy has one") {
  std::set<std::string> names;
  std::set<Strategy> ids;
  for (const StrategyInfo& s : strategyRegistry()) {
    CHECK(names.insert(s.name).second);
    CHECK(ids.insert(s.id).second);
    CHECK(std::filesystem::is_regular_file(std::filesystem::path(IBLX_REPO_DIR) / "shaders" / s.part));
    CHECK((s.usesEnvTechnique || s.usesBrdfTechnique));
    CHECK((!s.envTechniqueChosen || s.usesEnvTechnique));
    CHECK((s.drawsPerSample == 1 || s.drawsPerSample == 2));
    CHECK((!s.misSplit || s.drawsPerSample == 2));  // a one-sample split chooses one of two draws
  }
  for (const MethodInfo& m : methodRegistry()) CHECK(&findStrategy(m.strategy) == &m.strategyInfo());
}

TEST_CASE(
    "the resolver takes the techniques and options a strategy's capabilities name, and reports the rest") {
  const BrdfInfo& ggx = findBrdf("ggx");
  for (const MethodInfo& m : methodRegistry()) {
    CAPTURE(m.name);
    const StrategyInfo& s = m.strategyInfo();
    MethodSpec spec;
    spec.method = m.name;
    spec.envSampler = "env-hier";
    spec.brdfSampler = "cosine";
    spec.misHeuristic = "power";
    spec.risCandidates = 4;
    spec.misCompensation = true;
    const ResolvedMethod r = resolveMethod(spec, ggx);
    CHECK((r.envTechnique != nullptr) == s.usesEnvTechnique);
    CHECK((r.brdfTechnique != nullptr) == s.usesBrdfTechnique);
    if (s.envTechniqueChosen) CHECK(r.envTechnique->name == "env-hier");
    if (s.usesBrdfTechnique) CHECK(r.brdfTechnique->name == "cosine");
    const auto reported = [&](Setting setting) {
      return std::find(r.ignoredSettings.begin(), r.ignoredSettings.end(), setting) !=
             r.ignoredSettings.end();
    };
    CHECK(reported(Setting::EnvSampler) == !s.envTechniqueChosen);
    CHECK(reported(Setting::BrdfSampler) == !s.usesBrdfTechnique);
    CHECK(reported(Setting::MisHeuristic) == !s.misWeights);
    CHECK(reported(Setting::RisCandidates) == !s.risCandidates);
    CHECK(reported(Setting::MisCompensation) == !s.misSplit);
    CHECK(r.misCompensation == s.misSplit);
    CHECK(r.drawsPerSample() == s.drawsPerSample);
  }
  // ris takes no BRDF technique (a --brdf-sampler for it is reported, not silently used).
  MethodSpec ris;
  ris.method = "ris";
  ris.brdfSampler = "cosine";
  CHECK(resolveMethod(ris, ggx).brdfTechnique == nullptr);
  // A one-sample split draws one direction.
  MethodSpec oneSample;
  oneSample.method = "mis";
  oneSample.misEnvFraction = 0.3;
  CHECK(resolveMethod(oneSample, ggx).drawsPerSample() == 1);
  CHECK(resolveMethod(oneSample, ggx).label() == "mis(env-cdf+ggx-vndf, balance, one-sample 0.3)/sobol");
  // The default of every command and the viewer is mis/sobol (docs/RESULTS.md, "The default").
  CHECK(MethodSpec{}.method == "mis");
  CHECK(MethodSpec{}.sequence == "sobol");
}

TEST_CASE("an unknown --brdf lists every material file format of the registry") {
  try {
    findBrdfForArgument("nope");
    FAIL("expected an error");
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.find("merl .binary") != std::string::npos);
    for (const MaterialFileFormat& format : materialFileFormats()) {
      CAPTURE(format.name);
      CHECK(message.find(format.name) != std::string::npos);
    }
    CHECK(message.find(".bparam") != std::string::npos);
  }
}

TEST_CASE("every env technique with tables has a CPU twin whose pdf integrates to 1 over the sphere") {
  // A small map with a bright spot: the twins' pdfs follow it, and each must still hold unit mass
  // (midpoint rule on a fine lat-long grid; the pdfs are piecewise smooth at the map's texel scale).
  EnvImage env{32, 16, std::vector<float>(32 * 16 * 3, 0.2f)};
  for (int c = 0; c < 3; ++c) env.rgb[std::size_t((5 * 32 + 9) * 3 + c)] = 400.0f;
  for (const EnvTechniqueInfo& t : envTechniqueRegistry()) {
    CAPTURE(t.name);
    const bool baseline = t.name == "uniform" || t.name == "cosine";
    CHECK(bool(t.cpuPdf) == !baseline);
    if (!t.cpuPdf) continue;
    const auto pdf = t.cpuPdf(env);
    constexpr int kW = 512, kH = 256;
    double mass = 0.0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const glm::dvec3 w = latLongToDirection({(x + 0.5) / kW, (y + 0.5) / kH});
        mass += pdf(w) * latLongTexelSolidAngle(y, kW, kH);
      }
    CHECK(mass == doctest::Approx(1.0).epsilon(2e-3));
  }
}

}  // namespace iblx
