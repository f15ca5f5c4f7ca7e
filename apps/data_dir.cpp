#include "apps/data_dir.h"

#include <filesystem>
#include <system_error>

namespace lobe {

namespace fs = std::filesystem;

std::string findAssetsDir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "";
    const fs::path bin = exe.parent_path();
    const fs::path installed = bin / ".." / "share" / "lobe" / "assets";
    if (fs::is_directory(installed / "scenes", ec)) return fs::canonical(installed, ec).string();
    for (fs::path dir = bin; !dir.empty(); dir = dir.parent_path()) {
        if (fs::is_directory(dir / "assets" / "scenes", ec)) return (dir / "assets").string();
        if (dir == dir.root_path()) break;
    }
    return "";
}

}  // namespace lobe
