// Procedural meshes with known answers, for tests, examples and benchmarks.
// Each returns a validated TriangleMesh (closed surfaces oriented outward).
#pragma once

#include <glm/vec3.hpp>

#include "model/mesh_io.hpp"

namespace inkline {

// UV sphere: `slices` around the axis (y), `stacks` from pole to pole.
TriangleMesh make_sphere(glm::dvec3 center, double radius, int slices, int stacks);
// Torus around `axis` (unit) through `center`: major radius R, minor radius r.
TriangleMesh make_torus(glm::dvec3 center, glm::dvec3 axis, double R, double r, int major_segments,
                        int minor_segments);
// Axis-aligned box, two triangles per side (all edges between sides are 90-degree creases).
TriangleMesh make_box(glm::dvec3 lo, glm::dvec3 hi);
// Open square sheet in the plane y = height, n x n quads: a single border loop.
TriangleMesh make_sheet(double half_size, double height, int n);
// Concatenates meshes (vertex indices shifted); the result is validated again.
TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace inkline
