// The tone stage (src/tone/, seed 002) in GLSL for the preview window, as the paper runs it: pass 1
// renders the tone image (diffuse from the lights) and the separate specular channel into a float
// texture; a separable Gaussian of size w blurs both; a fragment pass fits the 3 x 3 least-squares
// quadratic at each pixel (the constant 6 x 9 matrix H as a uniform), searches toward the ridge
// (steps, beta), and composites dark lines (black) and highlight lines (white) with the opacity of
// section 3.3 over the toon base coat (or white). The same parameters and the same arithmetic as
// the CPU pass (tone::ToneOptions, ridges.cpp), in float: per-pixel lines, not traced polylines.
//
// Takes: the model's MeshTopology (read at construction and when its crease angle changes: the
// corner normals), a Camera (its size is the texture's), ToneOptions (lights non-empty: world
// directions) and which layers to show. Gives: a texture of the camera's size (RGBA8, GL rows
// bottom-up) that the scene draws under the object-space lines. Needs a current GL 3.3 core
// context for its whole life.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "model/topology.hpp"
#include "tone/tone.hpp"

namespace inkline {

// What the pass composites (each a panel toggle).
struct ToneLayers {
    bool dark = true;       // dark lines (valleys of the tone)
    bool highlight = true;  // highlight lines (ridges of the tone and of the specular channel)
    bool base = true;       // the toon base coat under them (else white)
};

// A light as two angles in the camera's frame, so that it turns with the view as the CPU pass's
// default headlight does: azimuth about the camera's up axis from the view direction toward the
// eye (positive to the right), elevation above the camera's horizontal plane.
struct LightAngles {
    double azimuth_deg = 0.0, elevation_deg = 0.0;
};
glm::dvec3 light_direction(const Camera& camera, const LightAngles& angles);  // unit world direction
LightAngles light_angles(const Camera& camera, const glm::dvec3& direction);  // the inverse (direction != 0)

// Where the pass runs: in GLSL, or on the CPU (tone::render_tone's stages on `threads`, its image
// uploaded). Auto: the CPU where GL is a software renderer (llvmpipe, softpipe, SwiftShader: a
// machine without a GPU), which runs the C++ pass several times faster than the shaders.
enum class TonePassMode { Auto, Glsl, Cpu };

class TonePass {
public:
    explicit TonePass(const MeshTopology& mesh, TonePassMode mode = TonePassMode::Auto, int threads = 1);
    bool on_cpu() const { return cpu_; }
    ~TonePass();
    TonePass(const TonePass&) = delete;
    TonePass& operator=(const TonePass&) = delete;

    // Draws the tone pass's image for `camera` over the whole of framebuffer 0 (opaque; viewport
    // the camera's size), running the passes again only when camera, options or layers differ
    // from the last run's. Options must be valid (tone_options_error empty) with at least one light.
    void draw(const Camera& camera, const tone::ToneOptions& options, const ToneLayers& layers);

    // The last run's time per pass (each finished before the next: glFinish), seconds.
    struct Times {
        double shade = 0.0, blur = 0.0, ridges = 0.0;
        double total() const { return shade + blur + ridges; }
    };
    const Times& last_times() const { return times_; }
    const Times& summed_times() const { return sum_; }  // over every run
    std::size_t runs() const { return runs_; }          // times the passes ran

private:
    void run(const Camera& camera, const tone::ToneOptions& options, const ToneLayers& layers);
    void upload_mesh();
    void resize(int w, int h);
    void shade(const Camera& camera, const tone::ToneOptions& options);
    void blur(double width);
    void ridges(const tone::ToneOptions& options, const ToneLayers& layers);
    void run_cpu(const Camera& camera, const tone::ToneOptions& options, const ToneLayers& layers);

    const MeshTopology& mesh_;
    double uploaded_crease_ = -1.0;  // the crease angle the corner normals were made with
    unsigned shade_prog_ = 0, blur_prog_ = 0, ridge_prog_[2] = {0, 0}, composite_prog_ = 0, copy_prog_ = 0;
    unsigned mesh_vao_ = 0, mesh_bufs_[2] = {0, 0}, empty_vao_ = 0;  // vertices (position, normal), indices
    std::size_t index_count_ = 0;
    // shaded: tone, specular, covered (float); ping, blurred: the blur's two passes (tone,
    // specular); lines: dark and highlight opacity; result: the composite (RGBA8).
    unsigned shaded_tex_ = 0, ping_tex_ = 0, blurred_tex_ = 0, lines_tex_ = 0, result_tex_ = 0, depth_rb_ = 0;
    unsigned shade_fbo_ = 0, ping_fbo_ = 0, blurred_fbo_ = 0, lines_fbo_ = 0, result_fbo_ = 0;
    int w_ = 0, h_ = 0;
    Times times_, sum_;
    std::size_t runs_ = 0;
    std::vector<double> last_key_;  // camera, options and layers of the texture's run
    // The CPU pass: its mesh normals (made for crease angle cpu_crease_), its working storage
    // (kept, so that a run allocates nothing new) and the composite uploaded into result_tex_.
    bool cpu_ = false;
    int threads_ = 1;
    double cpu_crease_ = -1.0;
    tone::ToneMesh cpu_normals_;
    tone::ToneResult cpu_result_;
    std::vector<std::uint32_t> cpu_pixels_;
};

}  // namespace inkline
