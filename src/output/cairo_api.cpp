#include "output/cairo_api.hpp"

#include "core/shared_library.hpp"

namespace inkline {
namespace {

CairoApi load_cairo() {
    static const std::string kLibrary = "libcairo.so.2";
    void* library = open_library(kLibrary, "PDF and PNG output, brushes and raster layers need Cairo");
    CairoApi api;
#define INKLINE_CAIRO_LOAD(name) \
    api.name = reinterpret_cast<decltype(api.name)>(library_symbol(library, kLibrary, "cairo_" #name));
    INKLINE_CAIRO_FUNCTIONS(INKLINE_CAIRO_LOAD)
#undef INKLINE_CAIRO_LOAD
    return api;
}

}  // namespace

const CairoApi& cairo_api() {
    static const CairoApi api = load_cairo();
    return api;
}

}  // namespace inkline
