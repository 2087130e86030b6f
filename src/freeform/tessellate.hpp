// Tessellation of freeform surfaces into the mesh pipeline (Elber 99, section 2.3: "the freeform
// surfaces are a-priori approximated using piecewise linear polygons"). Takes a SurfaceList; gives a
// validated TriangleMesh (the input of inkline::Model, so silhouettes, borders and visibility work
// unchanged) and the map from (surface, u, v) to the triangle under it, for stroke visibility.
//
// Each surface is sampled on a uniform grid, two triangles per cell oriented like S_u x S_v.
// Patches meet along shared edges but are separate in the input (the Utah teapot's 32 patches), so
// coincident vertices are welded (positions within 1e-7 of the bounding-box diagonal). Cells that
// collapse at poles (sphere; the teapot's lid, bottom and spout tip, where a whole patch edge is
// one point) then give triangles with a repeated vertex: these are dropped, the only thing the
// mesh checks (validate_mesh) would refuse. What is left must be a 2-manifold; anything else is
// refused with the validator's one-line error naming the file. Orientation: validate_mesh makes it
// consistent per connected part (closed parts outward); open parts (the teapot's spout and handle
// are open tubes pushed into the body) are turned outward by a parity vote of rays cast along
// their face normals (an outward normal sees an even number of layers). Each surface's normal sign
// follows its triangles, so stroke normals N_i point outward too.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "freeform/surface.hpp"
#include "model/mesh_io.hpp"

namespace inkline::freeform {

struct TessellationOptions {
    int bezier_segments = 16;     // per patch, along u and along v
    int primitive_segments = 128;  // around periodic directions (half along a sphere's colatitude or a tube)
};

struct Tessellation {
    TriangleMesh mesh;
    struct Grid {
        int nu = 0, nv = 0;
        std::size_t first_point = 0;  // grid point (i, j) at points[first_point + i * (nv + 1) + j]
        std::size_t first_cell = 0;   // cell (i, j) at cell_faces[first_cell + i * nv + j]
    };
    std::vector<Grid> grids;                                // per surface
    std::vector<glm::dvec3> points;                         // grid points before welding
    std::vector<std::array<std::uint32_t, 2>> cell_faces;   // per cell: its two triangles (or UINT32_MAX)
    std::size_t welded = 0;            // grid points merged into another
    std::size_t dropped = 0;           // collapsed triangles dropped
    std::size_t flipped_surfaces = 0;  // surfaces whose normal sign was turned to point outward

    // The point of the tessellation at surface s's (u, v) and the triangle it lies in; `other` is the
    // cell's second triangle (both may be UINT32_MAX where the cell collapsed).
    glm::dvec3 locate(const SurfaceList& surfaces, std::size_t s, glm::dvec2 uv, std::uint32_t& face,
                      std::uint32_t& other) const;
};

// Sets each surface's `sign` (outward normals). `where` names the source in errors.
Tessellation tessellate(SurfaceList& surfaces, const TessellationOptions& options, const std::string& where);

}  // namespace inkline::freeform
