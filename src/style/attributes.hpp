// Per-point attributes of the pieces of a view, for width rules by depth and by lighting
// (Markosian et al. 97, section 5: "the width of the stroke can be made to vary with lighting
// computed at the polyline vertices"). Takes the view's pieces and where they lie on the mesh
// (visibility's EdgeSpans: piece point 0 is the start of span 0, point k + 1 the end of span k);
// gives each point's camera depth and Lambertian tone, the normal at a point being the mean of
// the normals of its edge's faces, the light at the camera or a chosen direction.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "model/topology.hpp"
#include "style/strokes.hpp"
#include "visibility/visibility.hpp"

namespace inkline {

// A piece whose spans do not match its points (size + 1) gets empty vectors.
PointAttributes point_attributes(const MeshTopology& mesh, const Camera& camera, const Drawing& drawing,
                                 const std::vector<std::vector<EdgeSpan>>& spans, bool light_at_camera,
                                 const glm::dvec3& light);

}  // namespace inkline
