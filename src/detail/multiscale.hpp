// Detail control, multi-scale method (Ni, Jeong, Lee, Markosian, I3D 2006; seed 001): lines that
// show shape features of about a target size T in the image, fine ones near the eye, coarse ones
// far away. (A second method, progressive meshes, may join it: names say "multiscale".)
//
// Takes a Model (its MeshTopology and curvature). Gives, once per model (build_multiscale_levels),
// a sequence of smoothed copies M0..M(N-1) of the shape with its connectivity and their
// curvatures; then per view (MultiscaleSession) the shape blended per vertex between the two
// levels whose feature size brackets T, drawn by the unchanged pipeline (render_view's features,
// exact visibility, surface lines) on the blended geometry. docs/detail.md says how and why.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "pipeline.hpp"

namespace inkline {

// The fairing functional whose local minimizer predicts a vertex from its neighbourhood (GSS
// section 3): the umbrella (membrane) energy, the neighbours' centroid; or the second-order one
// (squared jumps of the gradient across edges, uniform weights), which keeps curved surfaces'
// volume and folds far fewer faces but smooths less per level (bench/results/multiscale.md).
enum class MultiscaleFairing { Umbrella, SecondOrder };

// Defaults measured on armadillo, bunny and elephant (bench/results/multiscale.md): with the
// umbrella functional the seed's r = 3/4 smooths too little for the density check; 1/2
// doubles the feature size per level, at the price of a few folded faces in the smoothest levels.
struct MultiscaleOptions {
    int levels = 4;        // N: M0 (the input) and N - 1 smoothed copies
    double ratio = 0.5;    // r: M_k keeps the detail of the first r^k n vertex splits (the seed: 3/4)
    double relax = 1.0;    // analysis: share of the way each ring vertex moves to its fairing minimizer
    double shrink_back = 0.0;  // analysis: then the same with this (negative) share (Taubin's mu)
    double spread = 0.5;   // synthesis: the same for the ring of each vertex split
    MultiscaleFairing fairing = MultiscaleFairing::Umbrella;
    // Then relaxation sweeps over each smoothed level (`spread` each, Gauss-Seidel in the order of
    // the positions; 8 for second-order): 4 take the umbrella's elephant to 0.49 of the plain
    // drawing's density growth (0.50 without) and fold fewer faces (bench/results/multiscale_order.md).
    int sweeps = 4;
    int tangential_sweeps = 0;  // then sweeps moving vertices along the surface only (32 for second-order)
    // Then a post-pass per level k >= 1 where smoothing > 0: (W + t_k L^order) x = p, L the
    // uniform Laplacian, t_k = smoothing * smoothing_growth^(k - 1), W a diagonal weight that spares
    // thin parts: with thin_guard > 0 a vertex where the shape is tau thick is smoothed with reach
    // min(sigma_k, thin_guard tau), sigma_k = L t_k^(1 / (2 order)) the level's own reach (W = 1
    // without). Off by default (docs/detail.md: meets both of the checks on armadillo only).
    double smoothing = 0.0;
    double smoothing_growth = 16.0;
    int smoothing_order = 2;
    double thin_guard = 0.0;
    // Called after each step of the pre-process (the model's curvature, the simplification, each
    // smoothed level): steps done and steps in all, for a progress line on long builds.
    std::function<void(int done, int total)> progress = {};
    // The steps `progress` counts in all: the model's curvature, the simplification, each level.
    int build_steps() const { return 2 + (levels > 1 ? levels - 1 : 0); }
};

// The smoothed levels. M0 is the model itself (its positions and Model::curvature(), exactly);
// levels 1..N-1 are stored here, per vertex 49 bytes a level (the seed needs 52): position (3
// floats), unit normal (octahedral, 2 floats), first principal direction (its angle in a frame
// fixed by the normal, 1 float), k1, k2, C (4 floats) and a validity byte. Flat arrays, level k at
// [(k - 1) V, k V).
struct MultiscaleLevels {
    int levels = 1;                  // N actually built (1: only M0; `note` says why)
    double ratio = 0.5;
    double feature_size = 0.0;       // L: mean edge length of M0
    std::size_t vertices = 0;        // V
    std::size_t collapses = 0;       // n: edge collapses down to the base mesh
    std::size_t base_vertices = 0;   // V - n
    std::vector<glm::vec3> position;
    std::vector<glm::vec2> normal_oct;
    std::vector<float> dir1_angle;
    std::vector<float> k1, k2;
    std::vector<std::array<float, 4>> dcurv;
    std::vector<std::uint8_t> valid;
    // Per level 0..N-1, over the valid vertices: a check of the smoothing. (The mean is pulled up by
    // the few folds of the smoothest levels: docs/detail.md.)
    std::vector<double> mean_abs_k1, median_abs_k1;
    // Where some level self-intersects the blend may too: views then find the blend's
    // self-intersections anew (exact, slower); else they are taken as none.
    bool levels_self_intersect = false;
    std::string note;                // empty, or why fewer levels than asked were built
    double seconds = 0.0;            // the pre-process's time, with
    double seconds_model = 0.0;      // the model's curvature and self-intersections (if not yet computed)
    std::size_t bytes() const;       // of the arrays above (the levels' memory)

