#include "volume/vdb_size_check.h"

#include "core/error.h"

#include <openvdb/Metadata.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/version.h>

#include <cstdint>
#include <cstring>
#include <algorithm>
#include <fstream>
#include <utility>

namespace lobe::detail {

namespace {

// The file read front to back with every length checked against the bytes left.
class Walk {
public:
    explicit Walk(const std::string& path) : path_(path), in_(path, std::ios::binary) {
        if (!in_) throw Error(path + ": cannot open");
        in_.seekg(0, std::ios::end);
        size_ = static_cast<std::uint64_t>(in_.tellg());
        in_.seekg(0);
    }

    std::uint64_t size() const { return size_; }
    std::uint64_t position() { return static_cast<std::uint64_t>(in_.tellg()); }
    bool ended() { return !in_ || position() >= size_; }

    template <typename T>
    T read(const char* what) {
        T value{};
        need(sizeof(T), what);
        in_.read(reinterpret_cast<char*>(&value), sizeof(T));
        return value;
    }

    // A string as OpenVDB stores it: a uint32 length, then the characters.
    std::string readString(const std::string& what) {
        const auto length = read<std::uint32_t>(what.c_str());
        need(length, what);
        std::string s(length, '\0');
        in_.read(s.data(), length);
        return s;
    }

    void skip(std::uint64_t bytes, const std::string& what) {
        need(bytes, what);
        in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
    }

    void seek(std::uint64_t offset, const std::string& what) {
        if (offset > size_) damaged(what + " points to offset " + std::to_string(offset));
        in_.seekg(static_cast<std::streamoff>(offset));
    }

    [[noreturn]] void damaged(const std::string& what) const {
        throw Error(path_ + ": cannot read the OpenVDB file (" + what + ", beyond the file's " +
                    std::to_string(size_) + " bytes: the file is damaged)");
    }

private:
    void need(std::uint64_t bytes, const std::string& what) {
        const std::uint64_t at = position();
        if (!in_ || at > size_ || bytes > size_ - at)
            damaged(what + " needs " + std::to_string(bytes) + " bytes at offset " +
                    std::to_string(at));
    }

    std::string path_;
    std::ifstream in_;
    std::uint64_t size_ = 0;
};

// MetaMap::readMeta: a uint32 count, then per entry a name, a type name and a uint32 byte count
// followed by the value. A registered fixed-size type (a default instance with a size) reads its
// own size whatever the byte count says (TypedMetadata::readValue), so a byte count that differs
// from it is refused. The delayed-load table (io/DelayedLoadMetadata) sizes its arrays by a
// leaf count at the start of its value: each leaf takes at least a byte of the file.
void checkMetaMap(Walk& walk, const std::string& where) {
    const auto count = walk.read<std::uint32_t>((where + " metadata count").c_str());
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::string name = walk.readString(where + " metadata name");
        const std::string field = where + " metadata '" + name + "'";
        const std::string type = walk.readString(field + " type name");
        const auto bytes = walk.read<std::uint32_t>((field + " size").c_str());
        if (openvdb::Metadata::isRegisteredType(type)) {
            const auto fixed = openvdb::Metadata::createMetadata(type)->size();
            if (fixed > 0 && bytes != fixed)
                walk.damaged(field + " of type " + type + " states " + std::to_string(bytes) +
                             " bytes instead of " + std::to_string(fixed));
        }
        if (type == openvdb::io::DelayedLoadMetadata::staticTypeName() && bytes >= 4) {
            const auto leaves = walk.read<std::uint32_t>((field + " leaf count").c_str());
            if (leaves > walk.size())
                walk.damaged(field + " counts " + std::to_string(leaves) + " leaves");
            walk.skip(bytes - 4, field + " value");
        } else {
            walk.skip(bytes, field + " value");
        }
    }
}

}  // namespace

