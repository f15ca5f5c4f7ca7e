// Volumes as OpenVDB grids: building a sparse FloatGrid from a dense file array (see volume.h
// for the sparsity rule), .vdb input and output, the dispatcher and the statistics `lobe info`
// prints. The only translation unit of lobe_volume that includes OpenVDB's tools.
#include "volume/volume.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/temporary_file.h"
#include "volume/dicom_file.h"
#include "volume/gaussian_blur.h"
#include "volume/grid_world.h"
#include "volume/vdb_size_check.h"
#include "volume/volume_file.h"
#include "volume/volume_summary.h"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

namespace lobe {

namespace {

constexpr const char* kDefaultGridName = "density";

// Metadata keys under which writeVdb stores what loadVdb needs to restore the Volume.
constexpr const char* kMetaDims = "lobe_dims";
constexpr const char* kMetaIndexOrigin = "lobe_index_origin";
constexpr const char* kMetaSource = "lobe_source";
constexpr const char* kMetaOriginalMin = "lobe_original_min";
constexpr const char* kMetaOriginalMax = "lobe_original_max";
constexpr const char* kMetaValueScale = "lobe_value_scale";
constexpr const char* kMetaBackground = "lobe_background";

void initializeOpenVdb() {
    // openvdb::initialize registers grid and metadata types; it is idempotent and guarded.
    static const bool done = [] {
        openvdb::initialize();
        return true;
    }();
    (void)done;
}

// Percentiles as `lobe info` prints them: nearest rank over this many bins of the value range.
constexpr int kPercentileBins = 65536;

// The value multiplier the options ask for, given the original range; `percentile(p)` gives the
// p-th percentile of the original values (called only when options ask for one).
template <typename PercentileFn>
double valueScaleFor(const std::string& path, const LoadOptions& options, double originalMax,
                     PercentileFn percentile) {
    double scale = options.scale;
    if (options.normalizePercentile > 0.0) {
        const double p = percentile(options.normalizePercentile);
        char text[64];
        std::snprintf(text, sizeof text, "%g", options.normalizePercentile);
        if (!(p > 0.0) || !std::isfinite(p))
            throw Error(path + ": cannot normalise by the " + text + " % percentile, which is " +
                        std::to_string(p) + " (not positive)");
        scale = 1.0 / p;
    } else if (options.normalizeByMax) {
        if (!(originalMax > 0.0))
            throw Error(path + ": cannot normalise by the maximum, which is " +
                        std::to_string(originalMax) + " (not positive)");
        scale = 1.0 / originalMax;
    } else if (options.normalize != 0.0) {
        if (!(options.normalize > 0.0) || !std::isfinite(options.normalize))
            throw Error(path + ": the normalisation divisor must be positive, got " +
                        std::to_string(options.normalize));
        scale = 1.0 / options.normalize;
    }
    if (!(scale > 0.0) || !std::isfinite(scale))
        throw Error(path + ": the value scale must be positive and finite, got " +
                    std::to_string(scale));
    return scale;
}

// Deactivates active values ≤ threshold (they stay stored: lookups still return them), then
// merges constant nodes (tolerance 0, so no value changes).
void applyBackground(openvdb::FloatTree& tree, float threshold) {
    for (auto it = tree.beginValueOn(); it; ++it)
        if (*it <= threshold) it.setValueOff();
    openvdb::tools::prune(tree);
}

Volume buildVolume(detail::DenseVolume&& dense, const std::string& path,
                   const LoadOptions& options) {
    initializeOpenVdb();
    Volume volume;
    volume.sourcePath = path;
    volume.dims = dense.dims;
    volume.originalMin = dense.min;
    volume.originalMax = dense.max;
    volume.valueScale = valueScaleFor(path, options, dense.max, [&](double p) {
        // The histogram `lobe info` uses (summaryOf), over the dense values: the same number.
        ValueHistogram h;
        h.lo = dense.min;
        h.hi = dense.max;
        h.counts.assign(kPercentileBins, 0);
        const double width = dense.max - dense.min;
        for (float v : dense.values) {
            const double f = width > 0.0 ? (double(v) - dense.min) / width * kPercentileBins : 0.0;
            h.counts[std::size_t(
                std::min(double(kPercentileBins - 1), std::max(0.0, std::floor(f))))]++;
        }
        return h.percentile(p);
    });
    volume.background = options.background;
    if (volume.valueScale != 1.0)
        for (float& v : dense.values) {
            v = static_cast<float>(double(v) * volume.valueScale);
            if (!std::isfinite(v))
                throw Error(path + ": a value overflows the float range after scaling by " +
                            std::to_string(volume.valueScale));
        }

    // The file's arrays are x fastest: OpenVDB's LayoutXYZ (offset = i + j·X + k·X·Y).
    const openvdb::CoordBBox box(
        openvdb::Coord(0, 0, 0),
        openvdb::Coord(dense.dims[0] - 1, dense.dims[1] - 1, dense.dims[2] - 1));
    openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> denseGrid(box, dense.values.data());
    volume.grid = openvdb::FloatGrid::create(0.0f);
    // Tolerance 0: only voxels exactly equal to the background 0 are left out (they read back
    // as 0, so the copy is lossless); copyFromDense also collapses constant blocks into tiles.
    openvdb::tools::copyFromDense(denseGrid, volume.grid->tree(), 0.0f);
    applyBackground(volume.grid->tree(),
                    static_cast<float>(options.background * volume.valueScale));
    std::vector<float>().swap(dense.values);

    // OpenVDB multiplies row vectors on the left (world = index · M), so M is the transpose of
    // the file's column-vector affine A, with the translation in the last row.
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) m[col][row] = dense.affine[row][col];
        m[3][row] = dense.affine[row][3];
    }
    // The header's map passed the relative test (core/math.h, nearlySingular); tiny voxels
    // (1e-5 mm) are rescaled for OpenVDB and their scale kept beside (volume/grid_world.h).
    try {
        setGridWorldMap(*volume.grid, m);
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": the voxel-to-world map is not usable (" + e.what() + ")");
    }
    for (int col = 0; col < 3; ++col)
        volume.spacing[col] = std::sqrt(dense.affine[0][col] * dense.affine[0][col] +
                                        dense.affine[1][col] * dense.affine[1][col] +
                                        dense.affine[2][col] * dense.affine[2][col]);
    volume.grid->setName(kDefaultGridName);
    volume.grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return volume;
}

