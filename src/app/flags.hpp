// One definition a flag: every flag that more than one command takes (its name, the form and
// limits of its value, its error message and its help line) is declared here once, and each
// command lists the flags it takes in a FlagTable that parses its words and prints its --help.
//
// A hand-written table rather than CLI11 (Debian 12 has 2.1.2): CLI11 also reads `--key value`
// (so a word after a flag stops being the model) and formats its own messages and exit codes;
// keeping today's `--key=value` grammar and the one-line errors the tests pin would mean
// overriding most of it.
//
// Errors: a bad value throws BadValue "FLAG: problem" (exit 2, one line); a word that is no flag
// of the command, or a flag without its value, throws Usage (exit 2, with a pointer to the
// command's --help).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "detail/multiscale.hpp"
#include "pipeline.hpp"
#include "tone/tone.hpp"

namespace inkline {

// A bad command line (exit 2). `command` names the command whose --help to point at (empty: the
// overview).
struct Usage : std::runtime_error {
    explicit Usage(const std::string& what, std::string command = "")
        : std::runtime_error(what), command(std::move(command)) {}
    std::string command;
};

// A value a flag refuses ("--crease: expected an angle in [0, 180] degrees"): a usage error
// (exit 2) printed as that one line.
struct BadValue : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Flag {
    std::string name;   // "--crease"
    std::string value;  // the value's form in the help ("DEG"); empty: a switch without a value
    std::string help;   // one line (wrapped to the terminal's 100 columns)
    std::function<void(const std::string& value)> set;  // parses and stores; Error naming the flag
    std::string short_name = "";  // "-o": takes the next word as its value (as does bare `name`)
};

class FlagTable {
public:
    // `command`: "render"; `synopsis`: the usage line after "inkline"; `about`: help's first lines.
    FlagTable(std::string command, std::string synopsis, std::string about);
    // Starts a group of the help ("Camera"); the flags added next belong to it.
    FlagTable& group(const std::string& title);
    FlagTable& add(Flag flag);
    FlagTable& add(std::vector<Flag> flags);
    // Free text printed at the end of the help.
    FlagTable& note(const std::string& text);