VdbLayout checkVdbSizeFields(const std::string& path) {
    VdbLayout layout;
    Walk walk(path);
    // Archive::readHeader: magic, file version, library version, grid offsets flag, UUID.
    if (walk.size() < 8 + 4 + 8 + 1 + 36)
        throw Error(path + ": cannot read the OpenVDB file (" + std::to_string(walk.size()) +
                    " bytes, shorter than its header)");
    const auto magic = walk.read<std::int64_t>("magic number");
    const auto version = walk.read<std::uint32_t>("file version");
    if (magic != openvdb::OPENVDB_MAGIC)
        throw Error(path + ": cannot read the OpenVDB file (no OpenVDB magic number at its start)");
    if (version > openvdb::OPENVDB_FILE_VERSION)  // OpenVDB only warns, then reads garbage
        throw Error(path + ": OpenVDB file format version " + std::to_string(version) +
                    " is newer than this OpenVDB reads (" +
                    std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
    // Older layouts read whole value arrays without compression, and a damaged one made the
    // reader allocate close to a gigabyte from 313 bytes: they are refused, not walked.
    if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
        throw Error(path + ": OpenVDB file format version " + std::to_string(version) +
                    " (before OpenVDB 2.0, 2013) is not read; write it again with a current "
                    "OpenVDB (e.g. vdb_tool -read FILE -write NEW.vdb)");
    walk.skip(8, "library version");
    const bool hasGridOffsets = walk.read<char>("grid offsets flag") != 0;
    walk.skip(36, "UUID");
    checkMetaMap(walk, "file");

    // File::readGridDescriptors: a count, then per grid a descriptor followed by the grid; the
    // next descriptor starts where the grid ends.
    layout.gridCountAt = walk.position();
    const auto grids = walk.read<std::int32_t>("grid count");
    for (std::int32_t g = 0; g < grids; ++g) {
        const std::uint64_t descriptorAt = walk.position();
        const std::string where = "grid " + std::to_string(g + 1);
        const std::string name = walk.readString(where + " name");
        const std::string grid = "grid '" + name + "'";
        const std::string type = walk.readString(grid + " type name");
        walk.readString(grid + " instance parent name");  // file versions from 216 on
        const auto gridPos = walk.read<std::int64_t>((grid + " offset").c_str());
        walk.read<std::int64_t>((grid + " block offset").c_str());
        const auto endPos = walk.read<std::int64_t>((grid + " end offset").c_str());
        const std::uint64_t here = walk.position();
        // OpenVDB writes a grid right after its descriptor; the grid ends where the next
        // descriptor starts.
        if (hasGridOffsets && (static_cast<std::uint64_t>(gridPos) != here || endPos < gridPos ||
                               static_cast<std::uint64_t>(endPos) > walk.size()))
            walk.damaged(grid + " offsets " + std::to_string(gridPos) + " to " +
                         std::to_string(endPos) + " do not follow its descriptor at " +
                         std::to_string(here));
        layout.grids.push_back({name, type, descriptorAt,
                                hasGridOffsets ? std::uint64_t(endPos) : walk.size()});
        // Archive::readGrid: the compression flags, the grid's metadata, its transform's map name.
        // Without grid offsets (a file written as a stream) the grid follows its descriptor and
        // the next descriptor follows the grid's tree, which this walk does not parse: only the
        // first grid is checked.
        if (hasGridOffsets) walk.seek(static_cast<std::uint64_t>(gridPos), grid + " offset");
        walk.read<std::uint32_t>((grid + " compression flags").c_str());
        checkMetaMap(walk, grid);
        walk.readString(grid + " transform type name");
        if (!hasGridOffsets) return layout;
        if (g + 1 < grids) walk.seek(static_cast<std::uint64_t>(endPos), grid + " end offset");
    }
    return layout;
}

namespace {

// Reads the pieces of a file in turn: [0, gridCountAt), a grid count of 1, [descriptorAt, end).
class OneGridBuffer : public std::streambuf {
public:
    OneGridBuffer(const std::string& path, const VdbLayout& layout, const VdbGridEntry& grid)
        : in_(path, std::ios::binary) {
        if (!in_) throw Error(path + ": cannot open");
        pieces_ = {{0, layout.gridCountAt}, {0, 0}, {grid.descriptorAt, grid.end}};
    }

private:
    int_type underflow() override {
        while (piece_ < pieces_.size()) {
            if (piece_ == 1) {  // the patched grid count
                const std::int32_t one = 1;
                std::memcpy(buffer_, &one, sizeof one);
                setg(buffer_, buffer_, buffer_ + sizeof one);
                ++piece_;
                return traits_type::to_int_type(buffer_[0]);
            }
            auto& [from, to] = pieces_[piece_];
            if (from < to) {
                const std::uint64_t n = std::min<std::uint64_t>(sizeof buffer_, to - from);
                in_.seekg(static_cast<std::streamoff>(from));
                in_.read(buffer_, static_cast<std::streamsize>(n));
                const auto got = static_cast<std::uint64_t>(in_.gcount());
                if (got == 0) return traits_type::eof();
                from += got;
                setg(buffer_, buffer_, buffer_ + got);
                return traits_type::to_int_type(buffer_[0]);
            }
            ++piece_;
        }
        return traits_type::eof();
    }

    std::ifstream in_;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> pieces_;
    std::size_t piece_ = 0;
    char buffer_[1 << 16];
};

}  // namespace

std::unique_ptr<std::streambuf> oneGridOf(const std::string& path, const VdbLayout& layout,
                                          const VdbGridEntry& grid) {
    return std::make_unique<OneGridBuffer>(path, layout, grid);
}

}  // namespace lobe::detail