template <typename MetaT, typename T>
bool readMeta(const openvdb::GridBase& grid, const char* key, T& out) {
    const auto meta = grid.getMetadata<MetaT>(key);
    if (!meta) return false;
    out = meta->value();
    return true;
}

}  // namespace

Volume loadRaw(const std::string& path, const RawLayout& layout, const LoadOptions& options) {
    return buildVolume(detail::readRawDense(path, layout), path, options);
}

Volume loadNifti(const std::string& path, const LoadOptions& options) {
    return buildVolume(detail::readNiftiDense(path), path, options);
}

Volume loadNrrd(const std::string& path, const LoadOptions& options) {
    return buildVolume(detail::readNrrdDense(path), path, options);
}

Volume loadMgh(const std::string& path, const LoadOptions& options) {
    return buildVolume(detail::readMghDense(path), path, options);
}

Volume loadVdb(const std::string& path, const LoadOptions& options) {
    initializeOpenVdb();
    const detail::VdbLayout layout = detail::checkVdbSizeFields(path);
    openvdb::GridBase::Ptr base;
    try {
        // The grid to read, chosen from the walk's list: the one named, or the first float grid.
        const detail::VdbGridEntry* chosen = nullptr;
        std::string names;
        for (const detail::VdbGridEntry& g : layout.grids) {
            const std::string name = openvdb::io::GridDescriptor::stripSuffix(g.name);
            names += (names.empty() ? "" : ", ") + name;
            const bool isFloat = g.type.rfind(openvdb::FloatGrid::gridType(), 0) == 0;
            if (!chosen && (options.gridName.empty() ? isFloat : name == options.gridName))
                chosen = &g;
        }
        if (!chosen && !options.gridName.empty())
            throw Error(path + ": no grid named '" + options.gridName +
                        "' (the file has: " + (names.empty() ? "none" : names) + ")");
        if (!chosen)
            throw Error(path + ": the file holds no float grid (Lobe volumes are float grids)");
        // Its transform and tree walked first: OpenVDB copies a value chunk of the size the
        // file states before it checks it (vdb_size_check.h).
        detail::checkVdbFloatTree(path, *chosen);
        // Only that grid, through a stream that throws at the end of its data: OpenVDB's
        // topology reader keeps allocating nodes after a read fails (a damaged child count or
        // mask in a few hundred bytes asked for gigabytes), so the first read past the end must
        // stop it; and no byte the size walk did not check is read as a grid descriptor.
        const std::unique_ptr<std::streambuf> buffer = detail::oneGridOf(path, layout, *chosen);
        std::istream in(buffer.get());
        in.exceptions(std::ios::failbit | std::ios::badbit);
        openvdb::io::Stream stream(in, /*delayLoad=*/false);
        const openvdb::GridPtrVecPtr grids = stream.getGrids();
        if (!grids || grids->empty() || !grids->front())
            throw Error(path + ": cannot read the OpenVDB file (no grid in it)");
        base = grids->front();
    } catch (const std::ios_base::failure&) {
        throw Error(path +
                    ": cannot read the OpenVDB file (it ends before the data its fields "
                    "announce: the file is damaged or truncated)");
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": cannot read the OpenVDB file (" + e.what() + ")");
    } catch (const std::bad_alloc&) {
        // OpenVDB allocates what a file's size fields say before it reads the data: a damaged
        // or hostile field asks for terabytes.
        throw Error(path +
                    ": cannot read the OpenVDB file (a size field asks for more memory "
                    "than there is: the file is damaged)");
    } catch (const std::length_error&) {
        throw Error(path +
                    ": cannot read the OpenVDB file (a size field is out of range: the "
                    "file is damaged)");
    }
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid)
        throw Error(path + ": grid '" + base->getName() + "' has type " + base->valueType() +
                    ", expected a float grid");
    if (!grid->transform().isLinear())
        throw Error(path + ": grid '" + grid->getName() + "' has a non-linear transform (" +
                    grid->transform().mapType() + ")");

    Volume volume;
    volume.sourcePath = path;
    volume.grid = grid;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (auto it = grid->tree().cbeginValueAll(); it; ++it) {
        if (!std::isfinite(*it)) {
            const openvdb::Coord c = it.getCoord();
            throw Error(path + ": grid '" + grid->getName() + "' holds a non-finite value at (" +
                        std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " +
                        std::to_string(c.z()) + "); volumes must hold finite values");
        }
        lo = std::min(lo, double(*it));
        hi = std::max(hi, double(*it));
    }
    openvdb::Vec3i dims, origin(0, 0, 0);
    if (readMeta<openvdb::Vec3IMetadata>(*grid, kMetaDims, dims)) {
        readMeta<openvdb::Vec3IMetadata>(*grid, kMetaIndexOrigin, origin);
    } else {
        // A foreign grid: its extent is the bounding box of everything stored.
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        if (box.empty()) throw Error(path + ": grid '" + grid->getName() + "' is empty");
        for (int a = 0; a < 3; ++a)  // CoordBBox::dim() is int: a span of 2^31 would overflow
            if (int64_t(box.max()[a]) - box.min()[a] + 1 > int64_t(1) << 30)
                throw Error(path + ": grid '" + grid->getName() +
                            "' spans more than 2^30 voxels "
                            "along an axis; Lobe's volumes span at most that");
        dims = openvdb::Vec3i(box.dim().x(), box.dim().y(), box.dim().z());
        origin = openvdb::Vec3i(box.min().x(), box.min().y(), box.min().z());
    }
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1 || dims[a] > (1 << 30))
            throw Error(path + ": metadata " + kMetaDims + " is not in 1 … 2^30 per axis");
        volume.dims[a] = dims[a];
        volume.indexOrigin[a] = origin[a];
    }
    // Voxel counts are int64 and exact in double up to 2^53: a box beyond that (2^30 a side is
    // 2^90) is refused by its size, before any count overflows.
    const double boxVoxels = double(dims[0]) * double(dims[1]) * double(dims[2]);
    if (boxVoxels > 9007199254740992.0)
        throw Error(path + ": grid '" + grid->getName() + "' spans " + std::to_string(dims[0]) +
                    " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) +
                    " voxels, more than 2^53 in all; Lobe's volumes hold at most that");
    // Lobe's own metadata, checked like any input: what would the volume hold otherwise?
    const auto finiteMeta = [&](const char* key, double& value) {
        if (readMeta<openvdb::DoubleMetadata>(*grid, key, value) && !std::isfinite(value))
            throw Error(path + ": metadata " + key + " is not a finite number");
    };
    double storedScale = 1.0;
    finiteMeta(kMetaValueScale, storedScale);
    if (!(storedScale > 0.0))
        throw Error(path + ": metadata " + kMetaValueScale + " is not positive");
    volume.originalMin = lo / storedScale;
    volume.originalMax = hi / storedScale;
    finiteMeta(kMetaOriginalMin, volume.originalMin);
    finiteMeta(kMetaOriginalMax, volume.originalMax);
    finiteMeta(kMetaBackground, volume.background);
    std::string source;
    if (readMeta<openvdb::StringMetadata>(*grid, kMetaSource, source)) volume.sourcePath = source;
    // The world scale of tiny voxels (volume/grid_world.h), as writeVdb keeps it.
    if ((*grid)[kMetaWorldScale] && (!grid->getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale) ||
                                     !validWorldScale(gridWorldScale(*grid))))
        throw Error(path + ": metadata " + kMetaWorldScale +
                    " is not a power of two in [2^-340, 2^-9] (a double)");

    // Further scaling asked for now composes with what the file already holds.
    const double extra =
        valueScaleFor(path, options, volume.originalMax * storedScale, [&](double p) {
            // Over every voxel of the box, as `lobe info` (summaryOf) counts them.
            return percentileHistogram(volume).percentile(p);
        });
    volume.valueScale = storedScale * extra;
    if (extra != 1.0)
        for (auto it = grid->tree().beginValueAll(); it; ++it)
            it.setValue(static_cast<float>(double(*it) * extra));
    if (options.background > volume.background) {
        applyBackground(grid->tree(), static_cast<float>(options.background * volume.valueScale));
        volume.background = options.background;
    }
    const openvdb::Vec3d o = gridIndexToWorld(*grid, openvdb::Vec3d(0, 0, 0));
    for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d e(0, 0, 0);
        e[a] = 1.0;
        volume.spacing[a] = (gridIndexToWorld(*grid, e) - o).length();
    }
    return volume;
}

