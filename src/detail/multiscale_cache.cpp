// The smoothed levels on disk (multiscale_cache.hpp), in a cache file (cache_file.hpp) of magic
// "INKMSL\r\n" whose payload is the MultiscaleLevels fields in declaration order (scalars, then
// each array as u64 count + elements).
#include "detail/multiscale_cache.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "core/clock.hpp"

namespace inkline {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'K', 'M', 'S', 'L', '\r', '\n'};
// Bump when the file layout or the levels' construction changes: older files are then stale.
constexpr std::uint32_t kVersion = 4;

std::uint64_t levels_key(std::uint64_t content_hash, const MultiscaleOptions& o, const std::string& variant) {
    std::uint64_t h = fnv1a_value(kVersion, kFnvOffset);
    h = fnv1a_value(content_hash, h);
    h = fnv1a_value(std::int32_t(o.levels), h);
    for (double x : {o.ratio, o.relax, o.shrink_back, o.spread}) h = fnv1a_value(x, h);
    h = fnv1a_value(std::int32_t(o.fairing), h);
    h = fnv1a_value(std::int32_t(o.sweeps), h);
    h = fnv1a_value(std::int32_t(o.tangential_sweeps), h);
    for (double x : {o.smoothing, o.smoothing_growth, o.thin_guard}) h = fnv1a_value(x, h);
    h = fnv1a_value(std::int32_t(o.smoothing_order), h);
    return fnv1a(variant.data(), variant.size(), h);
}

}  // namespace

std::string multiscale_cache_name(std::uint64_t content_hash, const MultiscaleOptions& options, const std::string& variant) {
    return cache_file_name(content_hash, levels_key(content_hash, options, variant), "levels");
}

void write_levels_file(const std::string& path, std::uint64_t key, const MultiscaleLevels& L) {
    CacheWriter w;
    w.put(std::int32_t(L.levels));
    w.put(L.ratio);
    w.put(L.feature_size);
    w.put(std::uint64_t(L.vertices));
    w.put(std::uint64_t(L.collapses));
    w.put(std::uint64_t(L.base_vertices));
    w.put_array(L.position);
    w.put_array(L.normal_oct);
    w.put_array(L.dir1_angle);
    w.put_array(L.k1);
    w.put_array(L.k2);
    w.put_array(L.dcurv);
    w.put_array(L.valid);
    w.put_array(L.mean_abs_k1);
    w.put_array(L.median_abs_k1);
    w.put(std::uint8_t(L.levels_self_intersect));
    w.put(std::uint64_t(L.note.size()));
    w.bytes += L.note;
    w.put(L.seconds);
    w.put(L.seconds_model);
    write_cache_file(path, kMagic, kVersion, key, w);
}

bool read_levels_file(const std::string& path, std::uint64_t key, std::size_t vertices, MultiscaleLevels& L,
                      std::string& problem) {
    CacheReader r;
    if (!open_cache_file(path, kMagic, kVersion, key, "a levels", r, problem)) return false;
    std::int32_t levels = 0;
    std::uint64_t v = 0, collapses = 0, base = 0;
    r.get(levels);
    r.get(L.ratio);
    r.get(L.feature_size);
    r.get(v);
    r.get(collapses);
    r.get(base);
    if (!r.ok || v != vertices || levels < 1 || levels > 64) {
        problem = "is stale (its vertex count differs from the model's)";
        return false;
    }
    L.levels = levels;
    L.vertices = v;
    L.collapses = collapses;
    L.base_vertices = base;
    const std::size_t stored = std::size_t(levels - 1) * vertices;
    r.get_array(L.position, stored);
    r.get_array(L.normal_oct, stored);
    r.get_array(L.dir1_angle, stored);
    r.get_array(L.k1, stored);
    r.get_array(L.k2, stored);
    r.get_array(L.dcurv, stored);
    r.get_array(L.valid, stored);
    r.get_array(L.mean_abs_k1, std::size_t(levels));
    r.get_array(L.median_abs_k1, std::size_t(levels));
    std::uint8_t pierced = 0;
    std::uint64_t note_size = 0;
    r.get(pierced);
    r.get(note_size);
    if (r.ok && r.bytes.size() - r.at >= note_size) {
        L.note.assign(r.bytes.data() + r.at, note_size);
        r.at += note_size;
    } else {
        r.ok = false;
    }
    r.get(L.seconds);
    r.get(L.seconds_model);
    if (!r.finished()) {
        problem = "has a layout that does not match its header (corrupt)";
        return false;
    }
    L.levels_self_intersect = pierced != 0;
    return true;
}

CachedLevels cached_multiscale_levels(const Model& model, const std::string& model_path, const std::string& variant,
                                      const MultiscaleOptions& options, const std::string& dir) {
    CachedLevels out;
    const std::uint64_t content = file_content_hash(model_path);
    const std::uint64_t key = levels_key(content, options, variant);
    out.path = (std::filesystem::path(dir) / multiscale_cache_name(content, options, variant)).string();
    const auto read = [&](std::string& problem) {
        const auto t0 = std::chrono::steady_clock::now();
        if (!read_levels_file(out.path, key, model.topology().vertex_count(), out.levels, problem)) return false;
        out.levels.seconds = seconds_since(t0);  // (what this run spent on the levels)
        out.levels.seconds_model = 0.0;
        const int total = options.build_steps();
        if (options.progress) options.progress(total, total);
        return true;
    };
    out.outcome = read_or_build(
        out.path, read, [&] { out.levels = build_multiscale_levels(model, options); },
        [&] { write_levels_file(out.path, key, out.levels); }, out.problem);
    return out;
}

}  // namespace inkline
