#include "model/mesh_io.hpp"
#include "model/reorder.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <string_view>
#include <unordered_map>
#include <unordered_set>


#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "core/error.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <numeric>

namespace inkline {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
Kernel::Point_3 cgal_point(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot + 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}


// Vertex positions and raw polygons (0-based indices, unchecked) as read from a file. The
// polygons' corners lie one after another in one array (no allocation per face).
struct Soup {
    std::vector<glm::dvec3> positions;
    std::vector<std::int64_t> corners;
    std::vector<std::size_t> polygon_end;  // per polygon, where its corners end in `corners`
    // Instead of the polygons, when a reader knows every one is a triangle whose corners are
    // vertices of the file (checked): the triangles as they are, 12 bytes a face rather than 32.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    LoadProgressReporter* progress = nullptr;  // the text readers report how far they are
    std::size_t polygon_count() const { return polygon_end.size(); }
    void end_polygon() { polygon_end.push_back(corners.size()); }
};

// ' ', '\t', '\n', '\v', '\f', '\r': std::isspace in the "C" locale, without a call per character.
inline bool is_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

// The text readers below are strict: OpenMesh's ASCII readers do not report malformed input
// (a failed number leaves the stream failed and later indices uninitialized, NaN/inf coordinates
// and truncated files come out as unrelated errors or silently corrupted meshes, OBJ faces with
// repeated or unparsable indices are dropped), so OFF, OBJ, ASCII PLY and STL are parsed here
// with line numbers in every message, and so are binary OFF and PLY (see read_ply_binary).
class Lines {
public:
    Lines(const std::string& text, bool hash_comments, LoadProgressReporter* progress = nullptr)
        : text_(text), comments_(hash_comments), progress_(progress) {}
    // Next line with at least one token (comments removed); false at the end of the text.
    bool next(std::vector<std::string_view>& tokens) {
        std::string_view line;
        if (!next_line(line)) return false;
        split(line, tokens);
        return true;
    }
    // The same line as next() without splitting it: comments removed, at least one token.
    bool next_line(std::string_view& line) {
        const char* const text = text_.data();
        while (pos_ < text_.size()) {
            const void* nl = std::memchr(text + pos_, '\n', text_.size() - pos_);
            const std::size_t end = nl ? std::size_t(static_cast<const char*>(nl) - text) : text_.size();
            line = std::string_view(text + pos_, end - pos_);
            pos_ = end + 1;
            if ((++line_ & 0xffff) == 0 && progress_) progress_->bytes(pos_, 0.0, kProgressParsed);
            if (comments_)
                if (const void* hash = std::memchr(line.data(), '#', line.size()))
                    line = line.substr(0, std::size_t(static_cast<const char*>(hash) - line.data()));
            for (char c : line)
                if (!is_space(c)) return true;
        }
        return false;
    }
    std::size_t line() const { return line_; }
    std::string at() const { return "line " + std::to_string(line_) + ": "; }

    static void split(std::string_view line, std::vector<std::string_view>& tokens) {
        tokens.clear();
        std::size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && is_space(line[i])) ++i;
            std::size_t j = i;
            while (j < line.size() && !is_space(line[j])) ++j;
            if (j > i) tokens.push_back(line.substr(i, j - i));
            i = j;
        }
    }

private:
    const std::string& text_;
    bool comments_;
    LoadProgressReporter* progress_;
    std::size_t pos_ = 0, line_ = 0;
};

// A whole token as a double, as strtod reads it: nan and inf are accepted (validation refuses them
// with its own message) and out-of-range values become infinite (or zero). std::from_chars
// (libstdc++ 12: the fast_float algorithm, correctly rounded like glibc's strtod, so the same
// doubles) reads the plain decimal numbers of nearly every file; strtod takes what it leaves: a
// leading '+', hexadecimal floats, values out of range.
bool parse_double(std::string_view tok, double& out) {
    if (tok.empty()) return false;
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    if (r.ec == std::errc() && r.ptr == tok.data() + tok.size()) return true;
    const std::string copy(tok);
    char* end = nullptr;
    out = std::strtod(copy.c_str(), &end);
    return end == copy.c_str() + copy.size();
}

bool parse_int(std::string_view tok, std::int64_t& out) {
    if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

// Reads a line's whitespace-separated numbers in turn, as parse_double and parse_int read its
// tokens, without making the tokens (most of a text file's time went to splitting its lines).
// next() is false, deciding nothing, where the tokenized path must look: no number left, or a
// token that std::from_chars does not read whole (a leading '+', hexadecimal, out of range, not a
// number); the caller then reads the line through Lines::split, which gives the same numbers or
// the error.
class NumberCursor {
public:
    explicit NumberCursor(std::string_view line) : p_(line.data()), end_(line.data() + line.size()) {}
    bool next(double& value) {
        if (!skip_space()) return false;
        return ended(std::from_chars(p_, end_, value));
    }
    // Decimal digits with an optional '-', as std::from_chars reads them; up to 18 digits here
    // (no overflow possible), more through from_chars itself.
    bool next(std::int64_t& value) {
        if (!skip_space()) return false;
        const char* q = p_;
        const bool negative = *q == '-';
        q += negative;
        std::int64_t v = 0;
        const char* const digits = q;
        while (q < end_ && q - digits < 18 && unsigned(*q - '0') < 10) v = 10 * v + (*q++ - '0');
        if (q == digits || (q < end_ && unsigned(*q - '0') < 10)) return ended(std::from_chars(p_, end_, value));
        value = negative ? -v : v;
        return ended({q, std::errc()});
    }

private:
    bool skip_space() {
        while (p_ < end_ && is_space(*p_)) ++p_;
        return p_ < end_;
    }
    // A number read whole: it ends the line or a token.
    bool ended(std::from_chars_result r) {
        if (r.ec != std::errc() || (r.ptr != end_ && !is_space(*r.ptr))) return false;
        p_ = r.ptr;
        return true;
    }

    const char* p_;
    const char* end_;
};

std::string in_quotes(std::string_view tok) { return "'" + std::string(tok.substr(0, 40)) + "'"; }

std::string lower(std::string_view s) {
    std::string r(s);
    std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return std::tolower(c); });
    return r;
}

// An OFF face line "n i0 .. i(n-1) [colour]" read without splitting it (NumberCursor); false,
// with nothing added, where read_off must look at its tokens.
bool read_polygon(std::string_view line, Soup& soup) {
    NumberCursor numbers(line);
    std::int64_t n = 0;
    if (!numbers.next(n) || n < 0) return false;
    const std::size_t before = soup.corners.size();
    for (std::int64_t j = 0; j < n; ++j) {
        std::int64_t v = 0;
        if (!numbers.next(v)) {
            soup.corners.resize(before);
            return false;
        }
        soup.corners.push_back(v);
    }
    soup.end_polygon();
    return true;
}

// OFF (Geomview): [ST][C][N][4][n]OFF header, optional dimension, counts, one vertex per line
// (further values on the line: normals, colours, texture coordinates), one face per line
// ("n i0 .. i(n-1)" then an optional colour).
void read_off(const std::string& text, const std::string& path, Soup& soup) {
    Lines lines(text, true, soup.progress);
    std::vector<std::string_view> tok;
    if (!lines.next(tok)) throw Error(path, "no OFF header");
    const std::string key(tok[0]);
    const auto off_at = key.rfind("OFF");
    if (off_at == std::string::npos || off_at + 3 != key.size())
        throw Error(path, lines.at() + "expected an OFF header, found " + in_quotes(tok[0]));
    const std::string prefix = key.substr(0, off_at);
    if (prefix.find_first_not_of("STCN4n") != std::string::npos)
        throw Error(path, lines.at() + "expected an OFF header, found " + in_quotes(tok[0]));
    const bool homogeneous = prefix.find('4') != std::string::npos;
    std::size_t k = 1;
    auto need = [&](const char* what) {
        while (k >= tok.size()) {
            if (!lines.next(tok)) throw Error(path, std::string("file ends before the ") + what + " (truncated)");
            k = 0;
        }
        return tok[k++];
    };
    std::int64_t dim = 3;
    if (prefix.find('n') != std::string::npos) {
        const auto t = need("vertex dimension");
        if (!parse_int(t, dim) || dim < 1 || dim > 16)
            throw Error(path, lines.at() + "bad vertex dimension " + in_quotes(t));
    }
    if (homogeneous) ++dim;
    std::int64_t nv = 0, nf = 0;
    {
        const auto t = need("vertex count");
        if (!parse_int(t, nv) || nv < 0) throw Error(path, lines.at() + "bad vertex count " + in_quotes(t));
        const auto u = need("face count");
        if (!parse_int(u, nf) || nf < 0) throw Error(path, lines.at() + "bad face count " + in_quotes(u));
        // The edge count, if present, is not used.
    }
    soup.positions.reserve(std::size_t(std::min<std::int64_t>(nv, std::int64_t(text.size() / 6 + 1))));
    const std::size_t faces = std::size_t(std::min<std::int64_t>(nf, std::int64_t(text.size() / 8 + 1)));
    soup.polygon_end.reserve(faces);
    soup.corners.reserve(3 * faces);
    std::string_view line;
    for (std::int64_t i = 0; i < nv; ++i) {
        if (!lines.next_line(line))
            throw Error(path, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
                                  " vertices (truncated)");
        if (!homogeneous && dim == 3) {  // nearly every file: "x y z" and maybe more
            NumberCursor numbers(line);
            double x, y, z;
            if (numbers.next(x) && numbers.next(y) && numbers.next(z)) {
                soup.positions.emplace_back(x, y, z);
                continue;
            }
        }
        Lines::split(line, tok);
        if (std::int64_t(tok.size()) < dim)
            throw Error(path, lines.at() + "vertex " + std::to_string(i) + " has " + std::to_string(tok.size()) +
                                  " coordinates, expected " + std::to_string(dim));
        double c[4] = {0.0, 0.0, 0.0, 1.0};
        for (std::int64_t j = 0; j < dim; ++j) {
            double x;
            if (!parse_double(tok[j], x))
                throw Error(path, lines.at() + "vertex " + std::to_string(i) + ": " + in_quotes(tok[j]) +
                                      " is not a number");
            if (j < 3) c[j] = x;
            if (homogeneous && j == dim - 1) c[3] = x;
        }
        if (homogeneous) c[0] /= c[3], c[1] /= c[3], c[2] /= c[3];
        soup.positions.emplace_back(c[0], c[1], c[2]);
    }
    for (std::int64_t f = 0; f < nf; ++f) {
        if (!lines.next_line(line))
            throw Error(path, "file ends after " + std::to_string(f) + " of " + std::to_string(nf) +
                                  " faces (truncated)");
        if (read_polygon(line, soup)) continue;
        Lines::split(line, tok);
        std::int64_t n = 0;
        if (!parse_int(tok[0], n) || n < 0)
            throw Error(path, lines.at() + "face " + std::to_string(f) + ": bad vertex count " + in_quotes(tok[0]));
        if (std::int64_t(tok.size()) < n + 1)
            throw Error(path, lines.at() + "face " + std::to_string(f) + " lists " +
                                  std::to_string(tok.size() - 1) + " of its " + std::to_string(n) +
                                  " vertex indices");
        for (std::int64_t j = 0; j < n; ++j) {
            std::int64_t v = 0;
            if (!parse_int(tok[j + 1], v))
                throw Error(path, lines.at() + "face " + std::to_string(f) + ": " + in_quotes(tok[j + 1]) +
                                      " is not a vertex index");
            soup.corners.push_back(v);
        }
        soup.end_polygon();
    }
}