Volume loadDicom(const std::vector<std::string>& inputs, const LoadOptions& options) {
    const std::string where = inputs.empty() ? std::string("DICOM") : inputs.front();
    if (options.hasLayout)
        throw Error(where +
                    ": a DICOM series has its own layout; the raw-file options (--dims, "
                    "--type, --endian, --spacing, --offset; a scene's dims, type, endian, "
                    "spacing) do not apply");
    std::string source = where;
    if (inputs.size() > 1) source += " (and " + std::to_string(inputs.size() - 1) + " more files)";
    if (!options.series.empty()) source += ", series " + options.series;
    detail::DenseVolume dense = detail::readDicomDense(inputs, options.series);
    std::string note = dense.note;
    Volume v = buildVolume(std::move(dense), source, options);
    v.note = note;
    return v;
}

Volume loadArray(const VolumeArray& array, const LoadOptions& options) {
    if (options.hasLayout)
        throw Error(array.name +
                    ": an array has its own layout; the raw-file options (dims, type, "
                    "endian, spacing) do not apply");
    return buildVolume(detail::readArrayDense(array), array.name, options);
}

Volume loadVolume(const std::vector<std::string>& paths, const LoadOptions& options) {
    if (paths.size() == 1) return loadVolume(paths.front(), options);
    for (const std::string& p : paths)
        if (!detail::hasDicomMagic(p))
            throw Error(p +
                        ": several input files are read as the slices of one DICOM series, "
                        "but this is not a DICOM file (no 'DICM' at byte 128)");
    return loadDicom(paths, options);
}

