#include "volume/vdb_size_check.h"

#include "core/error.h"

#include <fcntl.h>
#include <openvdb/Metadata.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/version.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bitset>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <utility>

namespace lobe::detail {

namespace {

// The file read front to back with every length checked against the bytes left. The file is
// mapped, not streamed: the tree walk skips over many small chunks, and each seek of an
// ifstream throws its buffer away (0.45 s for a 12 MB CThead grid; mapped: see
// docs/performance.md).
class Walk {
public:
    explicit Walk(const std::string& path) : path_(path) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw Error(path + ": cannot open");
        struct stat st {};
        if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
            ::close(fd);
            throw Error(path + ": cannot open (not a regular file)");
        }
        size_ = static_cast<std::uint64_t>(st.st_size);
        if (size_ > 0) {
            void* map = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
            if (map == MAP_FAILED) {
                ::close(fd);
                throw Error(path + ": cannot map the file into memory");
            }
            data_ = static_cast<const unsigned char*>(map);
            ::madvise(map, size_, MADV_SEQUENTIAL);
        }
        ::close(fd);
    }
    ~Walk() {
        if (data_) ::munmap(const_cast<unsigned char*>(data_), size_);
    }
    Walk(const Walk&) = delete;
    Walk& operator=(const Walk&) = delete;

    std::uint64_t size() const { return size_; }
    std::uint64_t position() const { return at_; }
    // Reads stop at `end` (a grid's end offset: OpenVDB reads no further, oneGridOf).
    void limit(std::uint64_t end, const std::string& name) {
        if (end < size_) size_ = end, extent_ = name;
    }
    bool ended() const { return at_ >= size_; }

    template <typename T>
    T read(const char* what) {
        T value{};
        readBytes(&value, sizeof(T), what);
        return value;
    }

    // A string as OpenVDB stores it: a uint32 length, then the characters.
    std::string readString(const std::string& what) {
        const auto length = read<std::uint32_t>(what.c_str());
        need(length, what);
        std::string s(reinterpret_cast<const char*>(data_ + at_), length);
        at_ += length;
        return s;
    }

    void skip(std::uint64_t bytes, const std::string& what) {
        need(bytes, what);
        at_ += bytes;
    }

    void seek(std::uint64_t offset, const std::string& what) {
        if (offset > size_) damaged(what + " points to offset " + std::to_string(offset));
        at_ = offset;
    }

    void readBytes(void* to, std::uint64_t bytes, const std::string& what) {
        need(bytes, what);
        if (bytes > 0) std::memcpy(to, data_ + at_, bytes);
        at_ += bytes;
    }

    // A field whose value contradicts the rest of the file (not one that runs past its end).
    [[noreturn]] void broken(const std::string& what) const {
        throw Error(path_ + ": cannot read the OpenVDB file (" + what + ": the file is damaged)");
    }

    [[noreturn]] void damaged(const std::string& what) const {
        throw Error(path_ + ": cannot read the OpenVDB file (" + what + ", beyond " + extent_ +
                    " " + std::to_string(size_) + " bytes: the file is damaged)");
    }

private:
    void need(std::uint64_t bytes, const std::string& what) const {
        if (at_ > size_ || bytes > size_ - at_)
            damaged(what + " needs " + std::to_string(bytes) + " bytes at offset " +
                    std::to_string(at_));
    }

    std::string path_, extent_ = "the file's";
    const unsigned char* data_ = nullptr;
    std::uint64_t size_ = 0, at_ = 0;
};

// MetaMap::readMeta: a uint32 count, then per entry a name, a type name and a uint32 byte count
// followed by the value. A registered fixed-size type (a default instance with a size) reads its
// own size whatever the byte count says (TypedMetadata::readValue), so a byte count that differs
// from it is refused. The delayed-load table (io/DelayedLoadMetadata) sizes its arrays by a
// leaf count at the start of its value: each leaf takes at least a byte of the file.
VdbMetaLayout checkMetaMap(Walk& walk, const std::string& where) {
    VdbMetaLayout layout;
    layout.countAt = walk.position();
    const auto count = walk.read<std::uint32_t>((where + " metadata count").c_str());
    layout.count = count;
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::uint64_t entryAt = walk.position();
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
        if (type == openvdb::io::DelayedLoadMetadata::staticTypeName())
            layout.dropped.emplace_back(entryAt, walk.position());
    }
    return layout;
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
    layout.fileMeta = checkMetaMap(walk, "file");

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
        const std::string parent = walk.readString(grid + " instance parent name");  // from 216 on
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
        VdbGridEntry& entry = layout.grids.emplace_back();
        entry.name = name;
        entry.type = type;
        entry.descriptorAt = descriptorAt;
        entry.end = hasGridOffsets ? std::uint64_t(endPos) : walk.size();
        entry.instance = !parent.empty();
        // Archive::readGrid: the compression flags, the grid's metadata, its transform's map name.
        // Without grid offsets (a file written as a stream) the grid follows its descriptor and
        // the next descriptor follows the grid's tree, which this walk does not parse: only the
        // first grid is checked.
        if (hasGridOffsets) walk.seek(static_cast<std::uint64_t>(gridPos), grid + " offset");
        entry.compression = walk.read<std::uint32_t>((grid + " compression flags").c_str());
        entry.meta = checkMetaMap(walk, grid);
        entry.transformAt = walk.position();
        walk.readString(grid + " transform type name");
        if (!hasGridOffsets) return layout;
        if (g + 1 < grids) walk.seek(static_cast<std::uint64_t>(endPos), grid + " end offset");
    }
    return layout;
}

