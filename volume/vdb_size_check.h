// A walk over the size fields of a .vdb file before OpenVDB reads it. OpenVDB's reader builds a
// string or a metadata buffer of whatever length the file states (util/Name.h readString,
// Metadata::read) before it finds out the file is shorter: a damaged or hostile field costs
// seconds and gigabytes. The walk reads the header, the file's metadata, every grid descriptor
// and each grid's metadata and transform name, and refuses any length that runs past the end of
// the file. The layout is OpenVDB's (io/Archive.cc, io/GridDescriptor.cc, MetaMap.cc), for file
// versions from 222 (OpenVDB 2.0, 2013) on; older files are left to OpenVDB.
#pragma once

#include <string>

namespace lobe::detail {

// Throws lobe::Error naming PATH and the field when a size field exceeds what the file holds.
// OpenVDB must be initialised (the registered metadata types give their sizes).
void checkVdbSizeFields(const std::string& path);

}  // namespace lobe::detail
