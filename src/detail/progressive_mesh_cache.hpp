// The progressive mesh's hierarchy kept on disk (--cache=DIR with --detail-method=pm), so that a
// model's collapse sequence is recorded once: OpenMesh's quadric decimation costs about 45 us a
// collapse (armadillo@2: 20 s of CPU), the file 8 bytes a vertex.
//
// Takes a model's topology, the path of the file it came from and the loader's `variant` (such
// as --subdivide); gives the hierarchy, read from DIR when a file there matches, else built and
// written. A file (detail/cache_file.hpp, extension .pm) is named by the model file's content hash
// and a hash of it with the variant and the format's version, repeated in its header, and ends
// with a checksum: a corrupt, truncated or stale file is rebuilt and rewritten (the caller warns
// once). The hierarchy does not depend on the target, camera or line options.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "detail/cache_file.hpp"
#include "detail/progressive_mesh.hpp"

namespace inkline {

struct CachedHierarchy {
    std::unique_ptr<ProgressiveMesh> pm;  // over the topology given (which must outlive it)
    CacheOutcome outcome = CacheOutcome::Built;
    std::string path;     // the cache file
    std::string problem;  // for Rebuilt and Unwritable: what was wrong, one line
};

// The cache file's name in DIR for this content and loader variant.
std::string pm_cache_name(std::uint64_t content_hash, const std::string& variant);

CachedHierarchy cached_progressive_mesh(const MeshTopology& topology, const std::string& model_path,
                                        const std::string& variant, const std::string& dir,
                                        const ProgressiveMesh::BuildProgress& progress = {});

// Reading and writing one file (the tests corrupt them): false and `problem` when it is not a
// valid file for `key` and a mesh of `vertices` vertices.
bool read_hierarchy_file(const std::string& path, std::uint64_t key, std::size_t vertices,
                         std::vector<std::uint32_t>& removed, std::vector<std::uint32_t>& kept, std::string& problem);
void write_hierarchy_file(const std::string& path, std::uint64_t key, std::size_t vertices, const ProgressiveMesh& pm);

}  // namespace inkline
