// Assembles a kernel from one part per role (docs/DESIGN.md §2) as the text of a prelude:
// #version, the interfaces, the techniques' definitions, the binding of every table the kernel's builders
// provide, the BRDF parameter block, the kernel and one #include per chosen part. CPU only: compiling the
// prelude is engine/render/kernel_assembly.h's.
#pragma once

#include "engine/sampling/product/env_hier_product.h"
#include "engine/sampling/technique_data.h"
#include "engine/scene/scene.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

// A table a kernel's parts may read, where it is bound: a part declares it IBLX_TABLE(name, words)
// (shaders/lib/table.glsl) and the prelude defines IBLX_SET_<name> and IBLX_BINDING_<name>_W<words>.
struct KernelTable {
  std::string name;
  std::uint32_t words = 1;
  std::uint32_t set = 0, binding = 0;
  std::string owner;  // who provides it, for messages: e.g. "env technique env-cdf"
};

// The descriptor sets of every kernel that renders a scene (docs/DESIGN.md §2): 0 the frame, 1 the kernel's
// own I/O, 2 the env technique's tables, 3 the BRDF (its parameter block at binding 0, the BRDF's own tables
// from binding kBrdfDataBinding on, then the BRDF technique's).
inline constexpr std::uint32_t kFrameSet = 0, kEnvTechniqueSet = 2, kBrdfSet = 3;
inline constexpr std::uint32_t kBrdfDataBinding = 1;

// The frame's tables (shaders/lib/frame_resources.glsl): the environment's radiance in up to four chunks and
// its row table. Every prelude binds them.
std::vector<KernelTable> frameTables();

struct KernelParts {
  std::string kernel;                                        // entry point, e.g. "integrate.comp"
  std::vector<std::string> parts;                            // one per role in use
  std::string brdfParamBlock;                                // paramBlockGlsl() of the scene's BRDF
  std::vector<std::pair<std::string, std::string>> defines;  // from the techniques' data and the strategy
  std::vector<KernelTable> tables;                           // beyond frameTables()
  // Generated parts (path, text) the compiler must know, e.g. a .brdf file's (BrdfInfo::evalSource).
  std::vector<std::pair<std::string, std::string>> sources;

  // Binds `data`'s tables to `set` from `firstBinding` on, in order, and takes its definitions. Returns the
  // binding after the last. Throws iblx::Error when a table name is already bound.
  std::uint32_t bindTables(std::uint32_t set, std::uint32_t firstBinding, const TechniqueData& data,
                           const std::string& owner);
};

// The prelude's text. Throws iblx::Error when two tables share a name.
std::string assemblePrelude(const KernelParts& parts);

// When glslang rejected a prelude because a part declares a table the kernel does not bind (or binds at
// another element width), the message a user can act on: the part's file and line, the table, its width
// and which tables the kernel does bind. Empty when `glslangMessage` is about something else.
std::string explainMissingTable(const KernelParts& parts, const std::string& glslangMessage);

// The parts of every kernel that evaluates `brdf`: its parameter block, its own tables (set 3 from
// kBrdfDataBinding on), for a generated BRDF that part's source, and the GLSL parts in include order:
// `parts`, which must list the BRDF's part among the others, or the BRDF's part alone when it is empty.
KernelParts brdfKernelParts(std::string kernel, const BrdfInfo& brdf, const TechniqueData& brdfData,
                            std::vector<std::string> parts = {});

// What the integrator kernel does: add samples to every pixel; integrate one pixel through the same code
// and store every sample's record (IBLX_RECORD_SAMPLES, shaders/lib/sample_record.glsl) in an extra set-0
// buffer at binding kSampleRecordBinding; or, for a product strategy whose tables are kept in buffers, only
// build and store every object pixel's table (PRODUCT_TABLE_BUILD), dispatched before the accumulation's
// first Image dispatch, so that the Image kernel loads tables and holds no code that builds them.
enum class IntegratorMode { Image, RecordPixel, ProductTables };
inline constexpr uint32_t kSampleRecordBinding = 8;
// Image and ProductTables modes of a product strategy, when the image's tables fit kProductTableMaxChunks
// buffers (engine/render/renderer.cpp): the per-pixel product tables, kProductTableStride 32-bit words per
// pixel, kept across the dispatches of an accumulation in set-0 buffers from this binding on, each holding
// the tables of pixelsPerChunk consecutive pixels (row-major), as the radiance is chunked (RecordPixel mode
// puts its records at this binding and rebuilds its one pixel's table in private memory).
inline constexpr uint32_t kProductTableBinding = 8;
inline constexpr uint32_t kProductTableStride = kEnvProductMaxTableWords;  // every product layout's table
inline constexpr uint32_t kProductTableMaxChunks = 4;
struct ProductTableChunks {
  uint32_t chunks = 0;  // 0: no buffers, each dispatch rebuilds the tables in private memory
  uint32_t pixelsPerChunk = 0;
};

// How the environment's radiance is split over the frame's radiance tables (engine/render/scene_gpu.h): the
// definitions every kernel that includes frame_resources.glsl gets.
struct EnvChunking {
  std::size_t chunks = 1;
  std::size_t texelsPerChunk = 0;
  std::vector<std::pair<std::string, std::string>> defines() const;
};

// The integrator for a scene and method, and the reference kernel for a scene.
KernelParts integratorParts(const Scene& scene, const TechniqueData& brdfData, const EnvChunking& chunking,
                            const ResolvedMethod& method, const TechniqueData& envData,
                            const TechniqueData& brdfTechniqueData,
                            IntegratorMode mode = IntegratorMode::Image,
                            ProductTableChunks productTables = {});
KernelParts referenceParts(const Scene& scene, const TechniqueData& brdfData, const EnvChunking& chunking);

}  // namespace iblx
