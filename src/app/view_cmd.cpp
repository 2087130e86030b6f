// `inkline view MODEL ...`: parses the flags (camera, lines, finder and visibility as `render`)
// and opens the preview window (src/view/).
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "app/cli.hpp"
#include "core/error.hpp"
#include "style/style.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "view/viewer.hpp"

namespace inkline {

int run_view(int argc, char** argv) {
    ViewerOptions o;
    std::string model_path;
    std::map<std::string, std::string> camera;
    double crease = 40.0;
    bool frames_given = false;
    // A window follows one camera path: its randomized finder starts from an exhaustive view by
    // default (then follows it exactly), since a first view with holes keeps them, and each hole
    // leaves a cluster inconsistent, decided by a ray test per piece.
    o.view.finder.first_full = true;
    // Frame coherence on by default: that first view, then the silhouette followed from view to
    // view (exact, so the window still draws what `render` writes, and cheaper than a scan while
    // the camera moves a few degrees a frame). The visibility of a large view on two threads where
    // there are two cores (the same drawing).
    o.view.finder.kind = FinderKind::Randomized;
    o.view.finder.coherence = true;
    o.view.threads = std::thread::hardware_concurrency() >= 2 ? 2 : 1;
    for (int i = 2; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--hidden") { o.hidden = true; continue; }
        if (arg == "--no-walk") { o.view.walk = false; continue; }
        if (arg == "--orbit") { o.orbit = true; continue; }
        if (arg == "--fps") { o.fps = true; continue; }
        if (arg == "--shading") { o.shading = true; continue; }
        if (arg == "--no-panel") { o.panel = false; continue; }
        if (arg == "--no-coherence") { o.view.finder.coherence = false; continue; }
        if (arg == "--screenshot-ui") { o.screenshot_ui = true; continue; }
        if (arg == "--recall") { o.recall = true; continue; }
        std::string key, value;
        if (!split_option(arg, model_path, key, value)) continue;
        const auto integer = [&](int lo, int hi) {
            const double n = parse_number(key, value);
            if (n < lo || n > hi || n != std::floor(n))
                throw Error(key, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
            return int(n);
        };
        if (key == "--eye" || key == "--target" || key == "--up" || key == "--fov" || key == "--size" ||
            key == "--ortho" || key == "--near")
            camera[key] = value;
        else if (key == "--subdivide") o.subdivide = integer(0, 6);
        else if (key == "--threads") o.view.threads = integer(1, 64);
        else if (key == "--in-flight") o.in_flight = integer(1, 2);
        else if (key == "--frames") o.frames = integer(1, 1000000), frames_given = true;
        else if (key == "--arc") {
            o.arc = parse_number(key, value);
            if (!(o.arc > 0.0 && o.arc <= 3600.0)) throw Error(key, "expected degrees in (0, 3600]");
        } else if (key == "--screenshot") {
            if (value.empty()) throw Error(key, "expected a file name");
            o.screenshot = value;
        } else if (key == "--style") {
            load_style(value);  // a bad style file fails before the window opens
            o.style = value;
        } else if (key == "--export") {
            if (value.empty()) throw Error(key, "expected a file name");
            output_format(value, "");  // refuse an unknown format before any work
            o.export_path = value;
        } else if (key == "--crease") {
            crease = parse_number(key, value);
            if (crease < 0.0 || crease > 180.0) throw Error(key, "expected an angle in [0, 180] degrees");
        } else if (key == "--visibility") {
            if (value == "appel") o.view.visibility = VisibilityMethod::Appel;
            else if (value == "rays") o.view.visibility = VisibilityMethod::Rays;
            else throw Error(key, "unknown method '" + value + "' (expected appel or rays)");
        } else if (key == "--finder") {
            if (value == "exhaustive") o.view.finder.kind = FinderKind::Exhaustive;
            else if (value == "randomized") o.view.finder.kind = FinderKind::Randomized;
            else throw Error(key, "unknown finder '" + value + "' (expected exhaustive or randomized)");
        } else if (key == "--fraction") {
            o.view.finder.fraction = parse_number(key, value);
            if (!(o.view.finder.fraction > 0.0 && o.view.finder.fraction <= 1.0))
                throw Error(key, "expected a share in (0, 1]");
        } else if (key == "--first-view") {
            if (value == "exhaustive") o.view.finder.first_full = true;
            else if (value == "random") o.view.finder.first_full = false;
            else throw Error(key, "unknown first view '" + value + "' (expected exhaustive or random)");
        } else if (key == "--seed") {
            o.view.finder.seed = std::uint64_t(integer(0, 2147483647));
        } else if (key == "--lines") {
            for (auto& k : o.view.features.kinds) k = false;
            std::stringstream ss(value);
            for (std::string name; std::getline(ss, name, ',');) {
                LineKind kind;
                if (!parse_line_kind(name, kind))
                    throw Error(key, "unknown line kind '" + name + "' (expected silhouette, crease, border)");
                o.view.features.kinds[int(kind)] = true;
            }
        } else
            throw Usage("unknown option '" + key + "'");
    }
    if (model_path.empty()) throw Usage("no model given");
    if (!frames_given && (o.orbit || !o.screenshot.empty() || o.fps || !o.export_path.empty()))
        throw Usage("--orbit, --screenshot, --export and --fps drive the window for --frames=N frames");
    if (!camera.count("--size")) camera["--size"] = "1024x768";
    o.model_path = model_path;
    Model model = Model::load(model_path, crease, o.subdivide);
    const Camera home = camera_from_flags(camera, model.topology());
    return run_viewer(model, home, o);
}

}  // namespace inkline
