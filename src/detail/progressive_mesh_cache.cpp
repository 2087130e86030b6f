// The hierarchy on disk (progressive_mesh_cache.hpp), in a cache file (cache_file.hpp) of magic
// "INKPMH\r\n" whose payload is the mesh's vertex count, then the removed and kept vertices of each
// collapse (u64 count + u32 elements each).
#include "detail/progressive_mesh_cache.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "core/clock.hpp"

namespace inkline {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'K', 'P', 'M', 'H', '\r', '\n'};
// Bump when the file layout or the hierarchy's construction (ProgressiveMesh::build) changes.
constexpr std::uint32_t kVersion = 1;

std::uint64_t hierarchy_key(std::uint64_t content_hash, const std::string& variant) {
    std::uint64_t h = fnv1a_value(kVersion, kFnvOffset);
    h = fnv1a_value(content_hash, h);
    return fnv1a(variant.data(), variant.size(), h);
}

}  // namespace

std::string pm_cache_name(std::uint64_t content_hash, const std::string& variant) {
    return cache_file_name(content_hash, hierarchy_key(content_hash, variant), "pm");
}

void write_hierarchy_file(const std::string& path, std::uint64_t key, std::size_t vertices, const ProgressiveMesh& pm) {
    CacheWriter w;
    w.put(std::uint64_t(vertices));
    w.put_array(pm.removed_vertex());
    w.put_array(pm.kept_vertex());
    write_cache_file(path, kMagic, kVersion, key, w);
}

bool read_hierarchy_file(const std::string& path, std::uint64_t key, std::size_t vertices,
                         std::vector<std::uint32_t>& removed, std::vector<std::uint32_t>& kept, std::string& problem) {
    CacheReader r;
    if (!open_cache_file(path, kMagic, kVersion, key, "a progressive mesh", r, problem)) return false;
    std::uint64_t v = 0, collapses = 0;
    r.get(v);
    if (!r.ok || v != vertices) {
        problem = "is stale (its vertex count differs from the model's)";
        return false;
    }
    const std::size_t removed_at = r.at;
    r.get(collapses);  // (the first list's count, read again by get_array: the second must match it)
    r.at = removed_at;
    r.get_array(removed, std::size_t(collapses));
    r.get_array(kept, std::size_t(collapses));
    const auto outside = [v](std::uint32_t x) { return x >= v; };
    if (!r.finished() || collapses >= std::max<std::uint64_t>(v, 1) || std::any_of(removed.begin(), removed.end(), outside) ||
        std::any_of(kept.begin(), kept.end(), outside)) {
        problem = "has a layout that does not match its header (corrupt)";
        return false;
    }
    return true;
}

CachedHierarchy cached_progressive_mesh(const MeshTopology& topology, const std::string& model_path,
                                        const std::string& variant, const std::string& dir,
                                        const ProgressiveMesh::BuildProgress& progress) {
    CachedHierarchy out;
    const std::uint64_t content = file_content_hash(model_path);
    const std::uint64_t key = hierarchy_key(content, variant);
    out.path = (std::filesystem::path(dir) / pm_cache_name(content, variant)).string();
    const auto read = [&](std::string& problem) {
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::uint32_t> removed, kept;
        if (!read_hierarchy_file(out.path, key, topology.vertex_count(), removed, kept, problem)) return false;
        out.pm = std::make_unique<ProgressiveMesh>(topology, std::move(removed), std::move(kept), seconds_since(t0));
        return true;
    };
    out.outcome = read_or_build(
        out.path, read, [&] { out.pm = std::make_unique<ProgressiveMesh>(topology, progress); },
        [&] { write_hierarchy_file(out.path, key, topology.vertex_count(), *out.pm); }, out.problem);
    return out;
}

}  // namespace inkline
