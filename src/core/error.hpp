// One error type for everything a user can get wrong (files, flags, styles): its message is a
// single line "<file or flag>: <problem>", printed by the app with a non-zero exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace inkline {

class Error : public std::runtime_error {
public:
    Error(const std::string& where, const std::string& what)
        : std::runtime_error(where + ": " + what) {}
};

}  // namespace inkline