Volume loadVolume(const std::string& path, const LoadOptions& options) {
    using detail::endsWith;
    if (endsWith(path, ".nii") || endsWith(path, ".nii.gz")) return loadNifti(path, options);
    if (endsWith(path, ".nhdr")) return loadNrrd(path, options);
    if (endsWith(path, ".mgh") || endsWith(path, ".mgz") || endsWith(path, ".mgh.gz"))
        return loadMgh(path, options);
    if (endsWith(path, ".vdb")) return loadVdb(path, options);
    // A folder or a file with the DICOM magic, whatever its name (DICOM files are often named
    // IM0001 or by their UID): never raw voxels.
    if (detail::isDicomInput(path)) return loadDicom({path}, options);
    if (!options.series.empty())
        throw Error(path + ": a series is chosen, but this is not a DICOM file or folder");
    if (!std::ifstream(path, std::ios::binary))
        throw Error(path + ": cannot open the file (" + std::strerror(errno) + ")");
    if (!options.hasLayout)
        throw Error(path +
                    ": a headerless (raw) volume needs its layout: give --dims X,Y,Z, "
                    "--type, --endian and --spacing (known formats: .nii, .nii.gz, .nhdr, "
                    ".mgh, .mgz, .vdb, DICOM series as a folder or files)");
    RawLayout layout = options.layout;
    layout.gzip = endsWith(path, ".gz");
    return loadRaw(path, layout, options);
}

