// iblx_libfuzzer: the fuzz targets of tests/fuzz/fuzz_target.h under libFuzzer, for long coverage-guided
// runs (tools/fuzz.sh). One executable serves every target; $IBLX_FUZZ_TARGET names the one to run:
//
//   IBLX_FUZZ_TARGET=exr build-fuzz/iblx_libfuzzer -max_total_time=60 corpus/exr
//
// iblx::Error is the expected outcome of bad input; anything else escaping reaches std::terminate, which
// libFuzzer reports as a crash with the input saved.
#include "tests/fuzz/fuzz_target.h"

#include "engine/core/error.h"
#include "engine/core/log.h"

#include <cstdio>
#include <cstdlib>

namespace {

const iblx::fuzz::FuzzTarget* gTarget = nullptr;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* name = std::getenv("IBLX_FUZZ_TARGET");
  gTarget = name ? iblx::fuzz::findFuzzTarget(name) : nullptr;
  if (gTarget == nullptr) {
    std::fprintf(stderr, "iblx_libfuzzer: set IBLX_FUZZ_TARGET to one of:");
    for (const auto& t : iblx::fuzz::fuzzTargets()) std::fprintf(stderr, " %s", std::string(t.name).c_str());
    std::fprintf(stderr, "\n");
    std::exit(2);
  }
  // Readers warn about what they repair: expected here, and far too many lines.
  iblx::setWarningSink([](const std::string&) {});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    gTarget->run({data, size});
  } catch (const iblx::Error&) {
    // The reader refused the input, as it should.
  }
  return 0;
}
