#include "core/files.hpp"

#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace inkline {

std::string read_whole_file(const std::string& path, const std::string& what) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot open " + what);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace inkline
