// The folder a command writes into (`--out DIR`): created when missing; an empty name, a file of
// that name or a folder that cannot be created is one input error naming it, before any work.
#pragma once

#include <string>

namespace lobe {

void createOutputFolder(const std::string& dir, const std::string& option = "--out");

}  // namespace lobe