// OBJ: "v x y z [...]" and "f a b c ..." with a, b, c of the forms v, v/vt, v//vn, v/vt/vn (1-based,
// negative: relative to the end); every other statement is ignored.
void read_obj(const std::string& text, const std::string& path, Soup& soup) {
    Lines lines(text, true, soup.progress);
    std::vector<std::string_view> tok;
    while (lines.next(tok)) {
        if (tok[0] == "v") {
            if (tok.size() < 4)
                throw Error(path, lines.at() + "vertex " + std::to_string(soup.positions.size()) + " has " +
                                      std::to_string(tok.size() - 1) + " coordinates, expected 3");
            double c[3];
            for (int j = 0; j < 3; ++j)
                if (!parse_double(tok[j + 1], c[j]))
                    throw Error(path, lines.at() + "vertex " + std::to_string(soup.positions.size()) + ": " +
                                          in_quotes(tok[j + 1]) + " is not a number");
            soup.positions.emplace_back(c[0], c[1], c[2]);
        } else if (tok[0] == "f") {
            for (std::size_t j = 1; j < tok.size(); ++j) {
                const std::string_view t = tok[j].substr(0, tok[j].find('/'));
                std::int64_t i = 0;
                if (!parse_int(t, i) || i == 0)
                    throw Error(path, lines.at() + "face " + std::to_string(soup.polygon_count()) + ": " +
                                          in_quotes(tok[j]) + " is not a vertex index");
                soup.corners.push_back(i > 0 ? i - 1 : std::int64_t(soup.positions.size()) + i);
            }
            soup.end_polygon();
        }
    }
}

// ASCII STL: solid / facet normal / outer loop / 3 x vertex / endloop / endfacet / endsolid.
// Corners with identical coordinates become one vertex (as OpenMesh's reader does).
struct PointKey {
    std::size_t operator()(const glm::dvec3& p) const {
        std::size_t h = 0;
        for (int i = 0; i < 3; ++i) {
            std::uint64_t b;
            const double v = p[i] == 0.0 ? 0.0 : p[i];  // -0 == +0
            std::memcpy(&b, &v, sizeof b);
            h = h * 1000003u ^ std::hash<std::uint64_t>()(b);
        }
        return h;
    }
};
struct PointEq {
    bool operator()(const glm::dvec3& a, const glm::dvec3& b) const {
        return a.x == b.x && a.y == b.y && a.z == b.z;
    }
};
// The index of the first corner at each position: an open-addressing table of vertex indices (4
// bytes a slot, at most half full), where a node-based hash map allocated per vertex.
class Welder {
public:
    Welder(Soup& soup, std::size_t expected_vertices) : soup_(soup) { grow(std::max<std::size_t>(64, 4 * expected_vertices)); }
    std::int64_t operator()(const glm::dvec3& p) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {  // refused later
            soup_.positions.push_back(p);
            return std::int64_t(soup_.positions.size() - 1);
        }
        for (std::size_t i = slot_of(p);; i = (i + 1) & mask_) {
            if (slot_[i] == kEmpty) {
                slot_[i] = std::uint32_t(soup_.positions.size());
                soup_.positions.push_back(p);
                if (2 * ++used_ > slot_.size()) grow(2 * slot_.size());
                return std::int64_t(soup_.positions.size() - 1);
            }
            if (PointEq()(soup_.positions[slot_[i]], p)) return slot_[i];
        }
    }

private:
    static constexpr std::uint32_t kEmpty = UINT32_MAX;
    std::size_t slot_of(const glm::dvec3& p) const {  // PointKey mixed: its low bits alone cluster
        std::uint64_t h = PointKey()(p);
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        return std::size_t(h) & mask_;
    }
    void grow(std::size_t at_least) {
        std::size_t size = 64;
        while (size < at_least) size *= 2;
        slot_.assign(size, kEmpty);
        mask_ = size - 1;
        for (std::uint32_t v = 0; v < soup_.positions.size(); ++v) {
            const glm::dvec3& p = soup_.positions[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
            std::size_t i = slot_of(p);
            while (slot_[i] != kEmpty) i = (i + 1) & mask_;
            slot_[i] = v;
        }
    }
    Soup& soup_;
    std::vector<std::uint32_t> slot_;
    std::size_t mask_ = 0, used_ = 0;
};

void read_stl_ascii(const std::string& text, const std::string& path, Soup& soup) {
    Lines lines(text, false, soup.progress);
    std::vector<std::string_view> tok;
    Welder weld(soup, text.size() / 256);
    auto expect = [&](const char* word) {
        if (!lines.next(tok)) throw Error(path, std::string("file ends before '") + word + "' (truncated)");
        if (lower(tok[0]) != word)
            throw Error(path, lines.at() + "expected '" + word + "', found " + in_quotes(tok[0]));
    };
    expect("solid");
    while (true) {
        if (!lines.next(tok)) throw Error(path, "file ends before 'endsolid' (truncated)");
        const std::string w = lower(tok[0]);
        if (w == "endsolid") break;
        if (w != "facet") throw Error(path, lines.at() + "expected 'facet' or 'endsolid', found " + in_quotes(tok[0]));
        expect("outer");
        for (int c = 0; c < 3; ++c) {
            expect("vertex");
            if (tok.size() != 4)
                throw Error(path, lines.at() + "facet " + std::to_string(soup.polygon_count()) +
                                      ": a vertex needs 3 coordinates");
            glm::dvec3 p;
            for (int j = 0; j < 3; ++j)
                if (!parse_double(tok[j + 1], p[j]))
                    throw Error(path, lines.at() + in_quotes(tok[j + 1]) + " is not a number");
            soup.corners.push_back(weld(p));
        }
        expect("endloop");
        expect("endfacet");
        soup.end_polygon();
    }
}

void read_stl_binary(const std::string& data, const std::string& path, Soup& soup) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);  // little-endian files on little-endian hosts
    Welder weld(soup, n);
    soup.corners.reserve(3 * std::size_t(n));
    soup.polygon_end.reserve(n);
    for (std::uint32_t f = 0; f < n; ++f) {
        const char* rec = data.data() + 84 + std::size_t(f) * 50;
        for (int c = 0; c < 3; ++c) {
            float v[3];
            std::memcpy(v, rec + 12 + 12 * c, 12);
            soup.corners.push_back(weld(glm::dvec3(v[0], v[1], v[2])));
        }
        soup.end_polygon();
    }
    (void)path;
}

enum class PlyType : std::uint8_t { I8, U8, I16, U16, I32, U32, F32, F64, Bad };

PlyType ply_type(std::string_view t) {
    if (t == "char" || t == "int8") return PlyType::I8;
    if (t == "uchar" || t == "uint8") return PlyType::U8;
    if (t == "short" || t == "int16") return PlyType::I16;
    if (t == "ushort" || t == "uint16") return PlyType::U16;
    if (t == "int" || t == "int32") return PlyType::I32;
    if (t == "uint" || t == "uint32") return PlyType::U32;
    if (t == "float" || t == "float32") return PlyType::F32;
    if (t == "double" || t == "float64") return PlyType::F64;
    return PlyType::Bad;
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::I8: case PlyType::U8: return 1;
        case PlyType::I16: case PlyType::U16: return 2;
        case PlyType::F64: return 8;
        default: return 4;
    }
}

// A PLY header: elements with their (scalar or list) properties and the properties' types. Reads
// `lines` up to and including the end_header line. Types are checked only when `typed` (binary
// files need them; ASCII bodies are read as numbers whatever the header says).
struct PlyProperty {
    std::string name;
    bool list = false;
    PlyType count = PlyType::U8, value = PlyType::F32;
};
struct PlyElement {
    std::string name;
    std::int64_t count = 0;
    std::vector<PlyProperty> props;
};

// Which properties of element e a mesh reads: a "vertex" element's x, y, z (scalars), a "face"
// element's "vertex_indices" (or "vertex_index") list; -1 where absent (a clear error when a
// vertex or face element lacks them).
struct PlyRoles {
    bool is_vertex = false, is_face = false;
    int xyz[3] = {-1, -1, -1};
    int indices = -1;
};

