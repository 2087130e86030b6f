// Detail control's files on disk (--cache=DIR): what the multi-scale levels' and the progressive
// mesh's caches share. Takes a kind's magic, format version, key and payload; gives a file that
// carries them with a checksum of all its bytes, written to a temporary name and renamed (a reader
// never sees half a file), and reads one back only when magic, checksum, version and key all match.
// A cache is local to its machine: numbers are written as this machine holds them.
//
// Layout: 8 magic bytes, u32 version, u64 key, the payload, u64 FNV-1a of all the bytes before.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace inkline {

enum class CacheOutcome {
    Built,     // no file yet: built and written
    Loaded,    // read from the file
    Rebuilt,   // the file was unreadable, corrupt, truncated or stale: built and rewritten
    Unwritable // built; DIR could not be written (the result is still returned)
};

// 64-bit FNV-1a, continued from `h`.
constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;
std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnvOffset);
template <class T>
std::uint64_t fnv1a_value(const T& v, std::uint64_t h) { return fnv1a(&v, sizeof v, h); }

// FNV-1a of a file's bytes. Throws std::runtime_error naming the file when it cannot be read.
std::uint64_t file_content_hash(const std::string& path);

// The loader's options that change the mesh a model file gives (part of every key).
std::string loader_variant(int subdivide, bool strict);

// "CONTENT-KEY.EXTENSION", both hashes in hexadecimal.
std::string cache_file_name(std::uint64_t content_hash, std::uint64_t key, const std::string& extension);

// A payload built in memory, then checksummed as a whole.
struct CacheWriter {
    std::string bytes;
    template <class T>
    void put(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
    template <class T>
    void put_array(const std::vector<T>& v) {
        put(std::uint64_t(v.size()));
        bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};

// Reads a payload in the order it was written; `ok` turns false at the first read past the end or
// an array whose count is not the one expected.
struct CacheReader {
    std::string bytes;
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
    // True when every payload byte was read (the checksum after them is not the payload's).
    bool finished() const { return ok && at + sizeof(std::uint64_t) == bytes.size(); }
};

// Writes magic, version, key, the payload and the checksum to `path` through a temporary file in
// the same folder. Throws std::runtime_error naming the file when it cannot be written or renamed.
void write_cache_file(const std::string& path, const char (&magic)[8], std::uint32_t version, std::uint64_t key,
                      const CacheWriter& payload);

// Opens `path` and checks it: false with `problem` (one phrase: "fails its checksum (corrupt or
// truncated)", "is stale (...)", ...) when it is not a valid `what` file of this version and key;
// else true with `reader` at the payload's start.
bool open_cache_file(const std::string& path, const char (&magic)[8], std::uint32_t version, std::uint64_t key,
                     const char* what, CacheReader& reader, std::string& problem);

// For a report: "read from PATH", "built, cached as PATH" or "built (not cached)".
std::string cache_outcome_text(CacheOutcome outcome, const std::string& path);

// The usual round: when `path` exists, `read` it (true: Loaded; false: its problem, then Rebuilt);
// otherwise, or after a bad file, `build` and `write` (a failed write: Unwritable, its message in
// `problem`). For Rebuilt, `problem` is "PATH PROBLEM: rebuilt".
CacheOutcome read_or_build(const std::string& path, const std::function<bool(std::string& problem)>& read,
                           const std::function<void()>& build, const std::function<void()>& write, std::string& problem);

}  // namespace inkline
