// A scene (docs/DESIGN.md §2: object, camera, environment, BRDF) and the method that renders it, as plain
// values (their GPU copies: engine/render/scene_gpu.h).
#pragma once

#include "engine/geometry/gbuffer.h"
#include "engine/io/env_image.h"
#include "engine/core/setting.h"
#include "engine/io/merl.h"
#include "engine/scene/methods.h"

#include <array>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

struct SceneSpec {
  std::filesystem::path envPath;  // empty: the default map in assets/
  double envRotationDeg = 0.0;
  std::string brdf = "ggx";
  std::vector<std::pair<std::string, std::string>> params;
  std::string object = "sphere";  // sphere | plane | teapot | an .obj file (engine/geometry/gbuffer.h)
  CameraSpec camera;              // --orbit, --zoom
  int width = 256, height = 256;
};

// Empty / unset fields take their defaults; a field set for a method that does not use it is reported.
inline constexpr int kMaxRisCandidates = 64;  // ris: the candidate loop unrolls

struct MethodSpec {
  std::string method = "mis";
  std::string envSampler;   // mis: default env-cdf
  std::string brdfSampler;  // brdf, mis: default the BRDF's best
  // The default of render, view and samples, measured: docs/RESULTS.md, "The default".
  std::string sequence = "sobol";
  // mis: given, one-sample MIS with this fraction of samples drawn by the env technique; unset, two-sample
  // MIS (one direction from each technique per sample).
  std::optional<double> misEnvFraction;
  std::string misHeuristic;          // mis: balance (default) | power
  std::optional<int> risCandidates;  // ris: default 8
  bool misCompensation = false;      // mis: the env technique samples max(p - mean(p), 0)
};

struct MerlThetaHData;
struct MerlTableData;

// A measured material read by `--brdf FILE.binary`, with its sampling tables built on first use and kept, so
// renderers of several methods on one scene (bench, converge, the viewer) build them once.
class MeasuredBrdf {
 public:
  explicit MeasuredBrdf(MerlBrdf brdf);
  ~MeasuredBrdf();
  const MerlBrdf brdf;

  const MerlThetaHData& thetaHTable() const;
  const MerlTableData& sampleTable() const;
  // Angular width of the specular lobe, estimated from the theta_h profile (0 for a flat one).
  double lobeWidth() const;

 private:
  mutable std::once_flag thetaHOnce_, tableOnce_;
  mutable std::unique_ptr<MerlThetaHData> thetaH_;
  mutable std::unique_ptr<MerlTableData> table_;
};

// A --brdf argument resolved: a registry BRDF, or one made from a .brdf file (engine/scene/analytic_brdf.h),
// with the material of a MERL file. A .bparam file resolves to the BRDF it names, with its saved values as
// the parameters' defaults (BRDF Explorer copies them by name) and its own file name as the BRDF's name.
struct LoadedBrdf {
  std::shared_ptr<const BrdfInfo> info;
  std::shared_ptr<const MeasuredBrdf> measured;  // set for the MERL BRDF
  std::filesystem::path file;                    // the .brdf / .binary read (empty for a built-in)
};
// Reads the files a --brdf argument names. Throws iblx::Error with the file (and line) and the problem.
LoadedBrdf loadBrdfArgument(const std::string& nameOrPath);

struct Scene {
  EnvImage env;
  double envRotationDeg = 0.0;
  std::shared_ptr<const BrdfInfo> brdf;
  ParamValues params;
  std::shared_ptr<const MeasuredBrdf> measured;  // set for the MERL BRDF
  std::filesystem::path brdfFile;                // the BRDF's file, for saving a .bparam (empty: a built-in)
  GBuffer gbuffer;
};

// The method with every name resolved and checked against the scene's BRDF.
struct ResolvedMethod {
  const MethodInfo* method = nullptr;
  const EnvTechniqueInfo* envTechnique = nullptr;    // null when the strategy needs none
  const BrdfTechniqueInfo* brdfTechnique = nullptr;  // null when the strategy needs none
  const SequenceInfo* sequence = nullptr;
  bool misOneSample = false;    // mis: one-sample MIS (a MIS split given) instead of two-sample MIS
  float misEnvFraction = 0.5f;  // one-sample MIS: the env technique's share of samples
  bool misPower = false;
  uint32_t risCandidates = 8;
  bool misCompensation = false;
  // Settings the spec gave that this method does not use (e.g. an env technique for `brdf`): the front end
  // says so, in its own words.
  std::vector<Setting> ignoredSettings;
  std::string label() const;           // e.g. "mis(env-cdf+ggx-vndf, balance)/sobol"
  std::string techniqueLabel() const;  // the same without the sequence
  // Directions each sample draws and records (lib/sample_record.glsl): 2 for two-sample MIS, else 1.
  uint32_t drawsPerSample() const;
};

std::filesystem::path defaultEnvPath();
Scene makeScene(EnvImage env, const SceneSpec& spec);  // reads the --brdf file, if any
// The same with the --brdf argument already loaded.
Scene makeScene(EnvImage env, const SceneSpec& spec, LoadedBrdf brdf);
Scene loadScene(const SceneSpec& spec);                   // reads spec.envPath (or the default map)
Scene loadScene(const SceneSpec& spec, LoadedBrdf brdf);  // the same with the --brdf argument already loaded
ResolvedMethod resolveMethod(const MethodSpec& spec, const BrdfInfo& brdf);

// The methods of the registry that apply to `brdf`, with their default options: what the measuring
// commands run when no method is named.
std::vector<MethodSpec> defaultMethodSpecs(const BrdfInfo& brdf);

// A method with its options in one word, as the measuring commands take it: NAME[:OPTION]..., where an option
// is an env technique (mis, ris), a BRDF technique (brdf, mis), balance | power, compensated, M=N (ris
// candidates) or split=F (mis). E.g. "mis:env-hier:power", "ris:env-hier:M=32", "brdf:brdf-tab".
MethodSpec parseMethodVariant(const std::string& text);

}  // namespace iblx
