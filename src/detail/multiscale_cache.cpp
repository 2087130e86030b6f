// The smoothed levels on disk (multiscale_cache.hpp). File layout, little-endian as written by
// this machine's std::fwrite (a cache is local to its machine):
//   magic "INKMSL\r\n", u32 version, u64 key, then the MultiscaleLevels fields in declaration
//   order (scalars, then each array as u64 count + elements), then u64 FNV-1a of all bytes before.
#include "detail/multiscale_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

#include "core/clock.hpp"

namespace inkline {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'K', 'M', 'S', 'L', '\r', '\n'};
// Bump when the file layout or the levels' construction changes: older files are then stale.
constexpr std::uint32_t kVersion = 4;
constexpr std::uint64_t kFnvOffset = 1469598103934665603ull, kFnvPrime = 1099511628211ull;

std::uint64_t fnv(const void* data, std::size_t n, std::uint64_t h = kFnvOffset) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kFnvPrime;
    return h;
}

template <class T>
std::uint64_t fnv_value(const T& v, std::uint64_t h) { return fnv(&v, sizeof v, h); }

std::uint64_t levels_key(std::uint64_t content_hash, const MultiscaleOptions& o, const std::string& variant) {
    std::uint64_t h = fnv_value(kVersion, kFnvOffset);
    h = fnv_value(content_hash, h);
    h = fnv_value(std::int32_t(o.levels), h);
    for (double x : {o.ratio, o.relax, o.shrink_back, o.spread}) h = fnv_value(x, h);
    h = fnv_value(std::int32_t(o.fairing), h);
    h = fnv_value(std::int32_t(o.sweeps), h);
    h = fnv_value(std::int32_t(o.tangential_sweeps), h);
    for (double x : {o.smoothing, o.smoothing_growth, o.thin_guard}) h = fnv_value(x, h);
    h = fnv_value(std::int32_t(o.smoothing_order), h);
    return fnv(variant.data(), variant.size(), h);
}

// Appends raw bytes to a buffer (the whole file is built in memory, then checksummed).
struct Writer {
    std::string bytes;
    template <class T>
    void put(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
    template <class T>
    void put_array(const std::vector<T>& v) {
        put(std::uint64_t(v.size()));
        bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};

struct Reader {
    const std::string& bytes;
    std::size_t at = 0;
    bool ok = true;
    template <class T>
    void get(T& v) {
        if (!ok || bytes.size() - at < sizeof v) { ok = false; return; }
        std::memcpy(&v, bytes.data() + at, sizeof v);
        at += sizeof v;
    }
    template <class T>
    void get_array(std::vector<T>& v, std::size_t expected) {
        std::uint64_t n = 0;
        get(n);
        if (!ok || n != expected || (bytes.size() - at) / sizeof(T) < n) { ok = false; return; }
        v.resize(n);
        std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
        at += n * sizeof(T);
    }
};

}  // namespace

std::uint64_t file_content_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot read the file to hash it for --cache");
    std::uint64_t h = kFnvOffset;
    std::vector<char> buffer(1 << 16);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        h = fnv(buffer.data(), std::size_t(in.gcount()), h);
    }
    return h;
}

std::string multiscale_cache_name(std::uint64_t content_hash, const MultiscaleOptions& options, const std::string& variant) {
    char name[64];
    std::snprintf(name, sizeof name, "%016llx-%016llx.levels", static_cast<unsigned long long>(content_hash),
                  static_cast<unsigned long long>(levels_key(content_hash, options, variant)));
    return name;
}

void write_levels_file(const std::string& path, std::uint64_t key, const MultiscaleLevels& L) {
    Writer w;
    w.bytes.append(kMagic, sizeof kMagic);
    w.put(kVersion);
    w.put(key);
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
    w.put(fnv(w.bytes.data(), w.bytes.size()));
    // A temporary name in the same folder, then rename: readers see the old file or the whole new one.
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(w.bytes.data(), std::streamsize(w.bytes.size()));
        out.close();
        if (!out) {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            throw std::runtime_error(tmp + ": cannot write the cache file");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error(path + ": cannot rename the cache file into place");
    }
}

bool read_levels_file(const std::string& path, std::uint64_t key, std::size_t vertices, MultiscaleLevels& L,
                      std::string& problem) {
    std::ifstream in(path, std::ios::binary);
    if (!in) { problem = "cannot be read"; return false; }
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < sizeof kMagic + sizeof(std::uint64_t) || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
        problem = "is not a levels file (or is truncated)";
        return false;
    }
    std::uint64_t stored_sum;
    std::memcpy(&stored_sum, bytes.data() + bytes.size() - sizeof stored_sum, sizeof stored_sum);
    if (fnv(bytes.data(), bytes.size() - sizeof stored_sum) != stored_sum) {
        problem = "fails its checksum (corrupt or truncated)";
        return false;
    }
    Reader r{bytes, sizeof kMagic};
    std::uint32_t version = 0;
    std::uint64_t stored_key = 0;
    r.get(version);
    r.get(stored_key);
    if (version != kVersion || stored_key != key) {
        problem = "is stale (written by another version or for other content or options)";
        return false;
    }
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
    if (r.ok && bytes.size() - r.at >= note_size) {
        L.note.assign(bytes.data() + r.at, note_size);
        r.at += note_size;
    } else {
        r.ok = false;
    }
    r.get(L.seconds);
    r.get(L.seconds_model);
    if (!r.ok || r.at + sizeof stored_sum != bytes.size()) {
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
    std::error_code ec;
    if (std::filesystem::exists(out.path, ec)) {
        const auto t0 = std::chrono::steady_clock::now();
        if (read_levels_file(out.path, key, model.topology().vertex_count(), out.levels, out.problem)) {
            out.outcome = CacheOutcome::Loaded;
            out.levels.seconds = seconds_since(t0);  // (what this run spent on the levels)
            out.levels.seconds_model = 0.0;
            const int total = 2 + std::max(options.levels - 1, 0);  // (as build_multiscale_levels counts)
            if (options.progress) options.progress(total, total);
            return out;
        }
        out.outcome = CacheOutcome::Rebuilt;
        out.problem = out.path + " " + out.problem + ": rebuilt";
    }
    out.levels = build_multiscale_levels(model, options);
    try {
        std::filesystem::create_directories(dir, ec);
        write_levels_file(out.path, key, out.levels);
    } catch (const std::exception& e) {
        out.outcome = CacheOutcome::Unwritable;
        out.problem = e.what();
    }
    return out;
}

}  // namespace inkline