namespace {

// Reads the pieces of a file in turn: [0, gridCountAt), a grid count of 1, [descriptorAt, end),
// each metadata table with its dropped entries left out and its count lowered to match.
class OneGridBuffer : public std::streambuf {
public:
    OneGridBuffer(const std::string& path, const VdbLayout& layout, const VdbGridEntry& grid)
        : in_(path, std::ios::binary) {
        if (!in_) throw Error(path + ": cannot open");
        addRange(0, layout.gridCountAt, layout.fileMeta);
        addLiteral(1);  // the grid count
        addRange(grid.descriptorAt, grid.end, grid.meta);
    }

private:
    // A piece is a byte range of the file, or four literal bytes.
    struct Piece {
        std::uint64_t from = 0, to = 0;
        bool isLiteral = false;
        std::uint32_t literal = 0;
    };

    void addLiteral(std::uint32_t value) { pieces_.push_back({0, 0, true, value}); }

    // [from, to), which holds the metadata table `meta`.
    void addRange(std::uint64_t from, std::uint64_t to, const VdbMetaLayout& meta) {
        if (meta.dropped.empty()) {
            pieces_.push_back({from, to});
            return;
        }
        pieces_.push_back({from, meta.countAt});
        addLiteral(meta.count - std::uint32_t(meta.dropped.size()));
        std::uint64_t at = meta.countAt + 4;
        for (const auto& [skipFrom, skipTo] : meta.dropped) {
            pieces_.push_back({at, skipFrom});
            at = skipTo;
        }
        pieces_.push_back({at, to});
    }

    int_type underflow() override {
        while (piece_ < pieces_.size()) {
            Piece& p = pieces_[piece_];
            if (p.isLiteral) {
                std::memcpy(buffer_, &p.literal, sizeof p.literal);
                setg(buffer_, buffer_, buffer_ + sizeof p.literal);
                ++piece_;
                return traits_type::to_int_type(buffer_[0]);
            }
            if (p.from < p.to) {
                const std::uint64_t n = std::min<std::uint64_t>(sizeof buffer_, p.to - p.from);
                in_.seekg(static_cast<std::streamoff>(p.from));
                in_.read(buffer_, static_cast<std::streamsize>(n));
                const auto got = static_cast<std::uint64_t>(in_.gcount());
                if (got == 0) return traits_type::eof();
                p.from += got;
                setg(buffer_, buffer_, buffer_ + got);
                return traits_type::to_int_type(buffer_[0]);
            }
            ++piece_;
        }
        return traits_type::eof();
    }

    std::ifstream in_;
    std::vector<Piece> pieces_;
    std::size_t piece_ = 0;
    char buffer_[1 << 16];
};

}  // namespace

std::unique_ptr<std::streambuf> oneGridOf(const std::string& path, const VdbLayout& layout,
                                          const VdbGridEntry& grid) {
    return std::make_unique<OneGridBuffer>(path, layout, grid);
}

