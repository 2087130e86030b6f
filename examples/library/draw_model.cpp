// Draws a model with inkline's library: plain lines to one file, a style preset to another.
// Usage: draw_model MODEL OUT.svg [STYLED.png [STYLE]]
#include <cstdio>
#include <inkline/inkline.hpp>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: draw_model MODEL OUT.svg [STYLED.png [STYLE]]\n");
        return 2;
    }
    try {
        namespace ink = inkline::api;
        const ink::Model model = ink::Model::load(argv[1]);
        const ink::Camera camera = ink::Camera::framing(model, 800, 600);

        ink::DrawOptions options;
        options.hidden = true;  // hidden lines too, dashed by QI
        const ink::Drawing drawing = ink::draw(model, camera, options);
        drawing.write(argv[2]);
        std::size_t visible = 0, hidden = 0;
        for (const ink::Polyline& line : drawing.polylines()) (line.qi == 0 ? visible : hidden) += 1;
        std::printf("%s: %zu triangles, %zu visible and %zu hidden pieces (inkline %s)\n", argv[2],
                    model.triangles(), visible, hidden, ink::version().c_str());

        if (argc > 3) {
            ink::DrawOptions styled;
            styled.style = argc > 4 ? argv[4] : "sketchy";
            styled.styles_dir = INKLINE_PACKAGE_STYLES;
            ink::draw(model, camera, styled).write(argv[3]);
            std::printf("%s: style %s\n", argv[3], styled.style.c_str());
        }
    } catch (const inkline::api::Error& e) {
        std::fprintf(stderr, "draw_model: %s\n", e.what());
        return 1;
    }
    return 0;
}
