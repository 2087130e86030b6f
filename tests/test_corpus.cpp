// Corpus test: every model of Debian's assimp-testmodels (/usr/share/assimp/models) that inkline
// reads by extension (its own OBJ/OFF/PLY/STL parsers, or Assimp for the rest) is loaded with the
// default, tolerant loading and drawn from the framing camera, each in a child process with a time
// limit. Each must either give a drawing with visible lines or be refused with one line naming a
// defect; no crash, no hang. The refused files and their reasons are tests/corpus.md, compared
// here line for line, so that a file that stops drawing (or is refused for another reason) shows.
// INKLINE_UPDATE_CORPUS=1 rewrites tests/corpus.md from this run.
#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "pipeline.hpp"
#include "scene/scene.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kModels = "/usr/share/assimp/models";
constexpr double kSecondsPerFile = 20.0;           // a file still loading or drawing then has hung
constexpr std::uintmax_t kMaxBytes = 20u << 20;    // larger files are skipped (none in the package today)

// Files not tried, with the reason (listed in tests/corpus.md as skipped).
// (IFC/AC14-FZK-Haus.ifc was, for a hang taken for a slow self-intersection search: a NaN edge
// cut from a rounded construction stopped the visibility's curve cutting; it draws in seconds now.)
const std::map<std::string, std::string> kSkipped = {};

std::string lower_ext(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

bool readable(const fs::path& p) {
    const std::string e = lower_ext(p);
    return e == ".obj" || e == ".off" || e == ".ply" || e == ".stl" || inkline::is_scene_file(p.string());
}

// In the child: load, draw, and say how it went in one line.
std::string draw_one(const fs::path& p) {
    try {
        const inkline::Model m = inkline::Model::load(p.string(), inkline::LoadOptions{});
        const inkline::Camera cam = inkline::Camera::framing(m.topology().bounds, 400, 400);
        const inkline::View v = inkline::render_view(m, cam);
        std::size_t visible = 0;
        for (const auto& piece : v.drawing.pieces) visible += piece.qi == 0;
        if (visible == 0) return "empty drawing";
        return "drawn";
    } catch (const inkline::Error& e) {
        std::string msg = e.what();
        const std::string prefix = p.string() + ": ";
        if (msg.rfind(prefix, 0) != 0 || msg.find('\n') != std::string::npos) return "bad message: " + msg;
        return "refused: " + msg.substr(prefix.size());
    } catch (const std::exception& e) {
        return std::string("not an inkline::Error: ") + e.what();
    }
}

// Runs draw_one in a child process; "timeout" or "crashed (signal N)" when it does not answer.
std::string run_isolated(const fs::path& p) {
    int fds[2];
    if (pipe(fds) != 0) return "pipe failed";
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        const std::string line = draw_one(p) + "\n";
        (void)!write(fds[1], line.data(), line.size());
        _exit(0);
    }
    close(fds[1]);
    std::string out;
    const auto t0 = std::chrono::steady_clock::now();
    char buf[4096];
    while (true) {
        const double left = kSecondsPerFile - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (left <= 0) {
            kill(pid, SIGKILL);
            waitpid(pid, nullptr, 0);
            close(fds[0]);
            return "timeout";
        }
        pollfd pfd{fds[0], POLLIN, 0};
        if (poll(&pfd, 1, int(left * 1000) + 1) <= 0) continue;
        const ssize_t n = read(fds[0], buf, sizeof buf);
        if (n <= 0) break;
        out.append(buf, std::size_t(n));
    }
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) return "crashed (signal " + std::to_string(WTERMSIG(status)) + ")";
    if (!out.empty() && out.back() == '\n') out.pop_back();
    return out.empty() ? "no answer" : out;
}

// The table of tests/corpus.md: "| file | reason |" rows under the header.
std::string table(const std::map<std::string, std::string>& refused, std::size_t tried, std::size_t drawn) {
    std::ostringstream s;
    s << "# Corpus: assimp-testmodels\n\n"
         "Every model of Debian's `assimp-testmodels` that inkline reads by extension, loaded tolerantly and\n"
         "drawn from the framing camera by `tests/test_corpus.cpp` (one child process per file, "
      << int(kSecondsPerFile)
      << " s each).\n"
         "Files that are not drawn are listed below with the reason; the test compares this table with its\n"
         "run, so a file that stops drawing, or is refused for another reason, fails it. Rewrite after a\n"
         "deliberate change: `INKLINE_UPDATE_CORPUS=1 build/tests/test_corpus`.\n\n"
      << "Tried: " << tried << " files; drawn: " << drawn << "; refused or skipped: " << refused.size() << ".\n\n"
      << "| file | reason |\n| --- | --- |\n";
    for (const auto& [file, why] : refused) {
        std::string w = why;
        std::replace(w.begin(), w.end(), '|', '/');
        s << "| " << file << " | " << w << " |\n";
    }
    return s.str();
}

}  // namespace

TEST(Corpus, AssimpTestModelsDrawOrAreRefusedForADefect) {
    if (!fs::is_directory(kModels)) GTEST_SKIP() << "assimp-testmodels is not installed";
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(kModels))
        if (e.is_regular_file() && readable(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::map<std::string, std::string> refused;
    std::size_t drawn = 0;
    for (const fs::path& p : files) {
        const std::string rel = fs::relative(p, kModels).string();
        if (const auto skip = kSkipped.find(rel); skip != kSkipped.end()) {
            refused[rel] = skip->second;
            continue;
        }
        if (fs::file_size(p) > kMaxBytes) {
            refused[rel] = "skipped: " + std::to_string(fs::file_size(p) >> 20) + " MB, over the corpus limit";
            continue;
        }
        const std::string r = run_isolated(p);
        if (r == "drawn") {
            ++drawn;
            continue;
        }
        // Only a one-line refusal is an answer; anything else is a failure of inkline's.
        EXPECT_EQ(r.rfind("refused: ", 0), 0u) << rel << ": " << r;
        refused[rel] = r.rfind("refused: ", 0) == 0 ? r.substr(9) : r;
    }
    const std::string now = table(refused, files.size(), drawn);
    const fs::path md = fs::path(INKLINE_SOURCE_DIR) / "tests" / "corpus.md";
    if (std::getenv("INKLINE_UPDATE_CORPUS")) {
        std::ofstream(md) << now;
        return;
    }
    std::ifstream in(md);
    std::stringstream was;
    was << in.rdbuf();
    // Only the lines that differ, each way.
    auto lines = [](const std::string& text) {
        std::vector<std::string> out;
        std::istringstream s(text);
        for (std::string l; std::getline(s, l);) out.push_back(l);
        std::sort(out.begin(), out.end());
        return out;
    };
    const std::vector<std::string> a = lines(was.str()), b = lines(now);
    std::vector<std::string> gone, added;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(gone));
    std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(added));
    std::string diff;
    for (const auto& l : gone) diff += "\n  - " + l;
    for (const auto& l : added) diff += "\n  + " + l;
    EXPECT_TRUE(diff.empty()) << "tests/corpus.md (-) differs from this run (+); INKLINE_UPDATE_CORPUS=1 rewrites it:" << diff;
}