PlyRoles ply_roles(const PlyElement& e, const std::string& path) {
    PlyRoles r;
    r.is_vertex = e.name == "vertex";
    r.is_face = e.name == "face";
    for (int j = 0; j < int(e.props.size()); ++j) {
        const auto& p = e.props[j];
        if (r.is_vertex && !p.list && (p.name == "x" || p.name == "y" || p.name == "z")) r.xyz[p.name[0] - 'x'] = j;
        if (r.is_face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) r.indices = j;
    }
    if (r.is_vertex && (r.xyz[0] < 0 || r.xyz[1] < 0 || r.xyz[2] < 0))
        throw Error(path, "PLY vertex element lacks an x, y or z property");
    if (r.is_face && r.indices < 0) throw Error(path, "PLY face element lacks a vertex_indices list");
    return r;
}

std::vector<PlyElement> read_ply_header(Lines& lines, const std::string& path, bool typed) {
    std::vector<std::string_view> tok;
    std::vector<PlyElement> elements;
    lines.next(tok);  // "ply", checked by the caller
    while (true) {
        if (!lines.next(tok)) throw Error(path, "file ends inside the PLY header (no end_header)");
        if (tok[0] == "end_header") return elements;
        if (tok[0] == "format" || tok[0] == "comment" || tok[0] == "obj_info") continue;
        if (tok[0] == "element") {
            PlyElement e;
            if (tok.size() != 3 || !parse_int(tok[2], e.count) || e.count < 0)
                throw Error(path, lines.at() + "malformed element line");
            e.name = std::string(tok[1]);
            elements.push_back(std::move(e));
        } else if (tok[0] == "property") {
            if (elements.empty()) throw Error(path, lines.at() + "property before any element");
            PlyProperty p;
            p.list = tok.size() >= 2 && tok[1] == "list";
            if (tok.size() != (p.list ? 5u : 3u)) throw Error(path, lines.at() + "malformed property line");
            p.name = std::string(tok.back());
            if (typed) {
                if (p.list) p.count = ply_type(tok[2]);
                p.value = ply_type(tok[p.list ? 3 : 1]);
                if (p.count == PlyType::Bad || p.value == PlyType::Bad ||
                    (p.list && (p.count == PlyType::F32 || p.count == PlyType::F64)))
                    throw Error(path, lines.at() + "bad property type");
            }
            elements.back().props.push_back(std::move(p));
        } else {
            // Other keywords ("Created by Blender", vendor keys): other readers skip them, and so does
            // this one; the elements and properties are all that the body's layout depends on.
            continue;
        }
    }
}

// ASCII PLY: header of elements and (scalar or list) properties; the "vertex" element gives x, y,
// z and the "face" element its "vertex_indices" (or "vertex_index") list; others are skipped.
void read_ply_ascii(const std::string& text, const std::string& path, Soup& soup) {
    Lines lines(text, false, soup.progress);
    const std::vector<PlyElement> elements = read_ply_header(lines, path, false);
    std::vector<std::string_view> tok;
    // The body as one token stream (an element instance is conventionally one line).
    std::size_t k = 0;
    tok.clear();
    for (const auto& e : elements) {
        const PlyRoles roles = ply_roles(e, path);
        const bool is_vertex = roles.is_vertex, is_face = roles.is_face;
        const int* xyz = roles.xyz;
        const int indices = roles.indices;
        for (std::int64_t i = 0; i < e.count; ++i) {
            glm::dvec3 p(0.0);
            for (int j = 0; j < int(e.props.size()); ++j) {
                auto next = [&]() {
                    while (k >= tok.size()) {
                        if (!lines.next(tok))
                            throw Error(path, "file ends inside " + e.name + " " + std::to_string(i) + " of " +
                                                  std::to_string(e.count) + " (truncated)");
                        k = 0;
                    }
                    return tok[k++];
                };
                if (e.props[j].list) {
                    const auto t = next();
                    std::int64_t n = 0;
                    if (!parse_int(t, n) || n < 0)
                        throw Error(path, e.name + " " + std::to_string(i) + ": bad list length " + in_quotes(t));
                    for (std::int64_t m = 0; m < n; ++m) {
                        const auto u = next();
                        if (j == indices) {
                            std::int64_t v = 0;
                            if (!parse_int(u, v))
                                throw Error(path, "face " + std::to_string(i) + ": " + in_quotes(u) +
                                                      " is not a vertex index");
                            soup.corners.push_back(v);
                        }
                    }
                } else {
                    const auto t = next();
                    double x;
                    if (!parse_double(t, x))
                        throw Error(path, e.name + " " + std::to_string(i) + ": " + in_quotes(t) + " is not a number");
                    for (int c = 0; c < 3; ++c)
                        if (is_vertex && j == xyz[c]) p[c] = x;
                }
            }
            if (is_vertex) soup.positions.push_back(p);
            if (is_face) soup.end_polygon();
        }
    }
}

// A binary PLY value of type t at b (little-endian), as a double.
inline double ply_value(PlyType t, const char* b) {
    switch (t) {
        case PlyType::I8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
        case PlyType::U8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
        case PlyType::I16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        case PlyType::U16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        case PlyType::I32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        case PlyType::U32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        case PlyType::F32: { float v; std::memcpy(&v, b, 4); return v; }
        default: { double v; std::memcpy(&v, b, 8); return v; }
    }
}

// The layout nearly every binary PLY mesh has, read straight into positions and triangles: a
// little-endian body of one vertex element (scalar properties only) followed by one face element
// whose only list is its integer corner indices, three for every face, each a vertex of the file.
// Returns false, leaving `soup` empty, on anything else (other elements, another list, a polygon,
// an index out of range, a short body): read_ply_binary's general reading then reads the file or
// gives its error, so the result is the same either way.
bool read_ply_binary_triangles(const std::string& data, std::size_t at, const std::vector<PlyElement>& elements,
                               const std::string& path, Soup& soup) {
    if (elements.size() != 2) return false;
    const PlyElement &ve = elements[0], &fe = elements[1];
    const PlyRoles vr = ply_roles(ve, path), fr = ply_roles(fe, path);
    if (!vr.is_vertex || !fr.is_face) return false;
    std::size_t vertex_bytes = 0, xyz_offset[3] = {0, 0, 0};
    PlyType xyz_type[3] = {PlyType::F32, PlyType::F32, PlyType::F32};
    for (int j = 0; j < int(ve.props.size()); ++j) {
        if (ve.props[j].list) return false;
        for (int c = 0; c < 3; ++c)
            if (j == vr.xyz[c]) xyz_offset[c] = vertex_bytes, xyz_type[c] = ve.props[j].value;
        vertex_bytes += ply_size(ve.props[j].value);
    }
    // The face record: scalars before the list, the list's count and three indices, scalars after.
    std::size_t before = 0, after = 0;
    for (int j = 0; j < int(fe.props.size()); ++j) {
        const PlyProperty& pr = fe.props[j];
        if (pr.list != (j == fr.indices)) return false;
        if (pr.list) {
            if (pr.count == PlyType::F32 || pr.count == PlyType::F64 || pr.value == PlyType::F32 || pr.value == PlyType::F64)
                return false;  // (float counts and indices: the general reading checks them)
        } else {
            (j < fr.indices ? before : after) += ply_size(pr.value);
        }
    }
    const PlyType count_type = fe.props[std::size_t(fr.indices)].count, index_type = fe.props[std::size_t(fr.indices)].value;
    const std::size_t count_bytes = ply_size(count_type), index_bytes = ply_size(index_type);
    const std::size_t face_bytes = before + count_bytes + 3 * index_bytes + after;
    const auto nv = std::uint64_t(ve.count), nf = std::uint64_t(fe.count);
    if (vertex_bytes == 0 || (data.size() - at) / vertex_bytes < nv) return false;
    const std::size_t face_at = at + nv * vertex_bytes;
    if ((data.size() - face_at) / face_bytes < nf) return false;
    soup.positions.resize(nv);
    const char* v = data.data() + at;
    for (std::uint64_t i = 0; i < nv; ++i, v += vertex_bytes)
        soup.positions[i] = {ply_value(xyz_type[0], v + xyz_offset[0]), ply_value(xyz_type[1], v + xyz_offset[1]),
                             ply_value(xyz_type[2], v + xyz_offset[2])};
    soup.triangles.resize(nf);
    const char* f = data.data() + face_at;
    bool ok = true;
    for (std::uint64_t i = 0; i < nf && ok; ++i, f += face_bytes) {
        ok = ply_value(count_type, f + before) == 3.0;
        for (int k = 0; k < 3; ++k) {
            const double index = ply_value(index_type, f + before + count_bytes + std::size_t(k) * index_bytes);
            ok &= index >= 0.0 && index < double(nv);
            soup.triangles[i][std::size_t(k)] = std::uint32_t(index);
        }
    }
    if (!ok) {
        soup.positions = {};
        soup.triangles = {};
    }
    return ok;
}

