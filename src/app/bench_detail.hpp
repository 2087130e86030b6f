// `inkline bench MODEL --detail=PX [--detail-method=multiscale|pm]`: the two detail-control
// methods along the bench's camera path (both, unless the method is named): build time and
// memory, then per frame the triangles kept, splits and collapses (pm), the adaptation's and the
// whole frame's time, the line density and the coherence between consecutive frames. Prints a
// Markdown table (also written to `markdown` when not empty).
#pragma once

#include <functional>
#include <string>

#include "app/flags.hpp"
#include "pipeline.hpp"

namespace inkline {

struct DetailBenchArgs {
    std::string name, path_note, markdown;
    const DetailFlags* detail = nullptr;
    bool both = true;  // --detail-method not given
    std::function<Camera(int frame)> camera;
    int frames = 60;
};

int run_detail_bench(const Model& model, const ViewOptions& base, const DetailBenchArgs& a);

}  // namespace inkline
