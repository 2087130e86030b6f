// libFuzzer targets for inkline's other parsers, one per build (FUZZ_PARSER): offsets (offset
// tables, style/offsets.hpp), style (JSON style files, style/style.hpp), bpt (Bezier patches) and
// surfaces (freeform JSON), both freeform/surface.hpp. The checks are in parser_checks.hpp (shared
// with the regression tests); a check that fails traps, so libFuzzer saves the input.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "parser_checks.hpp"

#ifndef FUZZ_PARSER
#error "define FUZZ_PARSER (offsets, style, bpt or surfaces)"
#endif
#ifndef FUZZ_STYLES_DIR
#define FUZZ_STYLES_DIR "styles"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string parser = FUZZ_PARSER;
    std::string problem;
    if (parser == "offsets") problem = inkline_fuzz::check_offsets(text);
    else if (parser == "style") problem = inkline_fuzz::check_style(text, FUZZ_STYLES_DIR);
    else if (parser == "bpt") problem = inkline_fuzz::check_bpt(text);
    else problem = inkline_fuzz::check_surfaces_json(text);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_%s: %s\n", FUZZ_PARSER, problem.c_str());
        __builtin_trap();
    }
    return 0;
}