// Binary PLY (little- or big-endian). Read here, not by OpenMesh, whose reader trusts the file:
// it reserves storage for the header's counts and resizes face lists to their stated lengths
// before reading them (a 300-byte file with one list claiming 2e9 entries took 17 GB). Here every
// count is checked against the bytes that remain before anything is allocated for it.
void read_ply_binary(const std::string& data, const std::string& path, bool big_endian, Soup& soup) {
    const auto end = data.find("end_header");
    if (end == std::string::npos) throw Error(path, "file ends inside the PLY header (no end_header)");
    const auto nl = data.find('\n', end);
    if (nl == std::string::npos) throw Error(path, "file ends after the PLY header (truncated)");
    const std::string header = data.substr(0, nl + 1);  // Lines keeps a reference
    Lines lines(header, false);
    const std::vector<PlyElement> elements = read_ply_header(lines, path, true);
    std::size_t at = nl + 1;
    // The minimum size of each element's instances (scalars and list lengths) must fit.
    {
        long double need = 0.0L;
        for (const auto& e : elements) {
            std::size_t bytes = 0;
            for (const auto& p : e.props) bytes += ply_size(p.list ? p.count : p.value);
            need += static_cast<long double>(e.count) * static_cast<long double>(std::max<std::size_t>(bytes, 1));
            if (need > static_cast<long double>(data.size() - at))
                throw Error(path, "header claims " + std::to_string(e.count) + " " + e.name + " elements, more than the " +
                                      std::to_string(data.size() - at) +
                                      " bytes after the header can hold (truncated or malformed)");
        }
    }
    if (!big_endian && read_ply_binary_triangles(data, at, elements, path, soup)) return;
    auto read = [&](PlyType t) -> double {
        const std::size_t n = ply_size(t);
        if (data.size() - at < n) throw Error(path, "file ends inside the PLY body (truncated)");
        unsigned char b[8];
        std::memcpy(b, data.data() + at, n);
        at += n;
        if (big_endian) std::reverse(b, b + n);  // to the little-endian order of this machine
        return ply_value(t, reinterpret_cast<const char*>(b));
    };
    for (const auto& e : elements) {
        const PlyRoles roles = ply_roles(e, path);
        const bool is_vertex = roles.is_vertex, is_face = roles.is_face;
        const int* xyz = roles.xyz;
        const int indices = roles.indices;
        if (is_vertex) soup.positions.reserve(std::size_t(e.count));  // fits in the file: checked
        if (is_face) soup.polygon_end.reserve(std::size_t(e.count));
        for (std::int64_t i = 0; i < e.count; ++i) {
            glm::dvec3 p(0.0);
            for (int j = 0; j < int(e.props.size()); ++j) {
                const PlyProperty& pr = e.props[j];
                if (pr.list) {
                    const double n = read(pr.count);
                    if (n < 0 || n * double(ply_size(pr.value)) > double(data.size() - at))
                        throw Error(path, e.name + " " + std::to_string(i) + ": list length " +
                                              std::to_string(std::int64_t(n)) +
                                              " does not fit in the rest of the file (truncated or malformed)");
                    for (std::int64_t m = 0; m < std::int64_t(n); ++m) {
                        const double v = read(pr.value);
                        if (j == indices) {
                            if (v != std::floor(v))
                                throw Error(path, "face " + std::to_string(i) + ": index " + std::to_string(v) +
                                                      " is not an integer");
                            soup.corners.push_back(std::int64_t(v));
                        }
                    }
                } else {
                    const double x = read(pr.value);
                    for (int c = 0; c < 3; ++c)
                        if (is_vertex && j == xyz[c]) p[c] = x;
                }
            }
            if (is_vertex) soup.positions.push_back(p);
            if (is_face) soup.end_polygon();
        }
    }
}

// Binary OFF, laid out as OpenMesh reads and writes it (little-endian): the header line, then
// vertex, face and edge counts (uint32), per vertex 3 floats (then 3 normal floats for NOFF and 2
// texture floats for STOFF), per face its corner count and corner indices (uint32). Read here, not
// by OpenMesh, whose reader trusts the counts: it reserves storage for them and reads faces past
// the end of the file, so a short file claiming billions of elements takes gigabytes.
void read_off_binary(const std::string& data, const std::string& path, const std::string& key, Soup& soup) {
    if (key.size() < 3 || key.compare(key.size() - 3, 3, "OFF") != 0 ||
        key.substr(0, key.size() - 3).find_first_not_of("STCN4n") != std::string::npos)
        throw Error(path, "line 1: expected an OFF header, found " + in_quotes(key));
    const std::string prefix = key.substr(0, key.size() - 3);
    if (prefix.find_first_of("C4n") != std::string::npos)
        throw Error(path, "binary OFF with colours or a vertex dimension other than 3 ('" + key +
                              "') is not supported");
    const std::size_t floats = 3 + (prefix.find('N') != std::string::npos ? 3 : 0) +
                               (prefix.find("ST") != std::string::npos ? 2 : 0);
    std::size_t at = data.find('\n') + 1;  // the caller saw a first line
    auto u32 = [&](const char* what) {
        if (data.size() - at < 4) throw Error(path, std::string("file ends inside the ") + what + " (truncated)");
        const auto* b = reinterpret_cast<const unsigned char*>(data.data() + at);
        at += 4;
        return std::uint32_t(b[0]) | (std::uint32_t(b[1]) << 8) | (std::uint32_t(b[2]) << 16) |
               (std::uint32_t(b[3]) << 24);
    };
    const std::uint64_t nv = u32("header"), nf = u32("header");
    u32("header");  // edge count, unused
    const std::uint64_t body = data.size() - at;
    if (nv * floats * 4 + nf * 16 > body)
        throw Error(path, "header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                              " faces, more than the " + std::to_string(body) +
                              " bytes after it can hold (truncated or malformed)");
    soup.positions.reserve(nv);
    for (std::uint64_t i = 0; i < nv; ++i) {
        float c[8];
        std::memcpy(c, data.data() + at, 4 * floats);  // fits: checked above
        at += 4 * floats;
        soup.positions.emplace_back(c[0], c[1], c[2]);
    }
    soup.polygon_end.reserve(nf);
    for (std::uint64_t f = 0; f < nf; ++f) {
        const std::uint64_t n = u32("faces");
        if (n * 4 > data.size() - at)
            throw Error(path, "face " + std::to_string(f) + " claims " + std::to_string(n) +
                                  " corners, more than the rest of the file holds (truncated or malformed)");
        for (std::uint64_t k = 0; k < n; ++k) soup.corners.push_back(u32("faces"));
        soup.end_polygon();
    }
}


// ---------------------------------------------------------------------------------------------
// Repairs (tolerant loading) and checks.

// New index of each vertex after merging vertices at exactly the same position (-0 == +0) into the
// first of them; positions are compacted in their order. Non-finite positions are never merged
// (they are refused afterwards by name), nor vertices of different groups (`group`, per vertex,
// when not empty). Empty when nothing merges: then nothing changes. Vertices are sorted by group
// and position (their index breaking ties), so each run of equal ones starts with the first of
// them; a sort, where a hash map allocated per vertex and was a large share of loading.
// Whether any two of the keys are equal: an open-addressing set of the keys' indices, at most
// half full (the repairs' quick check: most files need no repair, and a check that finds none
// costs a fraction of the sort that would make it). `hash(i)` and `equal(i, j)` take indices.
template <class Hash, class Equal>
bool any_equal(std::size_t n, Hash&& hash, Equal&& equal) {
    std::size_t size = 64;
    while (size < 2 * n) size *= 2;
    std::vector<std::uint32_t> slot(size, UINT32_MAX);
    for (std::uint32_t i = 0; i < n; ++i) {
        std::uint64_t h = hash(i);
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        for (std::size_t k = std::size_t(h) & (size - 1);; k = (k + 1) & (size - 1)) {
            if (slot[k] == UINT32_MAX) {
                slot[k] = i;
                break;
            }
            if (equal(slot[k], i)) return true;
        }
    }
    return false;
}

std::vector<std::uint32_t> weld_positions(std::vector<glm::dvec3>& positions, std::size_t& welded,
                                          const std::vector<std::uint32_t>& group = {}) {
    const std::size_t nv = positions.size();
    welded = 0;
    if (!any_equal(
            nv,
            [&](std::uint32_t i) {
                const glm::dvec3& p = positions[i];  // non-finite ones all alike: never merged, rarely there
                const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
                return finite ? PointKey()(p) ^ (group.empty() ? 0u : group[i]) : 0u;
            },
            [&](std::uint32_t i, std::uint32_t j) {
                const glm::dvec3 &a = positions[i], &b = positions[j];
                return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z) && PointEq()(a, b) &&
                       (group.empty() || group[i] == group[j]);
            }))
        return {};
    auto group_of = [&](std::size_t i) { return group.empty() ? 0u : group[i]; };
    auto finite = [&](std::size_t i) {
        const glm::dvec3& p = positions[i];
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    };
    std::vector<std::uint32_t> order;
    order.reserve(nv);
    for (std::uint32_t i = 0; i < nv; ++i)
        if (finite(i)) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
        const glm::dvec3 &a = positions[x], &b = positions[y];  // -0 == +0 in these comparisons
        if (group_of(x) != group_of(y)) return group_of(x) < group_of(y);
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z != b.z ? a.z < b.z : x < y;
    });
    std::vector<std::uint32_t> first(nv);  // the first vertex at each one's position (itself if none)
    std::iota(first.begin(), first.end(), 0u);
    for (std::size_t k = 1; k < order.size(); ++k) {
        const std::uint32_t v = order[k], u = order[k - 1];
        if (group_of(v) == group_of(u) && PointEq()(positions[v], positions[u])) {
            first[v] = first[u];
            ++welded;
        }
    }
    if (welded == 0) return {};
    std::vector<std::uint32_t> map(nv);
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < nv; ++i) map[i] = first[i] == i ? next++ : map[first[i]];  // first[i] <= i
    for (std::size_t i = 0; i < nv; ++i) positions[map[i]] = positions[i];  // map[i] <= i
    positions.resize(next);
    return map;
}

// Keeps the faces (and their object ids) whose flag is set, in order.
void keep_faces(TriangleMesh& m, const std::vector<char>& keep) {
    std::size_t k = 0;
    const bool objects = m.face_object.size() == m.triangles.size();
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
        if (!keep[f]) continue;
        m.triangles[k] = m.triangles[f];
        if (objects) m.face_object[k] = m.face_object[f];
        ++k;
    }
    m.triangles.resize(k);
    if (objects) m.face_object.resize(k);
}

