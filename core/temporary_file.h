// Temporary files written beside their final path and renamed when complete (images, reports):
// named after the process that writes them, so that one a killed run left behind (SIGKILL from
// an out-of-memory killer or a scheduler, which no handler sees: core/interrupt.h covers SIGINT
// and SIGTERM) is recognised by the next run that writes into the same folder.
//
// Name: ".NAME.partial-HOST~PID~TAG.EXT" — NAME the final file's stem, EXT its extension (image
// writers pick the format by it), HOST this machine's name, PID this process, TAG a random
// number. '~' appears in no host name (RFC 1123).
#pragma once

#include <string>

namespace lobe {

// The temporary sibling of `path` (keepExtension: ".NAME.partial-….EXT", else the whole file
// name before ".partial-…"). The first call for a folder also reclaims that folder's
// temporaries of dead owners (reclaimDeadTemporaries).
std::string temporarySibling(const std::string& path, bool keepExtension = true);

// Temporaries in `folder` whose owner is gone: on this host, a PID that is not running (or is
// running another program than lobe) — removed, with one line on stderr saying how many and
// whose; on another host (a shared file system) — only reported, once, as that run may be alive.
// Returns the number removed. Quiet when there are none.
int reclaimDeadTemporaries(const std::string& folder);

// Writes `text` to `path` completely under a temporary sibling (removed on SIGINT/SIGTERM or
// error), then puts it in place: renamed over any old file, or with `noReplace` linked to `path`
// only if no file of that name exists (returns false then, and nothing is written). Reports,
// scene files, the study's pages and answers. Throws lobe::Error naming the path on failure.
bool writeTextFileAtomic(const std::string& path, const std::string& text, bool noReplace = false);

}  // namespace lobe
