// libFuzzer target: the whole pipeline (features, crossings, both visibility methods) on small
// closed meshes and cameras made from the input (pipeline_input.hpp). Refusals are expected; a
// crash, a sanitizer report, a non-finite point, a negative QI or a hang is a finding.
#include "pipeline_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<inkline::View> views;
    inkline_fuzz::render_from_bytes(data, size, views);
    for (const auto& v : views)
        if (!inkline_fuzz::drawing_is_sane(v.drawing)) __builtin_trap();
    return 0;
}