void check_coordinates_and_indices(const TriangleMesh& mesh, const std::string& where) {
    const std::size_t nv = mesh.positions.size();
    for (std::size_t i = 0; i < nv; ++i) {
        const auto& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error(where, "vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    }
    if (mesh.triangles.empty())
        throw Error(where, nv > 0 ? "mesh has no faces (" + std::to_string(nv) +
                                        " vertices only: a point cloud has no surface to draw)"
                                  : std::string("mesh has no faces"));
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        for (auto i : mesh.triangles[f])
            if (i >= nv)
                throw Error(where, "face " + std::to_string(f) + " refers to vertex " + std::to_string(i) + " of " +
                                       std::to_string(nv));
}

// Undirected edge key: lower vertex << 32 | upper.
std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

// Exactly whether a, b, c are collinear: a float filter, then CGAL's exact predicate only where
// the filter cannot decide (nearly every face of a mesh is decided by the filter, and CGAL's
// interval filter alone was a large share of loading). Collinear means every coordinate-plane
// projection has a zero 2D orientation; one projection whose determinant exceeds the float error
// bound of its computation (Shewchuk's ccwerrboundA, 3.3e-16 of the terms' magnitude, taken as
// 4e-16; terms far from underflow) is certainly non-zero.
bool collinear(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 u = b - a, v = c - a;
    for (int k = 0; k < 3; ++k) {
        const int i = k, j = (k + 1) % 3;
        const double l = u[i] * v[j], r = u[j] * v[i];
        const double magnitude = std::abs(l) + std::abs(r);
        if (magnitude > 1e-280 && std::abs(l - r) > 4e-16 * magnitude) return false;
    }
    return CGAL::collinear(cgal_point(a), cgal_point(b), cgal_point(c));
}

// Per vertex, an id shared exactly by the vertices at the same position. After welding (tolerant
// mode) only a scene's objects keep vertices apart at one position; without objects the vertex
// index is the id.
std::vector<std::uint32_t> position_ids(const TriangleMesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> id(nv);
    std::iota(id.begin(), id.end(), 0u);
    if (mesh.object_names.size() <= 1) return id;
    std::vector<std::uint32_t> order = id;
    auto before = [&](std::uint32_t x, std::uint32_t y) {
        const glm::dvec3 &a = mesh.positions[x], &b = mesh.positions[y];  // -0 == +0 in these comparisons
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z != b.z ? a.z < b.z : x < y;
    };
    std::sort(order.begin(), order.end(), before);
    for (std::size_t k = 1; k < nv; ++k)
        if (PointEq()(mesh.positions[order[k]], mesh.positions[order[k - 1]])) id[order[k]] = id[order[k - 1]];
    return id;
}

// Marks (keep = 0) each face on the same three points as an earlier kept face; returns how many.
// Double-sided exports and objects listed twice: coincident surfaces have no defined QI, and the
// copy adds nothing. Faces are bucketed by their lowest corner's position id (a counting sort,
// a few faces a bucket), so equal ones meet in one bucket, in face order.
std::size_t drop_duplicate_faces(const TriangleMesh& mesh, std::vector<char>& keep) {
    const std::vector<std::uint32_t> id = position_ids(mesh);
    const std::size_t nf = mesh.triangles.size();
    std::vector<std::array<std::uint32_t, 3>> corners(nf);  // sorted ids
    std::vector<std::uint32_t> begin(id.size() + 2, 0), order(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        corners[f] = {id[t[0]], id[t[1]], id[t[2]]};
        std::sort(corners[f].begin(), corners[f].end());
        if (keep[f]) ++begin[corners[f][0] + 2];
    }
    for (std::size_t v = 0; v < id.size(); ++v) begin[v + 2] += begin[v + 1];
    for (std::uint32_t f = 0; f < nf; ++f)
        if (keep[f]) order[begin[corners[f][0] + 1]++] = f;
    std::size_t dropped = 0;
    for (std::size_t v = 0; v < id.size(); ++v) {
        const auto b0 = order.begin() + begin[v], b1 = order.begin() + begin[v + 1];
        if (b1 - b0 > 32)  // a vertex of many faces: sorted, so equal ones are neighbours (face order kept)
            std::sort(b0, b1, [&](std::uint32_t f, std::uint32_t g) { return corners[f] != corners[g] ? corners[f] < corners[g] : f < g; });
        for (auto j = b0 + 1; j < b1; ++j)
            for (auto i = b1 - b0 > 32 ? j - 1 : b0; i < j; ++i)
                if (corners[*i] == corners[*j]) {  // an earlier face on the same points
                    keep[*j] = 0;
                    ++dropped;
                    break;
                }
    }
    return dropped;
}

// Drops faces with a repeated corner, faces on the same three points as an earlier face (tolerant),
// and zero-area faces (exactly collinear corners) whose every
// edge has at least two other faces: removing those opens nothing (they are fins on edges that are
// already closed). A zero-area face that holds the surface together (a sliver between two sheets)
// is kept: the facing tests are exact and take zero-area faces as they are.
// The repairs' quick check for duplicate faces, from the corner pairing the orientation needs
// anyway: two faces on the same three vertices have all three of their corners paired with each
// other when no edge has more than two faces (mates.extra == 0). So where no face has its three
// mates in one face, there is none, and drop_duplicate_faces' sort is spared (most files).
// Meaningful only where vertex indices are the position ids (one object: position_ids).
bool may_have_duplicate_faces(const CornerMates& mates) {
    if (mates.extra > 0) return true;
    for (std::size_t c = 0; c < mates.mate.size(); c += 3) {
        const std::uint32_t m0 = mates.mate[c], m1 = mates.mate[c + 1], m2 = mates.mate[c + 2];
        if (m0 != kNoCorner && m1 != kNoCorner && m2 != kNoCorner && m0 / 3 == m1 / 3 && m1 / 3 == m2 / 3) return true;
    }
    return false;
}

// Returns true when it left the faces as they were and made `mates`, their corner pairing (tolerant
// mode, one object, no face with a repeated corner); `mates` is not to be used otherwise.
bool drop_degenerate_faces(TriangleMesh& mesh, const std::string& where, bool strict, CornerMates& mates,
                           HilbertOrderAhead* ahead) {
    const std::size_t nf = mesh.triangles.size();
    std::vector<char> keep(nf, 1);
    std::size_t dropped = 0;
    for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            if (strict) throw Error(where, "face " + std::to_string(f) + " repeats a vertex index");
            keep[f] = 0;
            ++dropped;
        }
    }
    bool mates_made = false;
    if (!strict) {
        if (dropped == 0 && mesh.object_names.size() <= 1) {
            mates = corner_mates(mesh.triangles, mesh.positions.size());
            mates_made = true;
        }
        if (!mates_made || may_have_duplicate_faces(mates)) dropped += drop_duplicate_faces(mesh, keep);
        std::vector<std::uint32_t> flat;
        for (std::size_t f = 0; f < nf; ++f) {
            const auto& t = mesh.triangles[f];
            if (keep[f] && collinear(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]))
                flat.push_back(std::uint32_t(f));
        }
        if (!flat.empty()) {
            std::unordered_map<std::uint64_t, std::uint32_t> uses;
            for (std::size_t f = 0; f < nf; ++f)
                if (keep[f])
                    for (int k = 0; k < 3; ++k) ++uses[edge_key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3])];
            for (std::uint32_t f : flat) {
                const auto& t = mesh.triangles[f];
                bool covered = true;
                for (int k = 0; k < 3; ++k) covered = covered && uses[edge_key(t[k], t[(k + 1) % 3])] >= 3;
                if (!covered) continue;
                for (int k = 0; k < 3; ++k) --uses[edge_key(t[k], t[(k + 1) % 3])];
                keep[f] = 0;
                ++dropped;
            }
        }
    }
    if (dropped == 0) return mates_made;
    mesh.repairs.faces_dropped += dropped;
    if (ahead) ahead->before_change();
    keep_faces(mesh, keep);
    if (mesh.triangles.empty())
        throw Error(where, "no faces left: all " + std::to_string(dropped) + " faces are degenerate (repeated corners)");
    return false;
}

std::string nonmanifold_message(const CornerMates& mates) {
    return "non-manifold: " + std::to_string(mates.extra) +
           " extra face(s) on edges shared by more than two faces (first at vertices " +
           std::to_string(mates.first_bad >> 32) + "-" + std::to_string(mates.first_bad & 0xffffffffu) +
           "); hidden-line removal by quantitative invisibility needs a 2-manifold mesh";
}

struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// Cuts the surface along its non-manifold edges. Each vertex on such an edge is split into one copy
// per fan: the faces around it joined through manifold edges (two faces); the first fan keeps the
// vertex. Two sheets that only meet at the edge then have their own copies of its ends and each
// meets the edge as a border, while a closed part with a fin on one of its edges keeps that edge
// (its two faces are one fan at both ends) and the fin alone is cut off. Faces still three or more
// on one edge after that (sheets joined around both ends) are detached: each beyond the first two
// gets its own copies of its corners. Every sheet is then a 2-manifold with border, so Appel's
// border rule (+-1 per sheet behind a border) holds for each sheet on its own.
void cut_nonmanifold_edges(TriangleMesh& mesh, const CornerMates& mates) {
    auto& tris = mesh.triangles;
    const std::size_t nc = 3 * tris.size();
    std::vector<char> on_cut(mesh.positions.size(), 0);
    UnionFind fans(nc);  // element 3f + k: face f at its corner k
    auto corner_at = [&](std::uint32_t f, std::uint32_t v) {
        return 3 * f + (tris[f][0] == v ? 0u : tris[f][1] == v ? 1u : 2u);
    };
    // A group of three or more corners (corner_mates): the middle ones point to the first, whose
    // mate is the last; mark each such group by its first corner.
    std::vector<char> group_of_many(nc, 0);
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t m = mates.mate[c];
        if (m != kNoCorner && m < c && mates.mate[m] != c && !group_of_many[m]) {
            group_of_many[m] = 1;
            ++mesh.repairs.nonmanifold_edges_cut;
        }
    }
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t m = mates.mate[c];
        const std::uint32_t a = tris[c / 3][c % 3], b = tris[c / 3][(c % 3 + 1) % 3];
        if (m == kNoCorner) continue;
        if (mates.mate[m] != c || group_of_many[c] || group_of_many[m]) {  // a non-manifold edge
            on_cut[a] = on_cut[b] = 1;
            continue;
        }
        if (m < c) continue;  // the pair was joined at its first corner
        for (std::uint32_t v : {a, b}) fans.unite(corner_at(c / 3, v), corner_at(m / 3, v));
    }
    std::vector<std::uint32_t> fan_vertex(nc, kNoCorner);
    std::vector<char> kept(mesh.positions.size(), 0);
    for (std::uint32_t c = 0; c < nc; ++c) {
        std::uint32_t& v = tris[c / 3][c % 3];
        if (!on_cut[v]) continue;
        std::uint32_t& nv = fan_vertex[fans.find(c)];
        if (nv == kNoCorner) {
            if (!kept[v]) {
                kept[v] = 1;
                nv = v;
            } else {
                nv = std::uint32_t(mesh.positions.size());
                mesh.positions.push_back(mesh.positions[v]);
                ++mesh.repairs.vertices_split;
            }
        }
        v = nv;
    }
    const CornerMates after = corner_mates(tris, mesh.positions.size());
    if (after.extra == 0) return;
    std::vector<char> detach(tris.size(), 0);
    for (std::uint32_t c = 0; c < nc; ++c) {  // the middle corners of a group (neither first nor last)
        const std::uint32_t m = after.mate[c];
        if (m != kNoCorner && m < c && after.mate[m] != c) detach[c / 3] = 1;
    }
    for (std::size_t f = 0; f < tris.size(); ++f) {
        if (!detach[f]) continue;
        for (auto& v : tris[f]) {
            mesh.positions.push_back(mesh.positions[v]);
            v = std::uint32_t(mesh.positions.size() - 1);
            ++mesh.repairs.vertices_split;
        }
    }
}