namespace {

// Map::read of each map type (math/Maps.h): fixed-size vectors and matrices of doubles, except
// the frustum map, which stores a box, taper and depth, then a second map by type name.
void skipMap(Walk& walk, const std::string& type, const std::string& where, int depth) {
    static const std::map<std::string, std::uint64_t> fixedBytes = {
        {"AffineMap", 16 * 8},
        {"UnitaryMap", 16 * 8},
        {"ScaleMap", 5 * 24},
        {"UniformScaleMap", 5 * 24},
        {"TranslationMap", 24},
        {"ScaleTranslateMap", 6 * 24},
        {"UniformScaleTranslateMap", 6 * 24}};
    if (const auto it = fixedBytes.find(type); it != fixedBytes.end()) {
        walk.skip(it->second, where + " " + type);
        return;
    }
    if (type != "NonlinearFrustumMap") walk.broken(where + " map type '" + type + "' is unknown");
    if (depth > 0) walk.broken(where + " nests one frustum map in another");
    walk.skip(6 * 8 + 2 * 8, where + " frustum box, taper and depth");
    skipMap(walk, walk.readString(where + " frustum's second map type"), where, depth + 1);
}

// A node mask as NodeMask::load reads it: bits/64 words. Returns the number of bits on; the
// words when asked for.
std::uint32_t readMask(Walk& walk, std::uint32_t bits, const std::string& what,
                       std::vector<std::uint64_t>* words = nullptr) {
    std::vector<std::uint64_t> local;
    std::vector<std::uint64_t>& w = words ? *words : local;
    w.assign(bits / 64, 0);
    walk.readBytes(w.data(), bits / 8, what);
    std::uint32_t on = 0;
    for (const std::uint64_t word : w) on += std::uint32_t(std::bitset<64>(word).count());
    return on;
}

struct ValueFormat {
    std::uint32_t compression = 0;  // io::COMPRESS_* flags
    bool half = false;              // values stored as 16-bit halves
};

// One chunk as bloscFromStream / unzipFromStream read it (io/Compression.cc): an int64 size,
// negative for `bytes` stored as they are, positive for a compressed block of that size.
void checkChunk(Walk& walk, bool blosc, std::uint64_t bytes, const std::string& where) {
    const auto stored = walk.read<std::int64_t>((where + " chunk size").c_str());
    if (stored <= 0) {
        // OpenVDB reads -stored bytes into the buffer of `bytes` and only then compares.
        const std::uint64_t magnitude = 0 - std::uint64_t(stored);  // -stored, even for INT64_MIN
        if (magnitude != bytes)
            walk.broken(where + " holds an uncompressed chunk of " + std::to_string(magnitude) +
                        " bytes where its node takes " + std::to_string(bytes));
        walk.skip(bytes, where + " values");
        return;
    }
    if (!blosc) {  // zlib's uncompress is given the buffer's size: it never writes past it
        walk.skip(std::uint64_t(stored), where + " zip chunk");
        return;
    }
    // Blosc 1.x header (blosc.h): version, versionlz, flags, typesize, then uint32 nbytes
    // (uncompressed), blocksize and cbytes (compressed, header included). blosc_decompress
    // trusts cbytes when it reads the block, so it must not exceed the chunk read.
    constexpr std::uint64_t kHeader = 16;
    if (std::uint64_t(stored) < kHeader)
        walk.broken(where + " holds a Blosc chunk of " + std::to_string(stored) +
                    " bytes, shorter than its header");
    std::array<unsigned char, kHeader> h{};
    walk.readBytes(h.data(), kHeader, where + " Blosc header");
    const auto u32 = [&](int at) {
        return std::uint32_t(h[at]) | std::uint32_t(h[at + 1]) << 8 |
               std::uint32_t(h[at + 2]) << 16 | std::uint32_t(h[at + 3]) << 24;
    };
    const std::uint32_t nbytes = u32(4), cbytes = u32(12);
    if (nbytes != bytes || cbytes < kHeader || cbytes > std::uint64_t(stored))
        walk.broken(where + " holds a Blosc chunk whose header states " + std::to_string(nbytes) +
                    " bytes in " + std::to_string(cbytes) + " (the chunk has " +
                    std::to_string(stored) + ", its node takes " + std::to_string(bytes) + ")");
    walk.skip(std::uint64_t(stored) - kHeader, where + " Blosc chunk");
}

// io::readCompressedValues (io/Compression.h) for a node of `size` values, `active` of them on
// in its value mask: a metadata byte, up to two inactive values, a selection mask, then the
// stored values — all of them, or with mask compression only the active ones.
void checkValues(Walk& walk, const ValueFormat& f, std::uint32_t size, std::uint32_t active,
                 const std::string& where) {
    using namespace openvdb::io;
    const auto metadata = walk.read<std::int8_t>((where + " compression byte").c_str());
    if (metadata == NO_MASK_AND_ONE_INACTIVE_VAL || metadata == MASK_AND_ONE_INACTIVE_VAL ||
        metadata == MASK_AND_TWO_INACTIVE_VALS)
        walk.skip(sizeof(float) * (metadata == MASK_AND_TWO_INACTIVE_VALS ? 2 : 1),
                  where + " inactive values");
    if (metadata == MASK_AND_NO_INACTIVE_VALS || metadata == MASK_AND_ONE_INACTIVE_VAL ||
        metadata == MASK_AND_TWO_INACTIVE_VALS)
        walk.skip(size / 8, where + " selection mask");
    const bool maskCompressed = (f.compression & COMPRESS_ACTIVE_MASK) != 0;
    const std::uint64_t count = maskCompressed && metadata != NO_MASK_AND_ALL_VALS ? active : size;
    if (f.half && count == 0) return;  // HalfReader reads nothing then
    const std::uint64_t bytes = count * (f.half ? 2 : sizeof(float));
    if (f.compression & COMPRESS_BLOSC)
        checkChunk(walk, true, bytes, where);
    else if (f.compression & COMPRESS_ZIP)
        checkChunk(walk, false, bytes, where);
    else
        walk.skip(bytes, where + " values");
}

// Tree_float_5_4_3: a root table of 4096³ internal nodes (32³ children), each child a 128³
// internal node (16³ children), each of those an 8³ leaf. Topology first (RootNode,
// InternalNode and LeafNode ::readTopology), then the leaves' buffers (::readBuffers) in the
// root table's order — a std::map by origin, where a later child with an equal origin replaces
// an earlier one — and each node's children in child-mask order.
void checkTree(Walk& walk, const ValueFormat& f) {
    walk.read<std::int32_t>("tree buffer count");
    walk.read<float>("tree background");
    const auto tiles = walk.read<std::uint32_t>("root tile count");
    const auto children = walk.read<std::uint32_t>("root child count");
    for (std::uint32_t t = 0; t < tiles; ++t) walk.skip(3 * 4 + 4 + 1, "root tile");

    // Per root child, its leaves' active counts in topology order (grown as children are
    // read: the count is the file's word, each child takes at least 8 kB of the file).
    std::vector<std::vector<std::uint16_t>> branches;
    std::map<std::array<std::int32_t, 3>, std::uint32_t> table;
    std::vector<std::uint64_t> upperChildren, lowerChildren;
    for (std::uint32_t c = 0; c < children; ++c) {
        std::array<std::int32_t, 3> origin{};
        walk.readBytes(origin.data(), sizeof origin, "root child origin");
        branches.emplace_back();
        const std::string upper = "node at (" + std::to_string(origin[0]) + ", " +
                                  std::to_string(origin[1]) + ", " + std::to_string(origin[2]) +
                                  ")";
        readMask(walk, 32768, upper + " child mask", &upperChildren);
        const auto upperActive = readMask(walk, 32768, upper + " value mask");
        checkValues(walk, f, 32768, upperActive, upper + " tile values");
        for (std::uint32_t i = 0; i < 32768; ++i) {
            if (!(upperChildren[i / 64] >> (i % 64) & 1)) continue;
            const std::string lower = upper + " child " + std::to_string(i);
            readMask(walk, 4096, lower + " child mask", &lowerChildren);
            const auto lowerActive = readMask(walk, 4096, lower + " value mask");
            checkValues(walk, f, 4096, lowerActive, lower + " tile values");
            for (std::uint32_t j = 0; j < 4096; ++j)
                if (lowerChildren[j / 64] >> (j % 64) & 1)
                    branches[c].push_back(
                        std::uint16_t(readMask(walk, 512, lower + " leaf value mask")));
        }
        table[origin] = c;
    }
    for (const auto& [origin, c] : table) {
        const std::string where = "leaf under the node at (" + std::to_string(origin[0]) + ", " +
                                  std::to_string(origin[1]) + ", " + std::to_string(origin[2]) +
                                  ")";
        for (const std::uint16_t topologyActive : branches[c]) {
            // The buffer repeats the leaf's mask; which copy OpenVDB counts depends on the
            // stream, so they must agree.
            const auto active = readMask(walk, 512, where + " value mask");
            if (active != topologyActive)
                walk.broken(where + ": its value mask differs between topology (" +
                            std::to_string(topologyActive) + " on) and buffers (" +
                            std::to_string(active) + " on)");
            checkValues(walk, f, 512, active, where);
        }
    }
}

}  // namespace

void checkVdbFloatTree(const std::string& path, const VdbGridEntry& grid) {
    if (grid.instance) return;                     // its tree is its parent's
    const std::string plain = "Tree_float_5_4_3";  // openvdb::FloatTree::treeType()
    const std::string halfSuffix = "_HalfFloat";  // io/GridDescriptor.cc HALF_FLOAT_TYPENAME_SUFFIX
    ValueFormat format;
    format.compression = grid.compression;
    if (grid.type == plain + halfSuffix)
        format.half = true;
    else if (grid.type != plain)
        throw Error(path + ": grid '" + grid.name + "' has type " + grid.type +
                    ", expected a float grid (" + plain + ")");
    Walk walk(path);
    walk.limit(grid.end, "the grid's");
    walk.seek(grid.transformAt, "grid '" + grid.name + "' transform");
    const std::string where = "grid '" + grid.name + "' transform";
    skipMap(walk, walk.readString(where + " type name"), where, 0);
    checkTree(walk, format);
}

}  // namespace lobe::detail
