// Measured files beyond MERL as iblx BRDFs: a UTIA .bin (engine/io/utia.h; shaders/brdf/utia.glsl) with the
// file's colour convention as parameters (prescale, srgb, scale), and an MIT CSAIL .dat
// (engine/io/mit_brdf.h; shaders/brdf/mit.glsl) with a scale, so `--param` and the viewer's sliders change
// how the stored values are read. Both are sampled by brdf-tab (its half-vector tables follow an anisotropic
// lobe's azimuth). An RGL-EPFL .bsdf (engine/sampling/brdf/rgl_sampling.h; shaders/brdf/rgl.glsl) is sampled
// by its own luminance and VNDF warps, technique rgl-vndf. An ALTA data file
// (engine/sampling/brdf/alta_grid.h; shaders/brdf/alta_data.glsl) becomes a grid of its parametrisation,
// sampled by brdf-tab.
//
// materialFileFormats() lists every format read from a file by content (ALTA function files too), in the
// order loadBrdfArgument (engine/scene/scene.h) tries them.
#pragma once

#include "engine/io/alta_data.h"
#include "engine/io/mit_brdf.h"
#include "engine/io/utia.h"
#include "engine/sampling/brdf/rgl_sampling.h"
#include "engine/scene/methods.h"

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace iblx {

// The BRDFs named after their files.
std::shared_ptr<const BrdfInfo> makeUtiaBrdf(UtiaBrdf brdf, const std::filesystem::path& file);
std::shared_ptr<const BrdfInfo> makeMitBrdf(MitBrdf brdf, const std::filesystem::path& file);
std::shared_ptr<const BrdfInfo> makeRglBrdf(const RglTables& tables, const std::filesystem::path& file);

std::shared_ptr<const BrdfInfo> makeAltaDataBrdf(const AltaData& data, const std::filesystem::path& file);

// A format of material files: recognised by its content whatever the file's name, or else by an extension
// (which then reports that format's problems with the file).
struct MaterialFileFormat {
  const char* name;
  std::vector<std::string> extensions;
  bool (*recognise)(const std::filesystem::path&);
  // Whether content recognition applies to files named .brdf or .bparam too (ALTA calls its function files
  // .brdf; the other formats never look like BRDF Explorer's text).
  bool evenWithExplorerNames;
  std::shared_ptr<const BrdfInfo> (*load)(const std::filesystem::path&);
};
std::span<const MaterialFileFormat> materialFileFormats();

// Every kind of material file --brdf reads, for messages and listings, in one phrase: the registry's BRDFs
// read from a file (MERL), materialFileFormats(), and BRDF Explorer's .brdf and .bparam.
std::string materialFileKindsText();

// The extensions of every BRDF file --brdf reads (BRDF Explorer's and MERL's too), for file dialogs and
// messages; and whether a file is one, by its extension or by its content.
std::vector<std::string> brdfFileExtensions();
bool isBrdfFile(const std::filesystem::path& path);

// Whether a BRDF is an RGL-EPFL material (what technique rgl-vndf samples).
bool isRglBrdf(const BrdfInfo& brdf);

// The convention of the parameter values (BrdfInfo::params of makeUtiaBrdf, as resolveParams returns them).
UtiaConvention utiaConvention(const ParamValues& values);

}  // namespace iblx
