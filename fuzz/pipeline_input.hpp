// The pipeline fuzzer's input decoding, shared with the regression tests (tests/test_extremes.cpp
// replays fuzz/regressions/pipeline-*): input bytes -> a small closed mesh and a camera, then
// render_view with both visibility methods. Returns false when the input is refused (an
// inkline::Error or a degenerate camera); throws nothing else.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "core/error.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"

namespace inkline_fuzz {

struct Bytes {
    const std::uint8_t* p;
    std::size_t n, i = 0;
    int next() { return i < n ? p[i++] : 0; }
    double coord() { return (next() - 128) / 32.0; }  // -4 .. 4 in steps of 1/32
};

// A sphere (4-8 slices, 2-5 stacks) whose vertices the input moves on a coarse grid (coplanar
// faces, coincident and collinear vertices, zero-area faces are frequent), and a camera
// (perspective or orthographic, eye and target on the grid, optional near plane).
inline bool render_from_bytes(const std::uint8_t* data, std::size_t size, std::vector<inkline::View>& views) {
    // Every read is sequenced (function arguments are evaluated in an unspecified order, and GCC
    // and clang differ), so an input decodes the same way in every build.
    Bytes in{data, size};
    const int slices = 4 + in.next() % 5;
    const int stacks = 2 + in.next() % 4;
    inkline::TriangleMesh m = inkline::make_sphere({0, 0, 0}, 1.0, slices, stacks);
    for (auto& p : m.positions) {
        const int mode = in.next() % 4;
        if (mode == 1) p = {in.coord(), in.coord(), in.coord()};  // braces: left to right
        else if (mode == 2) p = {std::round(p.x), std::round(p.y), std::round(p.z)};
        else if (mode == 3) p *= 0.0;
    }
    const int kind = in.next();
    views.clear();
    try {
        inkline::validate_mesh(m, "fuzz");
        const double crease = in.next() % 180;
        const inkline::Model model(m, crease);
        const glm::dvec3 eye{in.coord() * 4, in.coord() * 4, in.coord() * 4};
        const glm::dvec3 target{in.coord(), in.coord(), in.coord()};
        const glm::dvec3 up{in.coord(), in.coord(), in.coord()};
        const int w = 16 + in.next() * 4;
        const int h = 16 + in.next() * 4;
        const int size_byte = in.next();
        inkline::Camera cam = (kind & 1) ? inkline::Camera::orthographic(eye, target, up, 0.1 + size_byte / 16.0, w, h)
                                         : inkline::Camera::perspective(eye, target, up, 1 + size_byte % 178, w, h);
        if (kind & 2) cam.set_near((1 + in.next()) / 64.0);
        for (auto method : {inkline::VisibilityMethod::Rays, inkline::VisibilityMethod::Appel}) {
            inkline::ViewOptions opt;
            opt.visibility = method;
            opt.walk = (kind & 4) != 0;
            views.push_back(inkline::render_view(model, cam, opt));
        }
    } catch (const inkline::Error&) {
        return false;
    } catch (const std::invalid_argument&) {
        return false;
    }
    return true;
}

// Every point finite, every QI non-negative.
inline bool drawing_is_sane(const inkline::Drawing& d) {
    for (const auto& piece : d.pieces) {
        if (piece.qi < 0) return false;
        for (const auto& q : piece.points)
            if (!std::isfinite(q.x) || !std::isfinite(q.y)) return false;
    }
    return true;
}

}  // namespace inkline_fuzz
