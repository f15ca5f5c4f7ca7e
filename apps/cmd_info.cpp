// `lobe info FILE [layout options]`: loads a volume as the renderer would (volume/volume.h) and
// prints its dimensions, spacing, world bounding box, value range, mean, percentiles (1, 5, 50,
// 95, 99 %), active voxels, the grid's memory and the load time (FILE may be a DICOM folder or
// several DICOM files, --series picks a series); --blur-fwhm blurs first (as a
// scene's source does), --histogram / --bins N adds a histogram. Also home of the volume options
// `lobe convert` shares.
#include "apps/commands.h"
#include "core/error.h"
#include "volume/grid_world.h"
#include "volume/label_table.h"
#include "volume/labels.h"
#include "volume/volume_summary.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

void addVolumeOptions(CLI::App& cmd, VolumeOptionText& text) {
    cmd.add_option("--dims", text.dims, "raw files: voxels per axis, X,Y,Z (x fastest)");
    cmd.add_option("--type", text.type,
                   "raw files: uint8, int8, uint16, int16, uint32, int32, float32 or float64");
    cmd.add_option("--endian", text.endian, "raw files: little or big (multi-byte types)");
    cmd.add_option("--spacing", text.spacing, "raw files: voxel size X,Y,Z (default 1,1,1)");
    cmd.add_option("--offset", text.offset, "raw files: bytes to skip before the voxels");
    cmd.add_option("--scale", text.scale, "multiply every value by S (default 1)");
    cmd.add_option("--normalize", text.normalize,
                   "divide every value by D (e.g. CThead 3272), by the data maximum with 'max', "
                   "or by a percentile of every voxel's value with 'pNN' (e.g. p99, the number "
                   "lobe info prints for it)");
    cmd.add_option("--background", text.background,
                   "values <= B (file units) are stored inactive: skipped empty space (default 0)");
    cmd.add_option("--series", text.series,
                   "DICOM: the SeriesInstanceUID of the series to read when the files hold several "
                   "(without it, such input is an error that lists them)");
}

void printVolumeSummary(const VolumeSummary& s) {
    std::printf("file            %s\n", s.path.c_str());
    if (s.sourcePath != s.path) std::printf("source          %s\n", s.sourcePath.c_str());
    std::printf("grid            %s\n", s.gridName.c_str());
    std::printf("dimensions      %d x %d x %d  (%lld voxels", s.dims[0], s.dims[1], s.dims[2],
                static_cast<long long>(s.voxels));
    if (s.indexOrigin[0] != 0 || s.indexOrigin[1] != 0 || s.indexOrigin[2] != 0)
        std::printf(", first index %d,%d,%d", s.indexOrigin[0], s.indexOrigin[1], s.indexOrigin[2]);
    std::printf(")\n");
    std::printf("spacing         %g x %g x %g\n", s.spacing[0], s.spacing[1], s.spacing[2]);
    std::printf("voxel (0,0,0)   at world (%g, %g, %g)\n", s.worldOfFirstVoxel[0],
                s.worldOfFirstVoxel[1], s.worldOfFirstVoxel[2]);
    std::printf("world box       (%g, %g, %g) .. (%g, %g, %g)\n", s.worldMin[0], s.worldMin[1],
                s.worldMin[2], s.worldMax[0], s.worldMax[1], s.worldMax[2]);
    std::printf("file values     %.9g .. %.9g\n", s.originalMin, s.originalMax);
    std::printf("value scale     %.9g  (stored = file value x scale)\n", s.valueScale);
    std::printf("stored values   %.9g .. %.9g, mean %.6g\n", s.min, s.max, s.mean);
    if (s.blurFwhm > 0.0)
        std::printf("blurred         Gaussian, FWHM %g (world units)\n", s.blurFwhm);
    const auto percentiles = [&](const char* label, const std::array<double, 5>& p) {
        std::printf("%s", label);
        for (std::size_t i = 0; i < p.size(); ++i)
            std::printf("%s%g %%: %.6g", i ? ", " : "", VolumeSummary::kPercents[i], p[i]);
        std::printf("\n");
    };
    percentiles("percentiles     ", s.percentilesAll);
    if (s.activeVoxels > 0) percentiles("  active only   ", s.percentilesActive);
    std::printf("background      values <= %g (file units) inactive\n", s.background);
    std::printf("active voxels   %lld  (%.2f %%)\n", static_cast<long long>(s.activeVoxels),
                s.voxels > 0 ? 100.0 * double(s.activeVoxels) / double(s.voxels) : 0.0);
    std::printf("memory          %.2f MB  (dense float would be %.2f MB)\n",
                double(s.memoryBytes) / 1e6, double(s.voxels) * 4.0 / 1e6);
    std::printf("load time       %.3f s\n", s.loadSeconds);
    if (!s.histogram.counts.empty()) {
        // One row per bin: its value range, its voxels and a bar scaled to the fullest bin — but
        // the bin holding 0 (the background around a skull-stripped brain, say) is left out of
        // the scale when it holds more than half the voxels: its bar is cut ('>'), or every
        // other bar would be empty.
        const std::size_t n = s.histogram.counts.size();
        const auto binOf = [&](double v) {
            const double t = (v - s.histogram.lo) / (s.histogram.hi - s.histogram.lo);
            return std::size_t(std::clamp(t * double(n), 0.0, double(n - 1)));
        };
        std::int64_t total = 0;
        for (std::int64_t c : s.histogram.counts) total += c;
        const bool zeroInside =
            s.histogram.lo <= 0.0 && 0.0 <= s.histogram.hi && s.histogram.hi > s.histogram.lo;
        const std::size_t zeroBin = zeroInside ? binOf(0.0) : n;
        const bool cut = zeroBin < n && 2 * s.histogram.counts[zeroBin] > total;
        std::int64_t most = 1;
        for (std::size_t b = 0; b < n; ++b)
            if (!(cut && b == zeroBin)) most = std::max(most, s.histogram.counts[b]);
        std::printf("histogram       %zu bins over every voxel of the box%s\n", n,
                    cut ? "; bars scaled without the bin of 0, whose bar is cut (>)" : "");
        for (std::size_t b = 0; b < n; ++b) {
            const double lo =
                s.histogram.lo + (s.histogram.hi - s.histogram.lo) * double(b) / double(n);
            const double hi =
                s.histogram.lo + (s.histogram.hi - s.histogram.lo) * double(b + 1) / double(n);
            const std::int64_t c = s.histogram.counts[b];
            const bool over = c > most;
            std::string bar(std::size_t(40.0 * double(std::min(c, most)) / double(most) + 0.5),
                            '#');
            if (over) bar += '>';
            std::printf("  %12.6g .. %-12.6g %12lld  %6.2f %%  %s\n", lo, hi,
                        static_cast<long long>(c), total ? 100.0 * double(c) / double(total) : 0.0,
                        bar.c_str());
        }
    }
}