void writeVdb(const Volume& volume, const std::string& path, const std::string& gridName) {
    initializeOpenVdb();
    if (!volume.grid) throw Error(path + ": no grid to write");
    openvdb::FloatGrid::Ptr out = volume.grid->copy();  // shares the tree; own metadata
    out->setName(gridName.empty() ? std::string(kDefaultGridName) : gridName);
    out->insertMeta(kMetaDims, openvdb::Vec3IMetadata(
                                   openvdb::Vec3i(volume.dims[0], volume.dims[1], volume.dims[2])));
    out->insertMeta(kMetaIndexOrigin,
                    openvdb::Vec3IMetadata(openvdb::Vec3i(
                        volume.indexOrigin[0], volume.indexOrigin[1], volume.indexOrigin[2])));
    out->insertMeta(kMetaSource, openvdb::StringMetadata(volume.sourcePath));
    out->insertMeta(kMetaOriginalMin, openvdb::DoubleMetadata(volume.originalMin));
    out->insertMeta(kMetaOriginalMax, openvdb::DoubleMetadata(volume.originalMax));
    out->insertMeta(kMetaValueScale, openvdb::DoubleMetadata(volume.valueScale));
    out->insertMeta(kMetaBackground, openvdb::DoubleMetadata(volume.background));

    // Named after this host and process (core/temporary_file.h), so a run killed while writing
    // leaves a file the next run into the folder recognises and removes.
    const std::string temp = temporarySibling(path);
    const RemovedOnInterrupt guard(temp);
    // Through a stream of our own: openvdb::io::File does not report a short write (a full disk
    // left a truncated .vdb and exit 0), the stream's state does, and close() flushes.
    try {
        std::ofstream os(temp, std::ios::binary | std::ios::trunc);
        if (!os)
            throw Error(path + ": cannot write the OpenVDB file (cannot create '" + temp +
                        "': " + std::strerror(errno) + ")");
        openvdb::io::Stream(os).write({out});
        os.close();
        if (!os)
            throw Error(path + ": cannot write the OpenVDB file (" + std::strerror(errno) +
                        "; a full disk?)");
    } catch (const openvdb::Exception& e) {
        std::remove(temp.c_str());
        throw Error(path + ": cannot write the OpenVDB file (" + e.what() + ")");
    } catch (const Error&) {
        std::remove(temp.c_str());
        throw;
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        std::remove(temp.c_str());
        throw Error(path + ": cannot move the finished file into place");
    }
}

namespace {

// FNV-1a 64 (Fowler, Noll, Vo; the parameters of IETF draft-eastlake-fnv) over bytes.
struct Fnv1a64 {
    std::uint64_t h = 1469598103934665603ull;
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
    template <class T>
    void value(const T& v) {
        add(&v, sizeof v);
    }
};

}  // namespace

std::string volumeContentHash(const Volume& volume) {
    Fnv1a64 f;
    if (!volume.grid) return "none";
    const openvdb::math::Mat4d m = gridWorldMatrix(*volume.grid);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) f.value(m[r][c]);
    for (int a = 0; a < 3; ++a) {
        f.value(volume.dims[a]);
        f.value(volume.indexOrigin[a]);
    }
    f.value(volume.valueScale);
    f.value(volume.background);
    const openvdb::FloatTree& tree = volume.grid->tree();
    f.value(tree.background());
    // Leaves: origin, active mask and the 512 values (stored values only, not the memory
    // layout around them).
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord o = leaf->origin();
        f.value(o);
        const auto& mask = leaf->getValueMask();
        for (openvdb::Index w = 0; w < mask.WORD_COUNT; ++w)
            f.value(mask.getWord<openvdb::Index64>(w));
        f.add(leaf->buffer().data(), leaf->SIZE * sizeof(float));
    }
    // Tiles above the leaves: where, how large, the value and whether active.
    auto tile = tree.cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        f.value(tile.getCoord());
        f.value(tile.getLevel());
        f.value(*tile);
        f.value(tile.isValueOn());
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(f.h));
    return text;
}

