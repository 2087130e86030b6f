// Cairo, opened at its first use (core/shared_library.hpp) rather than linked: PDF and PNG output,
// stylized drawings' brushes, the base layer's inline PNG and the bench's plots need it; an SVG or
// JSON render does not, and does not pay for loading Cairo's 14 libraries. Takes nothing; gives
// the Cairo functions inkline calls, as `cairo_api().move_to(c, x, y)` for cairo_move_to. The
// first call opens libcairo.so.2 (throws inkline::Error naming it when it cannot).
#pragma once

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

namespace inkline {

// Each name, once: the table's members and their loading both come from this list.
#define INKLINE_CAIRO_FUNCTIONS(X) \
    X(arc) \
    X(close_path) \
    X(create) \
    X(destroy) \
    X(fill) \
    X(format_stride_for_width) \
    X(get_line_width) \
    X(image_surface_create) \
    X(image_surface_create_for_data) \
    X(image_surface_create_from_png) \
    X(image_surface_get_data) \
    X(image_surface_get_height) \
    X(image_surface_get_stride) \
    X(image_surface_get_width) \
    X(line_to) \
    X(mask_surface) \
    X(matrix_init) \
    X(move_to) \
    X(paint) \
    X(paint_with_alpha) \
    X(pattern_create_for_surface) \
    X(pattern_destroy) \
    X(pattern_set_extend) \
    X(pattern_set_filter) \
    X(pattern_set_matrix) \
    X(pdf_surface_create_for_stream) \
    X(pop_group_to_source) \
    X(push_group) \
    X(restore) \
    X(rotate) \
    X(save) \
    X(select_font_face) \
    X(set_dash) \
    X(set_fill_rule) \
    X(set_font_size) \
    X(set_line_cap) \
    X(set_line_join) \
    X(set_line_width) \
    X(set_source) \
    X(set_source_rgb) \
    X(set_source_rgba) \
    X(set_source_surface) \
    X(show_text) \
    X(status) \
    X(status_to_string) \
    X(stroke) \
    X(surface_destroy) \
    X(surface_finish) \
    X(surface_flush) \
    X(surface_mark_dirty) \
    X(surface_status) \
    X(surface_write_to_png_stream) \
    X(svg_surface_create_for_stream) \
    X(text_extents) \
    X(translate) \

struct CairoApi {
#define INKLINE_CAIRO_MEMBER(name) decltype(&::cairo_##name) name = nullptr;
    INKLINE_CAIRO_FUNCTIONS(INKLINE_CAIRO_MEMBER)
#undef INKLINE_CAIRO_MEMBER
};

// Loaded once, on the first call (thread-safe).
const CairoApi& cairo_api();

}  // namespace inkline
