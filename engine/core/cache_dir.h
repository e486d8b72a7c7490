// The on-disk cache shared by every cached artefact (SPIR-V, ground-truth images): where it lives and how
// entries are named.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace iblx {

// $IBLX_CACHE_DIR, else $XDG_CACHE_HOME/iblx, else ~/.cache/iblx; empty when none of them is set.
std::filesystem::path defaultCacheDir();

// A cache key as 16 lowercase hex digits (file names).
std::string hexKey(std::uint64_t key);

}  // namespace iblx
