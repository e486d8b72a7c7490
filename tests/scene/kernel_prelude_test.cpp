// Kernel preludes: every table bound by name and width at consecutive bindings, duplicates refused, and
// glslang's undeclared-table errors turned into messages that name the table and who provides what.
#include "engine/scene/kernel_prelude.h"

#include "engine/core/error.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_hier.h"
#include "engine/io/synthetic_envs.h"

#include <doctest/doctest.h>

#include <array>
#include <memory>

namespace iblx {
namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TechniqueData twoTables() {
  const std::array<float, 3> cdf{0.0f, 0.5f, 1.0f};
  const std::array<glm::vec4, 2> rects{};
  TechniqueData data;
  data.add("testCdf", std::span<const float>(cdf));
  data.add("testRects", std::span<const glm::vec4>(rects));
  data.define("TEST_SIZE", 3u);
  return data;
}

}  // namespace

TEST_CASE("a table's element width is its element type's") {
  const TechniqueData data = twoTables();
  REQUIRE(data.tables.size() == 2);
  CHECK(data.tables[0].words == 1);
  CHECK(data.tables[0].bytes.size() == 12);
  CHECK(data.tables[1].words == 4);
  CHECK(data.tables[1].bytes.size() == 32);
  const TechniqueData layout = data.layout();
  CHECK(layout.tables[1].name == "testRects");
  CHECK(layout.tables[1].words == 4);
  CHECK(layout.tables[1].bytes.empty());
  CHECK(layout.defines == data.defines);
}

TEST_CASE("the prelude defines each table's set and binding under its name and width") {
  KernelParts parts{"integrate.comp", {"env_technique/env_cdf.glsl"}, "", {}, {}, {}};
  CHECK(parts.bindTables(kEnvTechniqueSet, 0, twoTables(), "env technique test") == 2);
  const std::string prelude = assemblePrelude(parts);
  INFO(prelude);
  CHECK(contains(prelude, "#define IBLX_SET_testCdf 2\n#define IBLX_BINDING_testCdf_W1 0\n"));
  CHECK(contains(prelude, "#define IBLX_SET_testRects 2\n#define IBLX_BINDING_testRects_W4 1\n"));
  CHECK(contains(prelude, "#define TEST_SIZE 3u\n"));
  // The frame's tables are in every prelude.
  CHECK(contains(prelude, "#define IBLX_SET_envRgb 0\n#define IBLX_BINDING_envRgb_W1 2\n"));
  CHECK(contains(prelude, "#define IBLX_BINDING_envRows_W4 3\n"));
  // A second technique with the same table names cannot be bound beside the first.
  CHECK_THROWS_WITH_AS(
      parts.bindTables(kBrdfSet, 1, twoTables(), "BRDF technique test"),
      doctest::Contains("'testCdf' of BRDF technique test is already bound by env technique test"), Error);
}

TEST_CASE("an undeclared table becomes a message naming it and the tables the kernel binds") {
  KernelParts parts{"integrate.comp", {}, "", {}, {}, {}};
  parts.bindTables(kEnvTechniqueSet, 0, twoTables(), "env technique test");
  const std::string missing = explainMissingTable(
      parts,
      "shaders/env_technique/env_cdf.glsl:10: 'IBLX_SET_envCdf' : undeclared identifier (and 4 more errors)");
  INFO(missing);
  CHECK(contains(missing, "shaders/env_technique/env_cdf.glsl:10: the part reads table 'envCdf'"));
  CHECK(contains(missing, "testCdf (1-word, env technique test)"));
  CHECK(contains(missing, "testRects (4-word, env technique test)"));
  const std::string width = explainMissingTable(
      parts, "shaders/x.glsl:3: 'IBLX_BINDING_testCdf_W4' : undeclared identifier (and 4 more errors)");
  INFO(width);
  CHECK(contains(width,
                 "shaders/x.glsl:3: the part reads table 'testCdf' with 4-word elements, but env "
                 "technique test provides 1-word elements"));
  CHECK(explainMissingTable(parts, "shaders/x.glsl:3: 'foo' : undeclared identifier").empty());
}

