// The registry's lists, looked up by name, and the methods derived from the env techniques.
#include "engine/scene/methods.h"

#include "engine/core/error.h"

#include <doctest/doctest.h>

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

}  // namespace iblx
