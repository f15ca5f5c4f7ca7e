#include "core/output_folder.h"

#include "core/error.h"

#include <filesystem>
#include <system_error>

namespace lobe {

void createOutputFolder(const std::string& dir, const std::string& option) {
    namespace fs = std::filesystem;
    if (dir.empty()) throw Error(option + ": the output folder's name is empty");
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw Error(option + " '" + dir + "' is a file, not a folder");
    fs::create_directories(dir, ec);
    if (ec) throw Error(option + ": cannot create the folder '" + dir + "': " + ec.message());
}

}  // namespace lobe
