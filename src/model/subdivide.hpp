// Loop subdivision (OpenMesh's subdivider): smooth, larger versions of a model for benchmarks and
// for drawing coarse smooth models (`--subdivide=N`).
#pragma once
#include <cstddef>
#include <functional>

#include "model/mesh_io.hpp"

namespace inkline {

// Called with (triangles made so far, triangles the levels make in all): once at the start, then
// after each level (a level costs in proportion to the triangles it makes).
using SubdivideProgress = std::function<void(std::size_t done, std::size_t total)>;

// `levels` rounds of Loop subdivision (each quadruples the triangles). The result is validated.
TriangleMesh subdivide_loop(TriangleMesh mesh, int levels, const SubdivideProgress& progress = {});

}  // namespace inkline
