// A walk over the size fields of a .vdb file before OpenVDB reads it. OpenVDB's reader builds a
// string or a metadata buffer of whatever length the file states (util/Name.h readString,
// Metadata::read) before it finds out the file is shorter: a damaged or hostile field costs
// seconds and gigabytes. The walk reads the header, the file's metadata, every grid descriptor
// and each grid's metadata and transform name, and refuses any length that runs past the end of
// the file. The layout is OpenVDB's (io/Archive.cc, io/GridDescriptor.cc, MetaMap.cc), for file
// versions from 222 (OpenVDB 2.0, 2013) on; older files are left to OpenVDB.
#pragma once

#include <cstdint>
#include <memory>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

namespace lobe::detail {

// A metadata table's count and the entries left out of what OpenVDB reads: the delayed-load
// table ("__delayedload"), whose reader (io/DelayedLoadMetadata.cc) consumes as many bytes as
// its own fields say rather than the entry's stated size, so a damaged one shifts every read
// after it (a fuzz finding: a metadata name of gigabytes). Lobe reads without delayed loading,
// so the table is of no use to it.
struct VdbMetaLayout {
    std::uint64_t countAt = 0;
    std::uint32_t count = 0;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> dropped;  // [from, to) byte ranges
};

// Where the walk found each grid: its descriptor's first byte and the end of its data.
struct VdbGridEntry {
    std::string name;  // as stored (OpenVDB may append a "[n]" suffix to repeated names)
    std::string type;  // e.g. Tree_float_5_4_3, with "_HalfFloat" when saved as half floats
    std::uint64_t descriptorAt = 0, end = 0;
    std::uint64_t transformAt = 0;  // the transform's map type name; the tree follows the map
    std::uint32_t compression = 0;  // io::COMPRESS_* flags of this grid's values
    bool instance = false;          // an instance of another grid: no tree of its own
    VdbMetaLayout meta;             // the grid's metadata
};
struct VdbLayout {
    VdbMetaLayout fileMeta;
    std::uint64_t gridCountAt = 0;    // offset of the grid count (after the file metadata)
    std::vector<VdbGridEntry> grids;  // without grid offsets (a stream): the first grid only
};

// Throws lobe::Error naming PATH and the field when a size field exceeds what the file holds
// (or the file is no .vdb, or of a format version OpenVDB 2.0 … this one did not write);
// returns the layout. OpenVDB must be initialised (the registered metadata types give sizes).
VdbLayout checkVdbSizeFields(const std::string& path);

// The walk continued over one float grid's transform and tree (Tree_float_5_4_3), before
// OpenVDB reads it: every node mask, every value chunk's stated size against the number of
// values its node and mask call for, and each Blosc chunk's header. OpenVDB 10's
// bloscFromStream and unzipFromStream copy an uncompressed chunk of whatever size the file
// states into the node's buffer before they compare it with the buffer's size (a heap
// overflow: fuzz/openvdb-findings/); compressed chunks are handed to Blosc, which trusts its
// header's sizes. Throws lobe::Error naming PATH and the node when anything does not add up.
void checkVdbFloatTree(const std::string& path, const VdbGridEntry& grid);

// The file as OpenVDB should read it to get one grid: its header and metadata, a grid count of
// 1, and that grid's descriptor and data — so no byte the walk did not check is read as a
// descriptor — without the metadata entries the walk dropped (their tables' counts lowered). Reads
// past the end fail (give the istream exceptions to stop OpenVDB there).
std::unique_ptr<std::streambuf> oneGridOf(const std::string& path, const VdbLayout& layout,
                                          const VdbGridEntry& grid);

}  // namespace lobe::detail