    // Parses argv[first..] left to right: each flag's value is checked where it stands; the one
    // word that is not a flag goes to `model`. Returns false when -h/--help was asked for (the
    // help is then printed on stdout and nothing else is parsed).
    bool parse(int argc, char** argv, int first, std::string& model) const;
    // The same for a command that takes several models (render): every word that is no flag, in
    // order.
    bool parse(int argc, char** argv, int first, std::vector<std::string>& models) const;
    std::string help() const;
    const std::string& command() const { return command_; }

private:
    const Flag* find(const std::string& name) const;
    std::string command_, synopsis_, about_, notes_;
    std::vector<std::pair<std::string, std::vector<Flag>>> groups_;
};

// "inkline COMMAND ...; see 'inkline COMMAND --help'" for a usage error's second line.
std::string usage_line(const std::string& command);

// Value parsers, each naming the flag in its Error.
double parse_number(const std::string& flag, const std::string& s);  // finite
int parse_integer(const std::string& flag, const std::string& s, int lo, int hi);
glm::dvec3 parse_vec3(const std::string& flag, const std::string& s);

// The camera flags (--eye --target --up --fov --size --ortho --near), checked as they are read;
// unset ones are framed by make_camera.
struct CameraFlags {
    std::optional<glm::dvec3> eye, target, up;
    std::optional<double> fov, ortho, near;
    std::optional<int> width = 1024, height = 1024;
    // --camera: a camera of the model's file by name, or "frame"; empty: the file's first
    // perspective camera when no other camera flag is given.
    std::string file_camera;
};
std::vector<Flag> camera_flags(CameraFlags& camera);
// The camera of the flags; unset: framed (the whole model in view, fov 30, +Y up).
// Error "camera: ..." when eye, target and up make no camera.
Camera make_camera(const CameraFlags& flags, const MeshTopology& mesh);
// The same for a loaded model: a camera of its file (Model::cameras()) is the starting point that
// --camera names, or, with no camera flag at all, its first perspective camera; the other camera
// flags then override that camera's eye, target, up, fov. BadValue "--camera: ..." for a name the
// file does not have.
Camera make_camera(const CameraFlags& flags, const Model& model);

// Loads a model file as the commands do: tolerant, or strict with --strict; prints one warning
// line per kind of repair made ("inkline: warning: FILE: ...") on stderr, and with `progress` a
// progress line of the subdivision (app/progress.hpp: on a terminal only).
// `threads`: LoadOptions::threads.
Model load_model_file(const std::string& path, bool strict, double crease_degrees, int subdivide,
                      bool progress = true, int threads = 1);

// The shared flags, one definition each. (size_flag's help shows the size already set, if any.)
Flag size_flag(std::optional<int>& width, std::optional<int>& height);
Flag seed_flag(std::uint64_t& seed);
Flag crease_flag(double& degrees);
// The tone stage's line kinds (src/tone/), drawn by `render` (on the CPU) and `view` (in GLSL).
struct ToneKinds {
    bool dark = false, highlight = false;
    bool any() const { return dark || highlight; }
};
// --lines: mesh edge kinds (silhouette, crease, border), surface line kinds (suggestive, ...) and,
// where `tone` is given, tone-dark and tone-highlight (refused otherwise: a command without the
// tone stage); *given set when the flag was given (a style's kinds apply only when it was not).
Flag lines_flag(FeatureOptions& features, SurfaceLineOptions& surface, bool* given = nullptr, ToneKinds* tone = nullptr);
// Turns on exactly `kinds` (a style's "kinds", or --lines); tone kinds only where `tone` is given.
void set_line_kinds(const std::vector<LineKind>& kinds, FeatureOptions& features, SurfaceLineOptions& surface,
                    ToneKinds* tone = nullptr);
// --light=X,Y,Z, a world direction towards a light; each use adds one (tone lines, freeform shaders).
Flag light_flag(std::vector<glm::dvec3>& lights);
// Intersection lines are on by default for a scene of several objects (parts pressed into one
// another draw the curve where they meet, as in an assembly drawing; Blender's Line Art does the
// same), unless the kinds were chosen (--lines, a style's "kinds"). A single mesh keeps the
// default kinds: its crossings are more often modelling slips than edges meant to be seen.
void default_intersection_lines(FeatureOptions& features, const Model& model, bool kinds_chosen);
Flag suggestive_threshold_flag(SurfaceLineOptions& surface);
Flag ridge_threshold_flag(SurfaceLineOptions& surface);
// The tone stage's parameters (--tone-width, --tone-beta, --tone-dark, --tone-highlight, --specular,
// --toon-bands) and --base=none|toon (*toon_base set for toon). Each value is checked by range
// here; relations between them (c_l <= c_u) by tone::tone_options_error.
std::vector<Flag> tone_flags(tone::ToneOptions& options, bool& toon_base);
Flag finder_flag(FinderKind& kind);
Flag fraction_flag(double& share);
Flag first_view_flag(bool& first_full);
Flag visibility_flag(VisibilityMethod& method);
// --fast-buffer=PX: the fast visibility's depth buffer, long side in pixels.
Flag fast_buffer_flag(int& px);
// The fast visibility draws visible lines only: a one-line usage error when `hidden` lines are
// asked of it (`what`: the flag or setting that asked).
void check_fast_visibility(VisibilityMethod method, bool hidden, const std::string& what);
// The fast path's buffer size for a command drawing with `method`: `given_px` is --fast-buffer's
// value, 0 when not given (the default size). Given with another method it would be ignored
// without a word, so that is a usage error (BadValue).
int fast_buffer_px(int given_px, VisibilityMethod method);
Flag subdivide_flag(int& levels);
Flag strict_flag(bool& strict);
// --threads=N, the threads of each frame (ViewOptions::threads: the finder's facing pass and scan,
// the visibility; render's tone pass), 1 to kMaxThreads (more is a usage error, not a slow run);
// `unset` says the command's default in the help; *given set when the flag was given.
inline constexpr int kMaxThreads = 256;
// The machine's hardware threads, 1 to kMaxThreads (the commands' default).
int hardware_threads();
Flag threads_flag(int& threads, const std::string& unset, bool* given = nullptr);
Flag frames_flag(int& frames, const std::string& what, bool* given = nullptr);
Flag arc_flag(double& degrees, const std::string& what);  // help shows its default
Flag orbit_flag(bool& orbit, const std::string& help);
Flag jobs_flag(int& jobs, bool* given = nullptr);
Flag frame_rate_flag(double& fps, bool* given);
struct FrameRange;  // app/batch.hpp
Flag frame_range_flag(FrameRange& range);
Flag style_flag(std::string& style);
// Detail control (docs/detail.md): --detail=PX turns it on; --levels, --detail-method,
// --detail-ratio and --detail-depth tune it (and need --detail).
struct DetailFlags {
    double target_px = 0.0;  // 0: off (the drawing unchanged)
    std::optional<int> levels;
    std::string method = "multiscale";  // or "pm": the view-dependent progressive mesh
    // The target image area T of the progressive mesh's criterion: PX^2 square pixels.
    double target_area_px() const { return target_px * target_px; }
    std::optional<double> depth_exponent;
    std::optional<double> ratio;
    std::optional<MultiscaleFairing> fairing;
    bool smoothing_thin_guarded = false;  // --detail-smoothing=thin-guarded
    bool smoothing_given = false;
    std::string cache_dir;  // --cache: where the smoothed levels are kept (empty: not kept)
    std::vector<std::pair<std::string, double>> object_target_px;  // --detail-object=NAME=PX
    bool method_given = false;  // --detail-method
    MultiscaleOptions levels_options() const;
    // Usage error when a tuning flag comes without --detail.
    void check(const std::string& command) const;
};
std::vector<Flag> detail_flags(DetailFlags& detail);
Flag switch_flag(const std::string& name, bool& target, bool value_when_given, const std::string& help);
Flag text_flag(const std::string& name, const std::string& value, std::string& target, const std::string& help);

}  // namespace inkline