// `lobe info MAP --labels [--label-table T]`: the labels present in a label map, each with its
// voxel count, world box (voxel centres ± half a voxel) and name (from T, or MRIcron's MAP.txt
// beside the map).
void printLabels(const std::string& path, const std::string& tablePath) {
    const std::shared_ptr<const LabelMap> map = loadLabelMap(path);
    const LabelTable table = tablePath.empty() ? tableBeside(path) : readLabelTable(tablePath);
    std::printf("label map       %s\n", path.c_str());
    std::printf("label table     %s\n", table.empty() ? "none" : table.source.c_str());
    std::printf("labels present  %zu\n", map->labels.size());
    std::printf("%8s %10s  %-44s  %s\n", "label", "voxels", "world box (min .. max)", "name");
    for (const auto& [id, info] : map->labels) {
        openvdb::Vec3d lo(1e300), hi(-1e300);
        for (int c = 0; c < 8; ++c) {
            const openvdb::Vec3d idx((c & 1) ? info.box.max().x() + 0.5 : info.box.min().x() - 0.5,
                                     (c & 2) ? info.box.max().y() + 0.5 : info.box.min().y() - 0.5,
                                     (c & 4) ? info.box.max().z() + 0.5 : info.box.min().z() - 0.5);
            const openvdb::Vec3d w = gridIndexToWorld(*map->volume->grid, idx);
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], w[a]);
                hi[a] = std::max(hi[a], w[a]);
            }
        }
        char box[96];
        std::snprintf(box, sizeof box, "(%g, %g, %g) .. (%g, %g, %g)", lo[0], lo[1], lo[2], hi[0],
                      hi[1], hi[2]);
        const LabelEntry* e = table.find(id);
        std::printf("%8d %10lld  %-44s  %s\n", id, static_cast<long long>(info.voxels), box,
                    e ? e->name.c_str() : "");
    }
    std::vector<int> unnamed;
    if (!table.empty())
        for (const auto& [id, info] : map->labels)
            if (!table.find(id)) unnamed.push_back(id);
    if (!unnamed.empty())
        std::printf("note            %zu labels present are not in the table (first: %d)\n",
                    unnamed.size(), unnamed.front());
}

void registerInfoCommand(CLI::App& app) {
    struct Options {
        std::vector<std::string> files;
        VolumeOptionText text;
        double blurFwhm = 0.0;
        int bins = 0;
        bool histogram = false;
        bool labels = false;
        std::string labelTable;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "info",
        "Print a volume's dimensions, spacing, world box, value range, mean, percentiles, "
        "active voxels and memory, optionally a histogram (.nii, .nii.gz, .nhdr, .vdb, a "
        "DICOM series as a folder or its files; raw files with --dims --type ...)");
    cmd->add_option("FILE", options->files,
                    "the volume file; or a DICOM folder, or the DICOM files of one series")
        ->required();
    addVolumeOptions(*cmd, options->text);
    cmd->add_option("--name", options->text.gridName, ".vdb files: the grid to read");
    cmd->add_option("--blur-fwhm", options->blurFwhm,
                    "blur first, as a scene's source.blur_fwhm_mm does (world units)")
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_flag("--histogram", options->histogram,
                  "also print a histogram of the values (every voxel of the box)");
    cmd->add_option("--bins", options->bins,
                    "the histogram's bins (default 32; implies --histogram)")
        ->check(CLI::Range(1, 10000));
    cmd->add_flag("--labels", options->labels,
                  "FILE is a label map (segmentation, atlas): list the labels present with their "
                  "voxel counts, world boxes and names (from --label-table, or MRIcron's FILE.txt "
                  "beside it)");
    cmd->add_option("--label-table", options->labelTable,
                    "with --labels: the label table (FreeSurfer ColorLUT, ITK-SNAP label "
                    "description, MRIcron .txt/.lut)");
    cmd->callback([options] {
        if (options->labels || !options->labelTable.empty()) {
            if (!options->labels) throw Error("--label-table goes with --labels");
            if (options->files.size() != 1) throw Error("--labels takes one label map");
            printLabels(options->files.front(), options->labelTable);
            return;
        }
        const int bins = options->bins > 0 ? options->bins : (options->histogram ? 32 : 0);
        printVolumeSummary(summarizeVolume(options->files, parseLoadOptions(options->text),
                                           options->blurFwhm, bins));
    });
}

}  // namespace lobe
