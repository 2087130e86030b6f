// Feature lines for one view, found exhaustively (the reference finder).
// Takes MeshTopology + Camera; gives per-face facing, the silhouette/border/crease edges,
// the cusp vertices (three cases of Markosian et al. 97, Definition 3), and the edges chained
// into curves that stop at junctions and cusps.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "model/topology.hpp"

namespace inkline {

struct FeatureOptions {
    bool kinds[kLineKindCount] = {true, true, true};  // indexed by LineKind: which curves to chain
    bool wants(LineKind k) const { return kinds[int(k)]; }
};

enum class CuspCase : std::uint8_t {
    None = 0,
    FrontBackMeet = 1,    // exactly two silhouette edges, one front- and one back-facing
    ManySilhouettes = 2,  // more than two silhouette edges
    BorderEdge = 3,       // a silhouette vertex adjacent to a border edge
};

inline constexpr std::uint8_t kNoKind = 0xff;

struct FeatureCurve {
    LineKind kind = LineKind::Silhouette;
    std::vector<std::uint32_t> vertices;  // n+1 vertices for n edges (first == last if closed)
    std::vector<std::uint32_t> edges;
    bool closed = false;  // a loop whose start is an ordinary vertex (a loop from a junction back to it is open)
};

struct Features {
    std::vector<std::uint8_t> face_front;       // 1: eye strictly on the front side of the face
    std::vector<std::uint8_t> edge_kind;        // LineKind or kNoKind, per mesh edge
    std::vector<std::uint32_t> silhouette_edges;
    std::vector<std::uint32_t> border_edges;
    std::vector<std::uint32_t> crease_edges;    // creases that are not silhouettes
    std::vector<std::uint32_t> cusp_vertices;
    std::vector<CuspCase> cusp_cases;           // parallel to cusp_vertices
    std::vector<FeatureCurve> curves;           // only the requested kinds
};

// Exact facing of one face: orientation of the eye against the face's oriented plane (CGAL's
// filtered exact predicate); for an orthographic camera the sign of det[b-a, c-a, -f], exact.
// A face whose plane contains the eye (or the view direction) counts as not front-facing.
bool face_is_front(const MeshTopology& mesh, std::uint32_t face, const Camera& camera);

Features extract_features(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options = {});

}  // namespace inkline
