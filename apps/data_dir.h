// Where the `lobe` binary finds its data (assets/: the paper's scenes, the CThead, the brain
// volumes) without any path compiled into it:
//  1. installed (`cmake --install build --prefix P`): P/share/lobe/assets, i.e.
//     <directory of the executable>/../share/lobe/assets;
//  2. in a build tree: the first folder above the executable holding assets/scenes — the
//     repository's own assets/ for the README's build in build/ (build/apps/lobe).
// The executable's path comes from /proc/self/exe (Linux). `lobe demo --assets DIR` overrides.
#pragma once

#include <string>

namespace lobe {

// The assets folder, or "" when neither rule finds one.
std::string findAssetsDir();

}  // namespace lobe
