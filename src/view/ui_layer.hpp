// The panel (Dear ImGui) as a layer kept between frames: its draw data is rasterized into an
// offscreen texture only when it differs from the last one rasterized, and the texture is blended
// over each frame's drawing: on a software rasterizer the panel's quads cost more CPU than blending
// a texture, and that CPU is taken from the pipeline, though the panel rarely changes between
// frames (bench/results/view_fps.md, "the panel as a layer", holds the figures).
#pragma once

#include <cstddef>
#include <vector>

struct ImDrawData;

namespace inkline {

class UiLayer {
public:
    UiLayer() = default;
    UiLayer(const UiLayer&) = delete;
    UiLayer& operator=(const UiLayer&) = delete;
    ~UiLayer();
    // Takes this frame's draw data for a framebuffer of fb_w x fb_h pixels and rasterizes it into
    // the layer if it differs from the last taken (or the size changed); returns whether it did
    // (whether the panel looks different). Needs a current GL 3.3 context and ImGui's OpenGL3
    // backend initialised; the bound framebuffer and viewport are kept.
    bool update(ImDrawData* data, int fb_w, int fb_h);
    // Blends the layer over the bound framebuffer (of the size given to update()).
    void composite() const;
    std::size_t rasterized() const { return rasterized_; }  // times the draw data was rasterized
    void release();  // GL objects (before the context goes)

private:
    bool same_as_last(ImDrawData* data);
    void setup();
    unsigned fbo_ = 0, tex_ = 0, prog_ = 0, vao_ = 0;
    int w_ = 0, h_ = 0;
    int x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;  // pixels the layer covers (GL window coordinates)
    std::vector<unsigned char> last_;        // the draw data last rasterized, serialized
    std::vector<unsigned char> now_;         // this frame's, serialized (its storage kept)
    std::size_t rasterized_ = 0;
};

}  // namespace inkline
