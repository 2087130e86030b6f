// Detail control: the smoothed levels kept on disk (--cache=DIR), so that a model's pre-process
// runs once. Takes a Model, the path of the file it came from and the options that build its
// levels; gives the levels, read from DIR when a file there matches, else built and written.
//
// A file (detail/cache_file.hpp) is named by the model file's content hash and a hash of everything
// that changes the levels (MultiscaleOptions' shape options, the loader's `variant` such as
// --subdivide, the format's version), and carries both again in its header and a checksum of all
// its bytes: a truncated, corrupt or stale file is detected, rebuilt and rewritten (and the caller
// warns once).
#pragma once

#include <cstdint>
#include <string>

#include "detail/cache_file.hpp"
#include "detail/multiscale.hpp"

namespace inkline {

struct CachedLevels {
    MultiscaleLevels levels;
    CacheOutcome outcome = CacheOutcome::Built;
    std::string path;     // the cache file
    std::string problem;  // for Rebuilt and Unwritable: what was wrong, one line
};

// The cache file's name in DIR for this content and these options.
std::string multiscale_cache_name(std::uint64_t content_hash, const MultiscaleOptions& options, const std::string& variant);

// The levels of `model` (loaded from `model_path` with loader options summed up in `variant`),
// from `dir` when a valid file is there, else built with `options` and written there.
CachedLevels cached_multiscale_levels(const Model& model, const std::string& model_path, const std::string& variant,
                                      const MultiscaleOptions& options, const std::string& dir);

// Reading and writing one file (the tests corrupt them): false and `problem` when it is not a
// valid file for `key`.
bool read_levels_file(const std::string& path, std::uint64_t key, std::size_t vertices, MultiscaleLevels& out,
                      std::string& problem);
void write_levels_file(const std::string& path, std::uint64_t key, const MultiscaleLevels& levels);

}  // namespace inkline