VolumeStats computeStats(const Volume& volume) {
    VolumeStats s;
    const openvdb::FloatGrid& grid = *volume.grid;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0;
    const std::array<int, 3>& o = volume.indexOrigin;
    const openvdb::CoordBBox box(
        openvdb::Coord(o[0], o[1], o[2]),
        openvdb::Coord(o[0] + volume.dims[0] - 1, o[1] + volume.dims[1] - 1,
                       o[2] + volume.dims[2] - 1));
    s.voxels = std::int64_t(volume.dims[0]) * volume.dims[1] * volume.dims[2];
    // Over what the tree stores (voxels and tiles, each clipped to the box), then the background
    // for the voxels of the box the tree does not store: time in proportion to the stored data,
    // not to the box (a foreign grid's two voxels 1e5 apart span 1e15 voxels).
    std::int64_t covered = 0;
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        openvdb::CoordBBox b;
        it.getBoundingBox(b);
        b.intersect(box);
        if (b.empty()) continue;
        const std::int64_t n = std::int64_t(b.volume());
        const double v = *it;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        sum += v * double(n);
        covered += n;
    }
    if (covered < s.voxels) {
        const double background = grid.background();
        lo = std::min(lo, background);
        hi = std::max(hi, background);
        sum += background * double(s.voxels - covered);
    }
    s.min = lo;
    s.max = hi;
    s.mean = s.voxels > 0 ? sum / double(s.voxels) : 0.0;
    s.activeVoxels = static_cast<std::int64_t>(grid.activeVoxelCount());
    s.memoryBytes = static_cast<std::int64_t>(grid.memUsage());
    for (int corner = 0; corner < 8; ++corner) {
        openvdb::Vec3d p;
        for (int a = 0; a < 3; ++a) p[a] = o[a] - 0.5 + ((corner >> a) & 1 ? volume.dims[a] : 0);
        s.worldBox.expand(gridIndexToWorld(grid, p));
    }
    return s;
}

ValueHistogram valueHistogram(const Volume& volume, double lo, double hi, int bins,
                              bool activeOnly) {
    ValueHistogram h;
    h.lo = lo;
    h.hi = hi;
    h.counts.assign(std::size_t(std::max(1, bins)), 0);
    const auto binOf = [&](double v) {
        if (!(hi > lo)) return std::size_t(0);
        const double f = (v - lo) / (hi - lo) * double(h.counts.size());
        return std::size_t(std::min(double(h.counts.size() - 1), std::max(0.0, std::floor(f))));
    };
    const openvdb::FloatGrid& grid = *volume.grid;
    const std::array<int, 3>& o = volume.indexOrigin;
    const openvdb::CoordBBox box(
        openvdb::Coord(o[0], o[1], o[2]),
        openvdb::Coord(o[0] + volume.dims[0] - 1, o[1] + volume.dims[1] - 1,
                       o[2] + volume.dims[2] - 1));
    std::int64_t covered = 0;
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        if (activeOnly && !it.isValueOn()) continue;
        openvdb::CoordBBox b;
        it.getBoundingBox(b);
        b.intersect(box);
        if (b.empty()) continue;
        const std::int64_t n = std::int64_t(b.volume());
        h.counts[binOf(*it)] += n;
        covered += n;
    }
    const std::int64_t voxels = std::int64_t(volume.dims[0]) * volume.dims[1] * volume.dims[2];
    if (!activeOnly && covered < voxels) h.counts[binOf(grid.background())] += voxels - covered;
    return h;
}

ValueHistogram percentileHistogram(const Volume& volume, bool activeOnly) {
    // kPercentileBins (65 536): percentiles to 1.5e-5 of the value range.
    const VolumeStats stats = computeStats(volume);
    return valueHistogram(volume, stats.min, stats.max, kPercentileBins, activeOnly);
}

double ValueHistogram::percentile(double p) const {
    std::int64_t total = 0;
    for (std::int64_t c : counts) total += c;
    if (total == 0) return std::nan("");
    // Nearest rank: the ceil(p/100 · N)-th smallest value (at least the first).
    const std::int64_t rank =
        std::max<std::int64_t>(1, std::int64_t(std::ceil(p / 100.0 * double(total))));
    std::int64_t seen = 0;
    for (std::size_t b = 0; b < counts.size(); ++b) {
        seen += counts[b];
        if (seen >= rank) return lo + (hi - lo) * double(b) / double(counts.size());
    }
    return hi;
}

