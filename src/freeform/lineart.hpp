// Interactive line art of freeform surfaces (Elber 99), the whole method behind one class.
// Pre-process (constructor, once): tessellation (for silhouettes and visibility), uniform point
// coverage, stroke growth, cone buckets over the Gauss map. Per view (draw): the cones that can
// contribute, the shader at each of their strokes, the portion s_i * psi_i of each stroke around
// its seed, and visibility of that portion against the tessellation of the opaque surfaces by ray
// tests (the paper used a z-buffer; we clip each stroke where it becomes hidden, to within a
// bisection tolerance). Gives pieces of kind LineKind::Freeform with their QI, in pixels.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "freeform/cones.hpp"
#include "freeform/strokes.hpp"
#include "freeform/surface.hpp"
#include "freeform/tessellate.hpp"
#include "model/topology.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline::freeform {

struct LineArtOptions {
    TessellationOptions tessellation;
    std::size_t points = 4000;       // r: strokes grown
    std::uint64_t seed = 1;          // point coverage
    StrokeOptions strokes;           // field and marching; length is scaled by stroke_length below
    double stroke_length = 0.06;     // stroke length limit, fraction of the bounding-box diagonal
    int cones = 50;                  // m
    BucketMode buckets = BucketMode::Redundant;
    bool closed = true;              // the surfaces bound a solid: cull back-facing cones/strokes
};

struct LineArtStats {
    std::size_t strokes = 0, cones = 0, bucket_entries = 0;
    double alpha_degrees = 0.0;
    double seconds_tessellate = 0.0, seconds_cover = 0.0, seconds_grow = 0.0, seconds_buckets = 0.0;
};

struct DrawStats {
    SelectStats select;
    std::size_t selected = 0, pieces = 0, ray_tests = 0;
    double seconds_select = 0.0, seconds_visibility = 0.0;
};

struct DrawOptions {
    Shader shader;
    bool cull = true;         // visit only contributing cones (false: every cone, same strokes)
    bool visibility = true;   // false: every stroke drawn as visible (all surfaces transparent)
};

class LineArt {
public:
    // Throws inkline::Error(where, ...) for surfaces that cannot be tessellated into a 2-manifold.
    // Grows options.points strokes (none when 0; grow() can do it later).
    LineArt(SurfaceList surfaces, const LineArtOptions& options, const std::string& where);
    // (Re)does the pre-process after the tessellation: coverage, strokes, cone buckets.
    void grow(const LineArtOptions& options);
    ~LineArt();

    const SurfaceList& surfaces() const { return surfaces_; }
    const Tessellation& tessellation() const { return tess_; }
    const std::vector<Stroke>& strokes() const { return strokes_; }
    ConeBuckets& buckets() { return *buckets_; }
    const LineArtStats& stats() const { return stats_; }
    ViewQuery query(const Camera& camera) const;

    // Freeform pieces for one view (visible ones with qi 0, hidden ones with their layer count).
    std::vector<Piece> draw(const Camera& camera, const DrawOptions& options, DrawStats* stats = nullptr);

    // Layers of opaque surface between the eye and the point of the tessellation under (surface, uv).
    int layers_at(const Camera& camera, std::uint32_t surface, glm::dvec2 uv) const;

private:
    SurfaceList surfaces_;
    LineArtOptions options_;
    Tessellation tess_;
    std::vector<Stroke> strokes_;
    std::vector<glm::dvec3> normals_, seeds_;
    std::unique_ptr<ConeBuckets> buckets_;
    MeshTopology occluders_;                  // tessellation of the opaque surfaces
    std::vector<std::uint32_t> occluder_face_;  // tessellation face -> occluder face (or kNoFace)
    std::unique_ptr<RayCaster> rays_;
    glm::dvec3 center_{0.0};
    double radius_ = 0.0;
    LineArtStats stats_;
};

}  // namespace inkline::freeform
