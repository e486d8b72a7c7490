// Sample recording: a Renderer in IntegratorMode::RecordPixel, its records turned into world-space samples.
#include "engine/render/sample_recorder.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"

namespace iblx {
namespace {

// The record names the role of the technique; the method names the technique in that role.
std::string_view techniqueName(const ResolvedMethod& method, uint32_t role) {
  if (role == gpu::kSampleTechniqueEnv && method.envTechnique) return method.envTechnique->name;
  if (role == gpu::kSampleTechniqueBrdf && method.brdfTechnique) return method.brdfTechnique->name;
  if (role == gpu::kSampleTechniqueProduct) return "product";
  return "none";
}

}  // namespace

std::optional<std::string> unrecordablePixel(const GBuffer& gbuffer, int x, int y) {
  const std::string size = std::to_string(gbuffer.width) + "x" + std::to_string(gbuffer.height);
  if (x < 0 || y < 0 || x >= gbuffer.width || y >= gbuffer.height)
    return "outside the " + size + " image (x in [0, " + std::to_string(gbuffer.width - 1) + "], y in [0, " +
           std::to_string(gbuffer.height - 1) + "])";
  if (gbuffer.pixels[std::size_t(y) * std::size_t(gbuffer.width) + std::size_t(x)].normal.w == 0.0f)
    return "background, not on the object at " + size + "; samples exist only where the object is";
  return std::nullopt;
}

SampleRecorder::SampleRecorder(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                               const ResolvedMethod& method, uint32_t seed)
    : scene_(scene),
      method_(method),
      renderer_(context, compiler, scene, method, seed, IntegratorMode::RecordPixel) {}

void SampleRecorder::start(int x, int y) {
  if (const auto problem = unrecordablePixel(scene_.gbuffer, x, y))
    throw Error("pixel " + std::to_string(x) + "," + std::to_string(y) + ": " + *problem);
  x_ = uint32_t(x);
  y_ = uint32_t(y);
  renderer_.setRecordedPixel(x_, y_);
  passes_ = 0;
  started_ = true;
}

std::vector<RecordedSample> SampleRecorder::runPass(uint32_t samplesPerPass) {
  if (!started_) throw Error("SampleRecorder::runPass before start()");
  renderer_.runPass(samplesPerPass);
  const auto records = renderer_.lastPassRecords();
  std::vector<RecordedSample> samples;
  samples.reserve(records.size());
  for (const gpu::SampleRecord& r : records) {
    RecordedSample s;
    s.index = r.sampleIndex;
    s.pass = passes_;
    s.technique = techniqueName(method_, r.technique);
    s.envDirection = {r.direction.x, r.direction.y, r.direction.z};
    // The kernels turn world directions into the map's frame (lib/pixel_shading.glsl worldToEnv); undo it.
    s.direction = worldToEnv(s.envDirection, -scene_.envRotationDeg);
    s.uv = r.technique == gpu::kSampleTechniqueNone ? glm::dvec2(0.0) : directionToLatLong(s.envDirection);
    s.pdf = r.direction.w;
    s.misWeight = r.weight.w;
    s.weight = {r.weight.x, r.weight.y, r.weight.z};
    s.radiance = {r.radiance.x, r.radiance.y, r.radiance.z};
    s.estimate = {r.estimate.x, r.estimate.y, r.estimate.z};
    s.point = {r.pointX, r.pointY};
    if (r.productColumns > 0) {
      ProductNodeChoice c{r.productNode, r.productColumns, r.productRows, r.productNodeProbability, {}};
      const glm::dvec4 uv(r.productNodeUv.x, r.productNodeUv.y, r.productNodeUv.z, r.productNodeUv.w);
      if (uv.z > uv.x && uv.w > uv.y) c.mapUv = uv;
      s.productNode = c;
    }
    samples.push_back(s);
  }
  ++passes_;
  return samples;
}

glm::dvec3 SampleRecorder::pixelMean() const {
  const auto mean = renderer_.pixelMean(x_, y_);
  return {mean[0], mean[1], mean[2]};
}

}  // namespace iblx
