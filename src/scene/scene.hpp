// Scene loading through Assimp, for every format Assimp reads that inkline's own parsers
// (model/mesh_io: OBJ, OFF, PLY, STL) do not: glTF 2.0 (.gltf with its .bin, .glb), FBX, Collada
// .dae, 3DS, .blend, X3D and the rest.
// Takes a file path; gives one TriangleMesh of every mesh instance placed by its node's world
// transform (the whole parent chain; a mesh used by several nodes once per node; a mirroring
// transform, negative determinant, flips the winding so normals stay outward), in the file's own
// axes (no axis conversion: glTF's +Y up stays +Y), with a per-face object id and the objects'
// names (one object per node that holds meshes), repaired as load_mesh repairs (repair_mesh); and
// the file's cameras in world coordinates. Throws inkline::Error("<file>: <problem>") for anything
// it cannot read (truncated or inconsistent files, missing buffers, out-of-range indices, NaN in
// transforms, cyclic or deeper than kMaxNodeDepth node graphs, scenes without faces).
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "model/mesh_io.hpp"

namespace inkline {

// A camera of the file, placed by its node's world transform. glTF and the formats Assimp maps
// alike look down the node's local -Z with local +Y up.
struct SceneCamera {
    std::string name;
    glm::dvec3 eye{0.0}, target{0.0, 0.0, -1.0}, up{0.0, 1.0, 0.0};
    bool orthographic = false;
    double fov_deg = 0.0;       // perspective: full vertical field of view
    double ortho_height = 0.0;  // orthographic: world height that fills the image
    double aspect = 0.0;        // width / height the file asks for (0: not given)
    // The inkline camera for an image of width x height pixels (throws inkline::Error naming the
    // camera when its frame is degenerate).
    Camera to_camera(int width, int height) const;
};

struct Scene {
    TriangleMesh mesh;                 // mesh.face_object and mesh.object_names filled
    std::vector<SceneCamera> cameras;  // in file order
};

// Node graphs deeper than this are refused (real files nest a few dozen levels).
inline constexpr int kMaxNodeDepth = 256;

// True for a path that load_scene reads: an extension Assimp knows that is not OBJ, OFF, PLY or STL.
bool is_scene_file(const std::string& path);

Scene load_scene(const std::string& path, const LoadOptions& options = {});

}  // namespace inkline
