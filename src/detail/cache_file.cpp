#include "detail/cache_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace inkline {

namespace {
constexpr std::uint64_t kFnvPrime = 1099511628211ull;
}

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kFnvPrime;
    return h;
}

std::uint64_t file_content_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot read the file to hash it for --cache");
    std::uint64_t h = kFnvOffset;
    std::vector<char> buffer(1 << 16);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        h = fnv1a(buffer.data(), std::size_t(in.gcount()), h);
    }
    return h;
}

std::string loader_variant(int subdivide, bool strict) {
    return "subdivide=" + std::to_string(subdivide) + " strict=" + std::to_string(int(strict));
}

std::string cache_file_name(std::uint64_t content_hash, std::uint64_t key, const std::string& extension) {
    char name[40];
    std::snprintf(name, sizeof name, "%016llx-%016llx.", static_cast<unsigned long long>(content_hash),
                  static_cast<unsigned long long>(key));
    return name + extension;
}

void write_cache_file(const std::string& path, const char (&magic)[8], std::uint32_t version, std::uint64_t key,
                      const CacheWriter& payload) {
    CacheWriter w;
    w.bytes.reserve(sizeof magic + sizeof version + sizeof key + payload.bytes.size() + sizeof(std::uint64_t));
    w.bytes.append(magic, sizeof magic);
    w.put(version);
    w.put(key);
    w.bytes += payload.bytes;
    w.put(fnv1a(w.bytes.data(), w.bytes.size()));
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

bool open_cache_file(const std::string& path, const char (&magic)[8], std::uint32_t version, std::uint64_t key,
                     const char* what, CacheReader& r, std::string& problem) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        problem = "cannot be read";
        return false;
    }
    r = CacheReader{std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>())};
    const std::string& bytes = r.bytes;
    std::uint64_t stored_sum = 0;
    if (bytes.size() < sizeof magic + sizeof stored_sum || std::memcmp(bytes.data(), magic, sizeof magic) != 0) {
        problem = std::string("is not ") + what + " file (or is truncated)";
        return false;
    }
    std::memcpy(&stored_sum, bytes.data() + bytes.size() - sizeof stored_sum, sizeof stored_sum);
    if (fnv1a(bytes.data(), bytes.size() - sizeof stored_sum) != stored_sum) {
        problem = "fails its checksum (corrupt or truncated)";
        return false;
    }
    r.at = sizeof magic;
    std::uint32_t stored_version = 0;
    std::uint64_t stored_key = 0;
    r.get(stored_version);
    r.get(stored_key);
    if (!r.ok || stored_version != version || stored_key != key) {
        problem = "is stale (written by another version or for other content or options)";
        return false;
    }
    return true;
}

std::string cache_outcome_text(CacheOutcome outcome, const std::string& path) {
    return outcome == CacheOutcome::Loaded       ? "read from " + path
           : outcome == CacheOutcome::Unwritable ? "built (not cached)"
                                                 : "built, cached as " + path;
}

CacheOutcome read_or_build(const std::string& path, const std::function<bool(std::string& problem)>& read,
                           const std::function<void()>& build, const std::function<void()>& write, std::string& problem) {
    CacheOutcome outcome = CacheOutcome::Built;
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        if (read(problem)) return CacheOutcome::Loaded;
        outcome = CacheOutcome::Rebuilt;
        problem = path + " " + problem + ": rebuilt";
    }
    build();
    try {
        std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
        write();
    } catch (const std::exception& e) {
        outcome = CacheOutcome::Unwritable;
        problem = e.what();
    }
    return outcome;
}

}  // namespace inkline
