// The preview window's drawing in OpenGL: the line quads (antialiased, hidden ones grey and dashed
// by QI) or the stylized drawing as a texture, optionally over flat-shaded triangles of the model;
// and the back buffer saved as a PNG. Needs a current GL 3.3 core context for its whole life.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/camera.hpp"
#include "model/topology.hpp"
#include "view/line_mesh.hpp"

namespace inkline {

class GlScene {
public:
    explicit GlScene(const MeshTopology& mesh);  // the shading's triangles, uploaded on first use
    ~GlScene();
    GlScene(const GlScene&) = delete;
    GlScene& operator=(const GlScene&) = delete;

    // The stylized drawing changed: it is uploaded at the next draw() that shows it.
    void image_changed() { image_new_ = true; }
    // Clears the back buffer and draws the view seen from `camera` (its size is the viewport):
    // the model's triangles when `shading`, then `image` (the stylized drawing, camera-sized
    // Cairo RGB24 pixels) when not null, else the line quads. `underlay`, when given, draws
    // an opaque image in place of the shading (the tone pass: tone_pass.hpp).
    void draw(const Camera& camera, bool shading, const std::vector<LineVertex>& lines,
              const std::vector<std::uint32_t>* image, const std::function<void()>& underlay = {});

private:
    void upload_mesh();
    void draw_shading(const Camera& camera);
    void draw_image(const Camera& camera, const std::vector<std::uint32_t>& image);
    void draw_lines(const Camera& camera, const std::vector<LineVertex>& lines);

    const MeshTopology& mesh_;
    unsigned line_prog_ = 0, mesh_prog_ = 0, image_prog_ = 0, image_tex_ = 0;
    unsigned line_vao_ = 0, line_vbo_ = 0, mesh_vao_ = 0, mesh_bufs_[2] = {0, 0};
    std::size_t line_capacity_ = 0;  // bytes allocated in line_vbo_
    bool image_new_ = false;
};

// The back buffer (w x h pixels) as a PNG at `path`, written atomically; throws inkline::Error.
void save_screenshot(const std::string& path, int w, int h);

}  // namespace inkline