TEST_CASE(
    "the integrator binds the env technique's tables to set 2 and the BRDF technique's after the BRDF's") {
  Scene scene;
  scene.brdf = std::make_shared<const BrdfInfo>(findBrdf("ggx"));
  MethodSpec spec;
  spec.method = "mis";
  spec.envSampler = "env-hier";
  const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
  TechniqueData brdfData, brdfTechnique;
  const std::array<float, 1> one{1.0f};
  brdfData.add("testBrdfTable", std::span<const float>(one));
  brdfTechnique.add("testSamplerTable", std::span<const float>(one));
  const EnvImage env = constantEnv(8, 4, 1.0f);
  const KernelParts parts =
      integratorParts(scene, brdfData, EnvChunking{2, 16}, method, envHierTechniqueData(env), brdfTechnique);
  const std::string prelude = assemblePrelude(parts);
  INFO(prelude);
  CHECK(contains(prelude, "#define IBLX_SET_hierSplits 2\n#define IBLX_BINDING_hierSplits_W4 0\n"));
  CHECK(contains(prelude, "#define IBLX_BINDING_hierTexelRects_W4 2\n"));
  CHECK(contains(prelude, "#define IBLX_SET_testBrdfTable 3\n#define IBLX_BINDING_testBrdfTable_W1 1\n"));
  CHECK(
      contains(prelude, "#define IBLX_SET_testSamplerTable 3\n#define IBLX_BINDING_testSamplerTable_W1 2\n"));
  CHECK(contains(prelude, "#define ENV_RADIANCE_CHUNKS 2\n"));
  CHECK(contains(prelude, "#define ENV_HIER_WIDTH 8\n"));
  CHECK(contains(prelude, "#include \"env_technique/env_hier.glsl\"\n"));
  CHECK(contains(prelude, "#include \"strategy/mis.glsl\"\n"));
}

TEST_CASE(
    "a product strategy's image kernel may keep its per-pixel tables in a set-0 buffer; others may not") {
  Scene scene;
  scene.brdf = std::make_shared<const BrdfInfo>(findBrdf("ggx"));
  const EnvImage env = constantEnv(8, 4, 1.0f);
  MethodSpec spec;
  spec.method = "product";
  const ResolvedMethod product = resolveMethod(spec, *scene.brdf);
  const TechniqueData envData = product.method->envData(env);
  const auto prelude = [&](const ResolvedMethod& m, IntegratorMode mode, ProductTableChunks chunks) {
    return assemblePrelude(integratorParts(scene, {}, EnvChunking{1, 32}, m, envData, {}, mode, chunks));
  };
  const std::string kept = prelude(product, IntegratorMode::Image, {3, 1000});
  CHECK(contains(kept, "#define PRODUCT_TABLE_BINDING " + std::to_string(kProductTableBinding) + "\n"));
  // The largest table (32 x 16 nodes) and the refinement's block after it.
  CHECK(contains(kept, "#define PRODUCT_TABLE_STRIDE " +
                           std::to_string(productTableWords(32, 16) + productRefineWords(512)) + "u\n"));
  CHECK(contains(kept, "#define PRODUCT_TABLE_CHUNKS 3\n#define PRODUCT_TABLE_PIXELS_PER_CHUNK 1000u\n"));
  // The image kernel samples the stored tables; only the product-table kernel builds them.
  CHECK(!contains(kept, "PRODUCT_TABLE_BUILD"));
  const std::string builds = prelude(product, IntegratorMode::ProductTables, {3, 1000});
  CHECK(contains(builds, "#define PRODUCT_TABLE_CHUNKS 3\n"));
  CHECK(contains(builds, "#define PRODUCT_TABLE_BUILD 1\n"));
  CHECK_THROWS_AS(prelude(product, IntegratorMode::ProductTables, {}), Error);
  CHECK(!contains(prelude(product, IntegratorMode::Image, {}), "PRODUCT_TABLE_BINDING"));
  CHECK_THROWS_AS(prelude(product, IntegratorMode::Image, {kProductTableMaxChunks + 1, 1000}), Error);
  // Recording puts its records at that binding and rebuilds its one pixel's table.
  CHECK_THROWS_AS(prelude(product, IntegratorMode::RecordPixel, {1, 1000}), Error);
  spec.method = "env-hier";
  CHECK_THROWS_AS(prelude(resolveMethod(spec, *scene.brdf), IntegratorMode::Image, {1, 1000}), Error);
}

}  // namespace iblx