// The parts of the surface (faces joined across paired edges), numbered in the order of their
// first faces, when every pair of faces traverses its edge in opposite directions (windings
// already consistent, as in most files); false otherwise, or when an edge has more than two faces.
// It reads the corners in order, where the search of orient reads faces in the order it reaches
// them (random reads of their corners and states: most of orient's time on a large file).
bool parts_if_consistent(const TriangleMesh& mesh, const CornerMates& mates, std::vector<std::uint32_t>& part,
                         std::uint32_t& nparts) {
    if (mates.extra > 0) return false;
    const auto& tris = mesh.triangles;
    UnionFind parts(tris.size());
    for (std::uint32_t c = 0; c < mates.mate.size(); ++c) {
        const std::uint32_t m = mates.mate[c];
        if (m == kNoCorner || m < c) continue;  // each pair once (paired both ways when extra is 0)
        // c's face traverses a->b; its mate's corner is at a or b (orient's search, below).
        if (tris[m / 3][m % 3] != tris[c / 3][(c % 3 + 1) % 3]) return false;
        parts.unite(c / 3, m / 3);
    }
    part.resize(tris.size());
    nparts = 0;
    for (std::uint32_t f = 0; f < tris.size(); ++f) {
        const std::uint32_t root = parts.find(f);  // the part's first face: root <= f
        part[f] = root == f ? nparts++ : part[root];
    }
    return true;
}

// Consistent orientation by breadth-first search over faces: two faces sharing an edge must
// traverse it in opposite directions; a conflict means the surface is not orientable. Strict: it
// is refused. Tolerant (seams): the faces keep the windings the search gave them and the edges
// of conflict are the orientation seams (model/orientation.hpp), counted. state: 1 keep, -1 flip;
// component and nonorientable: each face's part and each part's. Returns the number of parts.
std::uint32_t search_orientation(TriangleMesh& mesh, const CornerMates& mates, const std::string& where, bool seams,
                                 std::vector<std::int8_t>& state, std::vector<std::uint32_t>& component,
                                 std::vector<char>& nonorientable) {
    const std::size_t nf = mesh.triangles.size();
    state.assign(nf, 0);  // 0 unvisited
    component.assign(nf, 0);
    std::vector<std::uint32_t> queue;
    queue.reserve(nf);
    std::uint32_t ncomp = 0;
    std::size_t conflicts = 0;  // corners whose edge is a seam (two per seam edge)
    for (std::uint32_t seed = 0; seed < nf; ++seed) {
        if (state[seed] != 0) continue;
        state[seed] = 1;
        component[seed] = ncomp;
        queue.assign(1, seed);
        bool flips = false, seamed = false;
        for (std::size_t qi = 0; qi < queue.size(); ++qi) {
            const std::uint32_t f = queue[qi];
            const auto& t = mesh.triangles[f];
            for (int k = 0; k < 3; ++k) {
                std::uint32_t a = t[k], b = t[(k + 1) % 3];
                if (state[f] < 0) std::swap(a, b);  // direction after the flip decided for f
                const std::uint32_t other = mates.mate[3 * f + k];
                if (other == kNoCorner) continue;  // border edge
                const std::uint32_t g = other / 3;
                // g must traverse b->a after its own flip state. Its mate corner's edge is {a, b}
                // (corners are paired by their edges' vertices, and no face repeats a vertex here),
                // so g traverses a->b exactly when that corner is at a.
                const std::int8_t need = mesh.triangles[g][other % 3] == a ? -1 : 1;
                if (state[g] == 0) {
                    state[g] = need;
                    flips = flips || need < 0;
                    component[g] = ncomp;
                    queue.push_back(g);
                } else if (state[g] != need) {
                    if (!seams)
                        throw Error(where, "non-orientable surface (faces " + std::to_string(f) + " and " +
                                               std::to_string(g) +
                                               " cannot be oriented consistently, e.g. a Moebius strip)");
                    ++conflicts;
                    seamed = true;
                }
            }
        }
        // (A seamed part's flips are its orientation, not a disagreement repaired: not counted.)
        mesh.repairs.components_reoriented += flips && !seamed;
        nonorientable.push_back(seamed);
        ++ncomp;
    }
    mesh.repairs.orientation_seam_edges += conflicts / 2;
    for (char c : nonorientable) mesh.repairs.nonorientable_parts += c;
    return ncomp;
}

// Orients the faces consistently (search_orientation, or nothing to do when parts_if_consistent
// finds the windings consistent already: the same parts, every face kept). Closed orientable
// components are then turned outward (positive signed volume), so that front-facing silhouette
// edges are the convex ones, as the Markosian et al. parity rule assumes. Each face is flipped at
// most once; faces_reoriented counts the faces whose final orientation differs from the input,
// repairs.components_reoriented the components whose faces disagreed. Returns per face 1 if this
// call flipped it, or nothing when it flipped none (most files).
std::vector<std::uint8_t> orient(TriangleMesh& mesh, const CornerMates& mates, const std::string& where, bool seams,
                                 HilbertOrderAhead* ahead) {
    const std::size_t nf = mesh.triangles.size();
    std::vector<std::int8_t> state;
    std::vector<std::uint32_t> component;
    std::vector<char> nonorientable;  // per component
    std::uint32_t ncomp = 0;
    if (parts_if_consistent(mesh, mates, component, ncomp)) {
        state.assign(nf, 1);
        nonorientable.assign(ncomp, 0);
    } else {
        ncomp = search_orientation(mesh, mates, where, seams, state, component, nonorientable);
    }
    std::vector<double> volume(ncomp, 0.0);
    std::vector<char> closed(ncomp, 1);
    for (std::size_t c = 0; c < mates.mate.size(); ++c)
        if (mates.mate[c] == kNoCorner) closed[component[c / 3]] = 0;
    const glm::dvec3 c = mesh.positions[mesh.triangles[0][0]];
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        const glm::dvec3 a = mesh.positions[t[0]] - c, b = mesh.positions[t[1]] - c,
                         d = mesh.positions[t[2]] - c;
        const double v = a.x * (b.y * d.z - b.z * d.y) - a.y * (b.x * d.z - b.z * d.x) +
                         a.z * (b.x * d.y - b.y * d.x);
        volume[component[f]] += state[f] < 0 ? -v : v;
    }
    std::vector<std::uint8_t> flipped;
    for (std::uint32_t f = 0; f < nf; ++f) {
        const bool outward_flip = closed[component[f]] && !nonorientable[component[f]] && volume[component[f]] < 0.0;
        if ((state[f] < 0) != outward_flip) {
            if (ahead && flipped.empty()) ahead->before_change();
            std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
            ++mesh.faces_reoriented;
            if (flipped.empty()) flipped.assign(nf, 0);
            flipped[f] = 1;
        }
    }
    return flipped;
}

// Keeps the corner pairing `mate` of the triangles before orient for the mesh's triangles, which
// are those with the faces `flipped` flipped (corners 1 and 2 swapped: the edges of corners 0 and
// 2 change places, corner 1 keeps its own); no flips, no change.
void keep_corner_mates(TriangleMesh& mesh, const std::vector<std::uint8_t>& flipped, std::vector<std::uint32_t> mate) {
    mesh.corner_mates_of = triangles_key(mesh.triangles);
    if (flipped.empty()) {
        mesh.corner_mates = std::move(mate);
        return;
    }
    const std::size_t nf = mesh.triangles.size();
    const auto moved = [&](std::uint32_t c) {  // a corner's index after the flips
        return c == kNoCorner || !flipped[c / 3] ? c : c - c % 3 + (2 - c % 3);
    };
    std::vector<std::uint32_t> after(3 * nf);
    for (std::uint32_t c = 0; c < 3 * nf; ++c) after[moved(c)] = moved(mate[c]);
    mesh.corner_mates = std::move(after);
}

// Checks and repairs a mesh whose vertices are already welded (see repair_mesh).
// With `ahead`, starts it once the indices are checked and announces each change to the mesh.
void repair_welded(TriangleMesh& mesh, const std::string& where, bool strict,
                   const LoadProgressCallback* progress_callback = nullptr, HilbertOrderAhead* ahead = nullptr) {
    LoadProgressReporter progress(progress_callback, 0);
    check_coordinates_and_indices(mesh, where);
    if (ahead) ahead->start(mesh);
    try {
        CornerMates mates;
        const bool mates_made = drop_degenerate_faces(mesh, where, strict, mates, ahead);
        progress.at(kProgressParsed + 0.4 * (kProgressRepaired - kProgressParsed));
        if (!mates_made) mates = corner_mates(mesh.triangles, mesh.positions.size());
        if (mates.extra > 0) {
            if (strict) throw Error(where, nonmanifold_message(mates));
            if (ahead) ahead->before_change();
            cut_nonmanifold_edges(mesh, mates);
            mates = corner_mates(mesh.triangles, mesh.positions.size());
        }
        progress.at(kProgressParsed + 0.7 * (kProgressRepaired - kProgressParsed));
        const std::vector<std::uint8_t> flipped = orient(mesh, mates, where, !strict, ahead);
        if (mates.extra == 0) keep_corner_mates(mesh, flipped, std::move(mates.mate));
    } catch (...) {
        if (ahead) ahead->before_change();  // (the mesh is about to be freed: the thread must be done reading it)
        throw;
    }
}

