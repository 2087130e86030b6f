// `inkline render SURFACES.{bpt,json}`: the flags of Elber's line art (src/freeform/) and the
// glue that adds its strokes to the drawing of the surfaces' tessellation.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/flags.hpp"
#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "freeform/lineart.hpp"
#include "model/mesh_io.hpp"

namespace inkline {

struct FreeformArgs {
    freeform::LineArtOptions options;
    freeform::DrawOptions draw;
    bool strokes = false;      // --strokes given: line art is drawn
    int given = 0;             // line-art flags given, --strokes included
    bool transparent = false, no_cull = false, open = false;
    std::vector<glm::dvec3> lights;  // the shared --light flags (app/flags.hpp), unit directions
    bool any() const { return given > 0 || transparent || no_cull || open; }
};
// The line-art flags, each value checked where it stands (a bad one is a usage error).
std::vector<Flag> freeform_flags(FreeformArgs& a);
bool is_freeform_model(const std::string& path);

class FreeformRender {
public:
    // Loads and tessellates the surfaces (inkline::Error naming the file on bad input). BadValue
    // when line-art flags are given without --strokes.
    FreeformRender(const std::string& path, const FreeformArgs& args);
    ~FreeformRender();
    const TriangleMesh& mesh() const;
    // With --strokes: grows the strokes for this camera's default isophote direction, selects and
    // draws them; appends the pieces to the drawing and prints a summary unless quiet.
    void add_strokes(const Camera& camera, Drawing& drawing, bool quiet);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
