// The one exception type for bad input (files, scenes, parameters, command lines). Its message is
// shown to the user as it is, so it names what was wrong and where; `lobe` catches it once in main
// and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace lobe {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace lobe
