// Loop subdivision (OpenMesh's subdivider): smooth, larger versions of a model for benchmarks and
// for drawing coarse smooth models (`--subdivide=N`).
#pragma once
#include "model/mesh_io.hpp"

namespace inkline {

// `levels` rounds of Loop subdivision (each quadruples the triangles). The result is validated.
TriangleMesh subdivide_loop(TriangleMesh mesh, int levels);

}  // namespace inkline