namespace {

VolumeSummary summaryOf(const Volume& volume, const std::string& path) {
    const VolumeStats s = computeStats(volume);
    VolumeSummary out;
    out.path = path;
    out.sourcePath = volume.sourcePath;
    out.gridName = volume.grid->getName();
    out.dims = volume.dims;
    out.indexOrigin = volume.indexOrigin;
    out.spacing = volume.spacing;
    const openvdb::Vec3d first = gridIndexToWorld(
        *volume.grid,
        openvdb::Vec3d(volume.indexOrigin[0], volume.indexOrigin[1], volume.indexOrigin[2]));
    for (int a = 0; a < 3; ++a) {
        out.worldMin[a] = s.worldBox.min()[a];
        out.worldMax[a] = s.worldBox.max()[a];
        out.worldOfFirstVoxel[a] = first[a];
    }
    out.originalMin = volume.originalMin;
    out.originalMax = volume.originalMax;
    out.valueScale = volume.valueScale;
    out.background = volume.background;
    out.min = s.min;
    out.max = s.max;
    out.mean = s.mean;
    out.voxels = s.voxels;
    out.activeVoxels = s.activeVoxels;
    out.memoryBytes = s.memoryBytes;
    const ValueHistogram all = percentileHistogram(volume, false);
    const ValueHistogram active = percentileHistogram(volume, true);
    for (std::size_t i = 0; i < VolumeSummary::kPercents.size(); ++i) {
        out.percentilesAll[i] = all.percentile(VolumeSummary::kPercents[i]);
        out.percentilesActive[i] = active.percentile(VolumeSummary::kPercents[i]);
    }
    return out;
}

}  // namespace

namespace {
std::string pathsText(const std::vector<std::string>& paths) {
    if (paths.empty()) throw Error("no input volume given");
    if (paths.size() == 1) return paths.front();
    return paths.front() + " (and " + std::to_string(paths.size() - 1) + " more files)";
}
}  // namespace

VolumeSummary summarizeVolume(const std::string& path, const LoadOptions& options, double blurFwhm,
                              int histogramBins) {
    return summarizeVolume(std::vector<std::string>{path}, options, blurFwhm, histogramBins);
}

VolumeSummary convertVolume(const std::string& in, const std::string& out,
                            const LoadOptions& options, const std::string& gridName) {
    return convertVolume(std::vector<std::string>{in}, out, options, gridName);
}

VolumeSummary summarizeVolume(const std::vector<std::string>& paths, const LoadOptions& options,
                              double blurFwhm, int histogramBins) {
    const std::string path = pathsText(paths);
    if (!(blurFwhm >= 0.0) || !std::isfinite(blurFwhm))
        throw Error(path + ": the blur FWHM must be finite and not negative");
    if (histogramBins < 0 || histogramBins > 100000)
        throw Error(path + ": the histogram's bins must be 1 … 100000");
    const auto start = std::chrono::steady_clock::now();
    Volume volume = loadVolume(paths, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (blurFwhm > 0.0) gaussianBlurFwhm(volume, blurFwhm);
    VolumeSummary out = summaryOf(volume, path);
    out.loadSeconds = seconds;
    out.blurFwhm = blurFwhm;
    if (histogramBins > 0) {
        const ValueHistogram h = valueHistogram(volume, out.min, out.max, histogramBins, false);
        out.histogram.lo = h.lo;
        out.histogram.hi = h.hi;
        out.histogram.counts = h.counts;
    }
    return out;
}

VolumeSummary convertVolume(const std::vector<std::string>& in, const std::string& out,
                            const LoadOptions& options, const std::string& gridName) {
    if (!detail::endsWith(out, ".vdb"))
        throw Error(out + ": the output of convert must be a .vdb file");
    pathsText(in);
    const auto start = std::chrono::steady_clock::now();
    const Volume volume = loadVolume(in, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    writeVdb(volume, out, gridName);
    VolumeSummary summary = summaryOf(volume, out);
    summary.gridName = gridName.empty() ? std::string(kDefaultGridName) : gridName;
    summary.loadSeconds = seconds;
    return summary;
}

}  // namespace lobe
