// Reading a whole text file for the parsers (styles, offset tables, surfaces). Takes a path; gives
// its bytes, or throws inkline::Error("<path>: cannot open <what>").
#pragma once

#include <string>

namespace inkline {

std::string read_whole_file(const std::string& path, const std::string& what);

}  // namespace inkline
