// Method resolution and method words, BRDF parameters: what the engine checks, in its own words
// (SettingError names the setting; the front ends name the flag or control).
#include "engine/core/setting.h"
#include "engine/scene/brdf_params.h"
#include "engine/scene/scene.h"

#include <doctest/doctest.h>

#include <cstring>

namespace iblx {
namespace {

// The setting and message of the SettingError `f` throws; fails the test when it throws nothing else.
template <typename F>
std::pair<Setting, std::string> settingErrorOf(F&& f) {
  try {
    f();
  } catch (const SettingError& e) {
    return {e.setting(), e.what()};
  }
  FAIL("expected a SettingError");
  return {};
}

}  // namespace

TEST_CASE("method words: options by name, errors that say what is valid") {
  const MethodSpec a = parseMethodVariant("mis:env-hier:power:split=0.25");
  CHECK(a.method == "mis");
  CHECK(a.envSampler == "env-hier");
  CHECK(a.misHeuristic == "power");
  CHECK(*a.misEnvFraction == 0.25);
  const MethodSpec b = parseMethodVariant("ris:M=32");
  CHECK(*b.risCandidates == 32);
  CHECK(parseMethodVariant("brdf:brdf-tab").brdfSampler == "brdf-tab");
  // `cosine` is an env and a BRDF technique: brdf:cosine used to set the env technique (ignored by brdf, with
  // a warning) and sample with the BRDF's best technique instead.
  CHECK(parseMethodVariant("brdf:cosine").brdfSampler == "cosine");
  CHECK(parseMethodVariant("brdf:cosine").envSampler.empty());
  CHECK(parseMethodVariant("mis:cosine").envSampler == "cosine");
  const MethodSpec both = parseMethodVariant("mis:env-cdf:cosine");
  CHECK(both.envSampler == "env-cdf");
  CHECK(both.brdfSampler == "cosine");
  CHECK(parseMethodVariant("mis:compensated").misCompensation);
  const auto [setting, message] = settingErrorOf([] { parseMethodVariant("mis:bogus"); });
  CHECK(setting == Setting::Method);
  CHECK(message ==
        "method mis:bogus: unknown option 'bogus'; options are env and BRDF technique names, "
        "balance, power, compensated, M=N and split=F");
  CHECK_THROWS_WITH_AS(parseMethodVariant("ris:M=0"), doctest::Contains("M must be 1-64"), SettingError);
  CHECK_THROWS_AS(parseMethodVariant("mis:"), SettingError);
  CHECK_THROWS_AS(parseMethodVariant("nomethod"), SettingError);
  // Defaults: every registry method that applies to the BRDF, each once.
  CHECK(defaultMethodSpecs(findBrdf("ggx")).size() == methodRegistry().size());
}

TEST_CASE("a SettingError reads with the engine's name, and with a front end's") {
  const auto [setting, message] = settingErrorOf([] { findMethod("bogus"); });
  CHECK(setting == Setting::Method);
  CHECK(message.rfind("unknown method 'bogus'; valid: uniform, cosine, env-cdf", 0) == 0);
  try {
    findMethod("bogus");
  } catch (const SettingError& e) {
    CHECK(e.named("--method").rfind("unknown --method 'bogus'; valid: ", 0) == 0);
  }
}

TEST_CASE("method resolution: defaults, ranges, techniques that do not apply, and ignored settings") {
  const BrdfInfo& ggx = findBrdf("ggx");
  const BrdfInfo& lambert = findBrdf("lambert");
  MethodSpec mis;
  const ResolvedMethod r = resolveMethod(mis, ggx);
  CHECK(r.envTechnique->name == "env-cdf");
  CHECK(r.brdfTechnique->name == ggx.bestSampler);
  CHECK_FALSE(r.misOneSample);
  CHECK(r.drawsPerSample() == 2);
  CHECK(r.ignoredSettings.empty());

  MethodSpec split = mis;
  split.misEnvFraction = 1.5;
  CHECK(settingErrorOf([&] { resolveMethod(split, ggx); }).first == Setting::MisSplit);
  MethodSpec candidates{"ris"};
  candidates.risCandidates = 65;
  CHECK(settingErrorOf([&] { resolveMethod(candidates, ggx); }).first == Setting::RisCandidates);
  MethodSpec heuristic = mis;
  heuristic.misHeuristic = "max";
  CHECK(settingErrorOf([&] { resolveMethod(heuristic, ggx); }).first == Setting::MisHeuristic);

  MethodSpec vndf{"brdf"};
  vndf.brdfSampler = "ggx-vndf";
  const auto [setting, message] = settingErrorOf([&] { resolveMethod(vndf, lambert); });
  CHECK(setting == Setting::BrdfSampler);
  CHECK(message ==
        "BRDF technique ggx-vndf does not apply to BRDF 'lambert'; those that do: cosine, brdf-tab");

  MethodSpec single{"env-cdf"};
  single.envSampler = "env-hier";
  single.misEnvFraction = 0.5;
  const ResolvedMethod ignoring = resolveMethod(single, ggx);
  CHECK(ignoring.envTechnique->name == "env-cdf");
  CHECK(ignoring.ignoredSettings == std::vector<Setting>{Setting::EnvSampler, Setting::MisSplit});
}

TEST_CASE("BRDF parameters: defaults, shorthands, ranges and the 16-byte slots of the GPU block") {
  const BrdfInfo& ggx = findBrdf("ggx");
  const ParamValues values = resolveParams(ggx, {{"color", "0.5"}, {"roughness", "0.1"}});
  CHECK(values.at("color") == std::array<double, 3>{0.5, 0.5, 0.5});  // grey shorthand
  CHECK(values.at("roughness")[0] == 0.1);
  CHECK(values.at("metallic")[0] == 1.0);  // default
  const std::vector<float> packed = packParams(ggx, values);
  REQUIRE(packed.size() == 12);
  CHECK(packed[0] == 0.5f);
  CHECK(packed[2] == 0.5f);
  CHECK(packed[4] == 0.1f);
  CHECK(packed[8] == 1.0f);
  const std::string block = paramBlockGlsl(ggx);
  CHECK(block.find("vec3 color; float iblxPad0;") != std::string::npos);
  CHECK(block.find("float roughness; float iblxPad1[3];") != std::string::npos);

  const auto bad = [&](const char* name, const char* value) {
    return settingErrorOf([&] { resolveParams(ggx, {{name, value}}); });
  };
  CHECK(bad("roughness", "2").second == "BRDF parameter roughness=2: out of range [0.001, 1]");
  CHECK(bad("roughness", "abc").second == "BRDF parameter roughness=abc: 'abc' is not a number");
  CHECK(bad("color", "1,1").second == "BRDF parameter color=1,1: expected a color r,g,b");
  CHECK(bad("color", "1,1,1,1").second == "BRDF parameter color=1,1,1,1: too many values");
  CHECK(bad("color", "1,").second == "BRDF parameter color=1,: trailing comma");
  CHECK(bad("shininess", "3")
            .second.find("has no parameter 'shininess'; its parameters: color, roughness, "
                         "metallic") != std::string::npos);
  CHECK(bad("roughness", "3").first == Setting::BrdfParam);
}

}  // namespace iblx