// Triangulates a polygon (corner indices, welded) by ear clipping in the plane of its Newell normal,
// unless it is strictly convex: then it leaves `poly` to the caller's fan and returns true. Returns
// false when the polygon has no area (nothing to draw). Ears are strictly convex corners whose
// triangle holds no other corner (corners of the same index as the ear's are the keyhole's other
// visit and do not count), so the triangles neither overlap nor have zero area; a polygon left
// without an ear (self-intersecting) is finished as a fan.
bool ear_clip(const std::vector<glm::dvec3>& positions, std::vector<std::int64_t>& poly,
              std::vector<std::array<std::uint32_t, 3>>& out) {
    const std::size_t n = poly.size();
    glm::dvec3 normal(0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 a = positions[std::size_t(poly[i])], b = positions[std::size_t(poly[(i + 1) % n])];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const glm::dvec3 an = glm::abs(normal);
    if (an.x == 0.0 && an.y == 0.0 && an.z == 0.0) return false;
    const int drop = an.x >= an.y && an.x >= an.z ? 0 : an.y >= an.z ? 1 : 2;  // the axis to project along
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    const double sign = normal[drop] > 0.0 ? 1.0 : -1.0;  // counter-clockwise in (u, v) when positive
    auto at = [&](std::int64_t i) { return glm::dvec2(positions[std::size_t(i)][u], positions[std::size_t(i)][v]); };
    auto turn = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
        const glm::dvec2 p = at(a), q = at(b), r = at(c);
        return sign * ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x));
    };
    std::vector<std::int64_t> sorted = poly;
    std::sort(sorted.begin(), sorted.end());
    bool convex = std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
    for (std::size_t i = 0; convex && i < n; ++i) convex = turn(poly[i], poly[(i + 1) % n], poly[(i + 2) % n]) > 0.0;
    if (convex) return true;
    std::vector<std::int64_t> ring = poly;
    auto emit = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
        out.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
    };
    while (ring.size() > 3) {
        const std::size_t m = ring.size();
        bool clipped = false;
        for (std::size_t i = 0; i < m && !clipped; ++i) {
            const std::int64_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
            if (turn(a, b, c) <= 0.0) continue;
            bool empty = true;
            for (std::size_t j = 0; j < m && empty; ++j) {
                const std::int64_t p = ring[j];
                if (p == a || p == b || p == c) continue;
                empty = !(turn(a, b, p) >= 0.0 && turn(b, c, p) >= 0.0 && turn(c, a, p) >= 0.0);
            }
            if (!empty) continue;
            emit(a, b, c);
            ring.erase(ring.begin() + std::ptrdiff_t(i));
            clipped = true;
        }
        if (!clipped) break;
    }
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) emit(ring[0], ring[k], ring[k + 1]);
    poly.clear();  // triangulated here
    return true;
}

// The parsed polygons into a repaired triangle mesh: indices checked, vertices welded, polygons
// cleaned (tolerant: corners repeated in a row merged, polygons that still repeat one dropped;
// strict: nothing welded, as before the repairs, so strict loading is the old loading exactly)
// and fan-triangulated, as OpenMesh's own triangulate() does for convex polygons.
// Soup::triangles to a mesh, as triangulate() would make it from the same faces as polygons: the
// same errors, welding and dropped faces.
TriangleMesh triangulate_triangles(Soup soup, const std::string& path, const LoadOptions& options, HilbertOrderAhead* ahead) {
    TriangleMesh mesh;
    if (options.strict)
        for (std::size_t fi = 0; fi < soup.triangles.size(); ++fi) {
            const auto& t = soup.triangles[fi];
            if (t[0] == t[1] || t[0] == t[2] || t[1] == t[2])
                throw Error(path, "face " + std::to_string(fi) + " repeats vertex index " +
                                      std::to_string(t[1] == t[0] ? t[1] : t[2]));
        }
    const std::vector<std::uint32_t> weld =
        options.strict ? std::vector<std::uint32_t>{} : weld_positions(soup.positions, mesh.repairs.vertices_welded);
    mesh.positions = std::move(soup.positions);
    mesh.triangles = std::move(soup.triangles);
    if (!options.strict) {  // (a repeated corner, in the file or by welding: the face has no area)
        std::size_t kept = 0;
        for (auto t : mesh.triangles) {
            if (!weld.empty()) t = {weld[t[0]], weld[t[1]], weld[t[2]]};
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
                ++mesh.repairs.faces_dropped;
                continue;
            }
            mesh.triangles[kept++] = t;
        }
        mesh.triangles.resize(kept);
    }
    if (mesh.triangles.empty() && mesh.repairs.faces_dropped > 0)
        throw Error(path, "no faces left: all " + std::to_string(mesh.repairs.faces_dropped) +
                              " faces are degenerate (repeated corners)");
    soup = Soup();
    LoadProgressReporter(&options.progress, 0).at(kProgressParsed + 0.2 * (kProgressRepaired - kProgressParsed));
    repair_welded(mesh, path, options.strict, &options.progress, ahead);
    return mesh;
}

TriangleMesh triangulate(Soup soup, const std::string& path, const LoadOptions& options, HilbertOrderAhead* ahead) {
    if (!soup.triangles.empty()) return triangulate_triangles(std::move(soup), path, options, ahead);
    const std::int64_t nv = std::int64_t(soup.positions.size());
    const auto polygon = [&soup](std::size_t fi) {  // the corners of polygon fi
        const std::size_t begin = fi == 0 ? 0 : soup.polygon_end[fi - 1];
        return std::span<std::int64_t>(soup.corners.data() + begin, soup.polygon_end[fi] - begin);
    };
    for (std::size_t fi = 0; fi < soup.polygon_count(); ++fi) {
        const std::span<const std::int64_t> poly = polygon(fi);
        if (poly.size() < 3) throw Error(path, "face " + std::to_string(fi) + " has fewer than 3 vertices");
        for (std::size_t a = 0; a < poly.size(); ++a) {
            if (poly[a] < 0 || poly[a] >= nv)
                throw Error(path, "face " + std::to_string(fi) + " refers to vertex " + std::to_string(poly[a]) +
                                      " of " + std::to_string(nv));
            if (options.strict)
                for (std::size_t b = 0; b < a; ++b)
                    if (poly[a] == poly[b])
                        throw Error(path, "face " + std::to_string(fi) + " repeats vertex index " +
                                              std::to_string(poly[a]));
        }
    }
    TriangleMesh mesh;
    const std::vector<std::uint32_t> weld =
        options.strict ? std::vector<std::uint32_t>{} : weld_positions(soup.positions, mesh.repairs.vertices_welded);
    mesh.positions = std::move(soup.positions);
    if (!weld.empty())
        for (auto& i : soup.corners) i = weld[std::size_t(i)];
    mesh.triangles.reserve(soup.corners.size() - 2 * soup.polygon_count());  // as many as a fan makes
    std::vector<std::int64_t> clean, poly;
    for (std::size_t fi = 0; fi < soup.polygon_count(); ++fi) {
        const std::span<const std::int64_t> corners = polygon(fi);
        if (corners.size() == 3 && (options.strict || (corners[0] != corners[1] && corners[1] != corners[2] &&
                                                       corners[2] != corners[0]))) {
            // A proper triangle (nearly every face): taken as it is, as the general path below would.
            mesh.triangles.push_back(
                {std::uint32_t(corners[0]), std::uint32_t(corners[1]), std::uint32_t(corners[2])});
            continue;
        }
        poly.assign(corners.begin(), corners.end());
        if (!options.strict) {
            clean.clear();
            for (std::size_t a = 0; a < poly.size(); ++a)
                if (poly[a] != poly[(a + 1) % poly.size()]) clean.push_back(poly[a]);
            if (clean.size() < 3) {  // (a triangle that repeats a corner is down to two here)
                ++mesh.repairs.faces_dropped;
                continue;
            }
            poly.swap(clean);
            // Keyhole polygons (a corner repeated where a bridge edge is walked twice) and
            // polygons that are not strictly convex are cut into ears: a fan would overlap itself
            // or make zero-area triangles there.
            if (poly.size() > 3) {
                if (!ear_clip(mesh.positions, poly, mesh.triangles)) {
                    ++mesh.repairs.faces_dropped;
                    continue;
                }
                if (poly.empty()) {  // triangulated by ear_clip
                    ++mesh.polygons_triangulated;
                    continue;
                }
            }
        }
        if (poly.size() > 3) ++mesh.polygons_triangulated;
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            mesh.triangles.push_back({std::uint32_t(poly[0]), std::uint32_t(poly[k]), std::uint32_t(poly[k + 1])});
    }
    if (mesh.triangles.empty() && mesh.repairs.faces_dropped > 0)
        throw Error(path, "no faces left: all " + std::to_string(mesh.repairs.faces_dropped) +
                              " faces are degenerate (repeated corners)");
    // (freed before the repairs, as the file's bytes)
    soup = Soup();
    clean = poly = {};
    LoadProgressReporter(&options.progress, 0).at(kProgressParsed + 0.2 * (kProgressRepaired - kProgressParsed));
    repair_welded(mesh, path, options.strict, &options.progress, ahead);
    return mesh;
}

}  // namespace

TriangleMesh load_mesh(const std::string& path, const LoadOptions& options) { return load_mesh(path, options, nullptr); }

