// Output stage: takes a finished Drawing (pieces with QI, in pixels) and gives SVG, PDF, PNG or
// JSON (schema of DESIGN.md). Files are written atomically: a temporary in the same directory,
// renamed onto the target only when complete.
#pragma once

#include <string>
#include <vector>

#include "core/drawing.hpp"
#include "style/strokes.hpp"

struct _cairo;  // cairo_t, without Cairo's header

namespace inkline {

enum class Format { Svg, Pdf, Png, Json };

// From `explicit_format` ("svg", "pdf", "png", "json") when non-empty, else from the extension of
// `path` (case-insensitive). Unknown: throws inkline::Error naming "--format" or the path.
Format output_format(const std::string& path, const std::string& explicit_format);

struct OutputOptions {
    bool hidden = false;       // draw hidden pieces (qi > 0) too
    double line_width = 0.0;   // visible line width in px; <= 0: max(1, 1.5 * height / 1024)
    bool keep_specks = false;  // SVG, PDF, PNG: keep strokes shorter than a pixel (--keep-specks)
};

// Pieces with fewer than two points or a non-finite point are never written. JSON keeps the
// pieces and their points exactly (an "object" name per polyline when the drawing has several
// objects; stats.specks_dropped: pieces that SVG, PDF and PNG of these options leave out).
// SVG, PDF and PNG draw strokes (drawing_strokes), clipped to the image grown by an image-sized
// margin on each side.
std::string drawing_to_json(const Drawing& drawing, const OutputOptions& options);
// One Inkscape layer (<g>) per line kind and QI level, hidden layers first, visible last; inside
// it, with several objects, a group per object labelled with its name; one <path> per stroke
// with class="KIND visible|hidden qiN", data-kind, data-qi and (several objects) data-object.
std::string drawing_to_svg(const Drawing& drawing, const OutputOptions& options);

// The strokes that SVG, PDF and PNG draw: chain_strokes (style/strokes.hpp) with its defaults
// (pieces that continue each other joined; lone specks shorter than a pixel dropped unless
// options.keep_specks, and counted in *specks_dropped).
std::vector<Stroke> drawing_strokes(const Drawing& drawing, const OutputOptions& options,
                                    std::size_t* specks_dropped = nullptr);

struct WriteSummary {
    std::size_t strokes = 0;         // paths drawn by SVG, PDF, PNG (the JSON's pieces are counted in stats)
    std::size_t specks_dropped = 0;  // pieces left out of them as specks
};

// Throws inkline::Error(path, reason) on failure; the target is then left untouched.
WriteSummary write_drawing(const Drawing& drawing, const std::string& path, Format format,
                           const OutputOptions& options);

// A base layer (Drawing::base) for the writers: painted over a Cairo context (cairo_t), and as an
// SVG Inkscape layer "base" holding the image as an inline PNG.
void paint_raster_layer(::_cairo* context, const RasterLayer& layer);
std::string svg_raster_layer(const RasterLayer& layer);

// Writes `content` to `path` atomically (same rules as write_drawing).
void write_text_file(const std::string& path, const std::string& content);

// Text for an XML attribute value (&, <, >, quotes and newlines escaped).
std::string xml_escape(const std::string& text);

// A scatter plot as SVG (drawn with Cairo): one labelled point per entry, x and y axes with ticks.
struct PlotPoint {
    double x = 0.0, y = 0.0;
    std::string label;
    int series = 0;  // colour
};
std::string scatter_plot_svg(const std::vector<PlotPoint>& points, const std::string& title,
                             const std::string& x_label, const std::string& y_label,
                             const std::vector<std::string>& series_names);

}  // namespace inkline