    // Level k >= 1 of vertex v, decoded.
    glm::vec3 normal(int k, std::size_t v) const;
    glm::vec3 dir1(int k, std::size_t v) const;
    std::size_t at(int k, std::size_t v) const { return std::size_t(k - 1) * vertices + v; }
};

// The pre-process (section 3 of the seed, after Guskov, Sweldens, Schroder 1999): OpenMesh's
// half-edge collapses with the Decimater's legality rules, shortest edge first (so that every stage of the simplification has about
// uniform edge lengths), down to a base mesh, recording per collapse the removed vertex's ring
// and the detail coefficients of it and its ring (actual position minus the position the local
// umbrella fairing predicts); then M_k is rebuilt by vertex splits from the base mesh, adding
// the detail back only for the first r^k n splits. Curvature of each level by estimate_curvature.
// A mesh OpenMesh refuses (a non-manifold vertex), or one of which fewer than half the vertices
// can be collapsed (too small, borders everywhere), gets only M0 and a `note`.
MultiscaleLevels build_multiscale_levels(const Model& model, const MultiscaleOptions& options = {});

// `options` turned into the thin-guarded setting (`--detail-smoothing=thin-guarded`): the
// second-order functional at r = 3/4 with its sweeps, then the implicit post-pass with the thin
// guard. The one setting that meets both of issue 43's checks on armadillo (M3's mean |k1| 0.80 of
// M0's, density growth 0.43 of the plain drawing's; bench/results/multiscale.md); `keep_ratio` and
// `keep_fairing` leave a ratio or functional the user chose.
MultiscaleOptions thin_guarded(MultiscaleOptions options, bool keep_ratio = false, bool keep_fairing = false);

// The positions of level k (k = 0: the model's own; k >= 1: the stored floats, widened).
std::vector<glm::dvec3> level_positions(const Model& model, const MultiscaleLevels& levels, int k);

struct MultiscaleViewOptions {
    double target_px = 4.0;  // T: features of about this size in the image
    // Depth-dependent target (seed section 5, Figure 3): T * (d / d_ref)^depth_exponent with d_ref
    // the distance of the model's centre. 0: constant T (the seed's results); > 0: far surfaces
    // coarser still (depth cueing); -1: every vertex at the level of the centre (detail fixed on
    // the object, as without detail control but smoothed); between -1 and 0: Figure 3's "between".
    double depth_exponent = 0.0;
    // Per object of a scene (MeshTopology::object_names): its own T (the seed's "finer features
    // for important objects"); objects not named take target_px.
    std::vector<std::pair<std::string, double>> object_target_px = {};
};

// The names in `options.object_target_px` that `mesh` has no object of ("" when all are there).
std::string unknown_detail_objects(const MeshTopology& mesh, const MultiscaleViewOptions& options);

// Per vertex level for a view: l = log2(d / d0), d0 = F L / T (F the camera's focal length in
// pixels, so L at distance d0 projects to T pixels), clamped to [0, N - 1]; orthographic views
// one level for the whole model (L's projection, the same everywhere) or per object with
// per-object targets. A vertex shared by two objects takes the first object's target.
void multiscale_vertex_levels(const Model& model, const MultiscaleLevels& levels, const Camera& camera,
                              const MultiscaleViewOptions& options, std::vector<float>& out);

// Views of a model with detail control: per view the blend's positions move a working copy of the
// model (its ray-test index refitted, not rebuilt), n.v, kr and D_w kr are blended between the
// levels, and a ViewSession draws silhouettes, borders and creases (of M0) and the surface lines
// on the blended geometry with the exact visibility. Storage is reused from view to view.
class MultiscaleSession {
public:
    MultiscaleSession(const Model& model, const MultiscaleLevels& levels, const ViewOptions& options,
                      const MultiscaleViewOptions& view_options);
    ~MultiscaleSession();
    MultiscaleSession(const MultiscaleSession&) = delete;
    MultiscaleSession& operator=(const MultiscaleSession&) = delete;

    // The drawing of one view (valid until the next call). Its stats' seconds_features include
    // the blend (levels, positions, index refit).
    View& render(Camera camera);
    const std::vector<float>& vertex_levels() const { return level_; }
    const Model& blended() const { return *blended_; }
    double seconds_blend() const { return seconds_blend_; }
    void set_target(double target_px) { view_options_.target_px = target_px; }

private:
    void blend(const Camera& camera);
    const Model* model_;
    const MultiscaleLevels* levels_;
    MultiscaleViewOptions view_options_;
    std::unique_ptr<Model> blended_;
    std::unique_ptr<ViewSession> session_;
    // The blend's self-intersections when they are known without a search: M0's when there is one
    // level, none when no level has any; else null (Model::move_vertices finds them).
    std::unique_ptr<SelfIntersections> known_pierced_;
    const CurvatureField* surface_field_ = nullptr;  // M0's, when surface lines are drawn
    std::vector<float> level_;
    std::vector<glm::dvec3> positions_;
    ViewCurvature view_;
    double seconds_blend_ = 0.0;
};

}  // namespace inkline