TriangleMesh load_mesh(const std::string& path, const LoadOptions& options, HilbertOrderAhead* ahead) {
    const std::string ext = lower_extension(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        throw Error(path, "unsupported mesh format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    std::string data;
    {
        // In one read of the file's size (a stream copied through its iterators took a few ms
        // of a 2.6 MB file), then to its end in case the file grew meanwhile.
        std::ifstream in(path, std::ios::binary | std::ios::ate);
        if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
        const std::streamoff size = in.tellg();
        in.seekg(0);
        if (size > 0) {
            data.resize(std::size_t(size));
            in.read(data.data(), size);
            data.resize(std::size_t(in.gcount()));
        }
        if (in.bad()) throw Error(path, "read error");
        if (in) data.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (in.bad()) throw Error(path, "read error");
    }
    if (data.empty()) throw Error(path, "file is empty");
    if (data.size() >= 2 && ((data[0] == '\xff' && data[1] == '\xfe') || (data[0] == '\xfe' && data[1] == '\xff')))
        throw Error(path, "UTF-16 text (byte-order mark) is not read: save the file as UTF-8 or ASCII");

    LoadProgressReporter progress(&options.progress, data.size());
    Soup soup;
    soup.progress = &progress;
    std::vector<std::string_view> first;
    Lines::split(std::string_view(data).substr(0, data.find('\n')), first);
    if (ext == "off") {
        if (first.size() >= 2 && first[1] == "BINARY") {
            read_off_binary(data, path, std::string(first[0]), soup);
        }
        else read_off(data, path, soup);
    } else if (ext == "obj") {
        read_obj(data, path, soup);
    } else if (ext == "ply") {
        if (first.empty() || first[0] != "ply") throw Error(path, "not a PLY file (no 'ply' magic line)");
        Lines header(data, false);
        std::vector<std::string_view> tok;
        std::string format;
        while (header.next(tok) && tok[0] != "end_header")
            if (tok[0] == "format" && tok.size() >= 2) format = std::string(tok[1]);
        if (format == "ascii") read_ply_ascii(data, path, soup);
        else if (format == "binary_little_endian") read_ply_binary(data, path, false, soup);
        else if (format == "binary_big_endian") read_ply_binary(data, path, true, soup);
        else throw Error(path, "unknown PLY format " + in_quotes(format) +
                                   " (expected ascii, binary_little_endian or binary_big_endian)");
    } else {
        // ASCII if it starts with "solid" and holds no NUL byte (binary headers may start with
        // "solid" too, but the records' attribute words are practically always zero).
        const bool ascii = !first.empty() && lower(first[0]) == "solid" && data.find('\0') == std::string::npos;
        std::uint32_t n = 0;
        if (data.size() >= 84) std::memcpy(&n, data.data() + 80, 4);
        if (ascii) read_stl_ascii(data, path, soup);
        else if (data.size() >= 84 && data.size() == 84 + 50 * std::uint64_t(n)) read_stl_binary(data, path, soup);
        else
            throw Error(path, "not ASCII STL, and " + std::to_string(data.size()) +
                                  " bytes is not the size of a binary STL (84 + 50 x " + std::to_string(n) +
                                  " facets): truncated or malformed");
    }

    // The file's bytes freed before the repairs: not held through them (blocks under 4 MB go back to
    // the programs' arena for the repairs' arrays; larger ones are unmapped: src/app/huge_pages.cpp).
    std::string().swap(data);
    progress.stage(kProgressParsed);
    TriangleMesh mesh = triangulate(std::move(soup), path, options, ahead);
    try {
        progress.stage(kProgressRepaired);
    } catch (...) {
        if (ahead) ahead->before_change();  // (as in repair_welded)
        throw;
    }
    return mesh;
}

std::uint64_t triangles_key(const std::vector<std::array<std::uint32_t, 3>>& triangles) {
    // Four independent chains, triangle i in chain i % 4: a single chain waited on its multiplies
    // (a load hashes its triangles three times: a few milliseconds a million each).
    const auto mix = [](std::uint64_t h, const std::array<std::uint32_t, 3>& t) {
        h = (h ^ ((std::uint64_t(t[0]) << 32) | t[1])) * 0xFF51AFD7ED558CCDull;
        h = (h ^ t[2]) * 0xC4CEB9FE1A85EC53ull;
        return h ^ (h >> 29);
    };
    std::uint64_t h[4] = {0x9E3779B97F4A7C15ull ^ triangles.size(), 0xBF58476D1CE4E5B9ull, 0x94D049BB133111EBull,
                          0x2545F4914F6CDD1Dull};
    const std::size_t n = triangles.size();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (int k = 0; k < 4; ++k) h[k] = mix(h[k], triangles[i + std::size_t(k)]);
    for (; i < n; ++i) h[0] = mix(h[0], triangles[i]);
    return mix(mix(mix(h[0], {std::uint32_t(h[1]), std::uint32_t(h[1] >> 32), std::uint32_t(h[2])}),
                   {std::uint32_t(h[2] >> 32), std::uint32_t(h[3]), std::uint32_t(h[3] >> 32)}),
               {0, 0, 0});
}

CornerMates corner_mates(const std::vector<std::array<std::uint32_t, 3>>& triangles, std::size_t nv) {
    const std::size_t nc = 3 * triangles.size();
    CornerMates out;
    out.mate.assign(nc, kNoCorner);
    std::vector<std::uint32_t> begin(nv + 2, 0);
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) ++begin[std::min(t[k], t[(k + 1) % 3]) + 2];
    for (std::size_t v = 0; v < nv; ++v) begin[v + 2] += begin[v + 1];
    std::vector<std::uint64_t> key(nc);  // (upper vertex, corner), bucketed by lower vertex
    for (std::uint32_t c = 0; c < nc; ++c) {
        const auto& t = triangles[c / 3];
        const std::uint32_t a = t[c % 3], b = t[(c % 3 + 1) % 3];
        key[begin[std::min(a, b) + 1]++] = (std::uint64_t(std::max(a, b)) << 32) | c;
    }
    std::uint32_t first_bad_corner = kNoCorner;
    for (std::size_t v = 0; v < nv; ++v) {
        const auto b0 = key.begin() + begin[v], b1 = key.begin() + begin[v + 1];
        if (b1 - b0 > 16) {
            std::sort(b0, b1);
        } else {  // a vertex's few edges (six on average): insertion sort, without std::sort's set-up
            for (auto i = b0 + 1; i < b1; ++i) {
                const std::uint64_t k = *i;  // held, the larger ones moved up (no overlapping swaps)
                auto j = i;
                for (; j > b0 && *(j - 1) > k; --j) *j = *(j - 1);
                *j = k;
            }
        }
        for (auto g0 = b0; g0 != b1;) {  // one group: the same upper vertex
            auto g1 = g0 + 1;
            while (g1 != b1 && (*g1 >> 32) == (*g0 >> 32)) ++g1;
            const auto first = std::uint32_t(*g0);
            if (g1 - g0 > 1) {
                out.mate[first] = std::uint32_t(*(g1 - 1));
                for (auto it = g0 + 1; it != g1; ++it) out.mate[std::uint32_t(*it)] = first;
            }
            if (g1 - g0 > 2) {
                out.extra += std::size_t(g1 - g0 - 2);
                if (std::uint32_t(g0[2]) < first_bad_corner) {
                    first_bad_corner = std::uint32_t(g0[2]);
                    out.first_bad = (std::uint64_t(v) << 32) | (*g0 >> 32);
                }
            }
            g0 = g1;
        }
    }
    return out;
}


void repair_mesh(TriangleMesh& mesh, const std::string& where, const LoadOptions& options) {
    check_coordinates_and_indices(mesh, where);  // before welding: the messages name input indices
    // A scene's objects are welded each on its own (objects that touch stay apart).
    std::vector<std::uint32_t> group;
    if (!mesh.face_object.empty() && mesh.face_object.size() == mesh.triangles.size()) {
        group.assign(mesh.positions.size(), UINT32_MAX);
        for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
            for (auto v : mesh.triangles[f])
                if (group[v] == UINT32_MAX) group[v] = mesh.face_object[f];
    }
    std::size_t welded = 0;
    const std::vector<std::uint32_t> weld =
        options.strict ? std::vector<std::uint32_t>{} : weld_positions(mesh.positions, welded, group);
    mesh.repairs.vertices_welded += welded;
    if (!weld.empty())
        for (auto& t : mesh.triangles)
            for (auto& i : t) i = weld[i];
    LoadProgressReporter(&options.progress, 0).at(kProgressParsed + 0.2 * (kProgressRepaired - kProgressParsed));
    repair_welded(mesh, where, options.strict, &options.progress);
}

void validate_mesh(TriangleMesh& mesh, const std::string& where) { repair_welded(mesh, where, true); }

std::vector<std::string> LoadReport::warnings(const std::string& where) const {
    std::vector<std::string> out;
    if (vertices_welded > 0)
        out.push_back(where + ": welded " + std::to_string(vertices_welded) +
                      " vertices at the same position as another (seams split by UVs or normals)");
    if (faces_dropped > 0)
        out.push_back(where + ": dropped " + std::to_string(faces_dropped) +
                      " degenerate or duplicate faces (a repeated corner, zero area, or the corners of another face)");
    if (nonmanifold_edges_cut > 0)
        out.push_back(where + ": cut the surface at " + std::to_string(nonmanifold_edges_cut) +
                      " non-manifold edges (more than two faces; " + std::to_string(vertices_split) +
                      " vertices split, each sheet now has a border there)");
    if (components_reoriented > 0)
        out.push_back(where + ": re-oriented " + std::to_string(components_reoriented) +
                      " connected parts whose faces disagreed in orientation");
    if (orientation_seam_edges > 0)
        out.push_back(where + ": " + std::to_string(nonorientable_parts) +
                      " connected part(s) cannot be oriented (a Moebius strip, a Klein bottle): their faces are "
                      "drawn two-sided, with an orientation seam of " + std::to_string(orientation_seam_edges) +
                      " edges where the winding flips (--strict refuses them)");
    if (cameras_dropped > 0)
        out.push_back(where + ": left out " + std::to_string(cameras_dropped) +
                      " of the file's cameras that cannot make a view (the first, " + first_camera_problem + ")");
    return out;
}

}  // namespace inkline
