// `lobe info FILE [layout options]`: loads a volume as the renderer would (volume/volume.h) and
// prints its dimensions, spacing, world bounding box, value range, mean, active voxels, the
// grid's memory and the load time. Also home of the volume options `lobe convert` shares.
#include "apps/commands.h"
#include "volume/volume_summary.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>

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
                   "divide every value by D, or by the data maximum with 'max' (e.g. CThead 3272)");
    cmd.add_option("--background", text.background,
                   "values <= B (file units) are stored inactive: skipped empty space (default 0)");
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
    std::printf("background      values <= %g (file units) inactive\n", s.background);
    std::printf("active voxels   %lld  (%.2f %%)\n", static_cast<long long>(s.activeVoxels),
                s.voxels > 0 ? 100.0 * double(s.activeVoxels) / double(s.voxels) : 0.0);
    std::printf("memory          %.2f MB  (dense float would be %.2f MB)\n",
                double(s.memoryBytes) / 1e6, double(s.voxels) * 4.0 / 1e6);
    std::printf("load time       %.3f s\n", s.loadSeconds);
}

void registerInfoCommand(CLI::App& app) {
    struct Options {
        std::string file;
        VolumeOptionText text;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "info", "Print a volume's dimensions, spacing, world box, value range, mean, active "
                "voxels and memory (.nii, .nii.gz, .nhdr, .vdb; raw files with --dims --type ...)");
    cmd->add_option("FILE", options->file, "the volume file")->required();
    addVolumeOptions(*cmd, options->text);
    cmd->add_option("--name", options->text.gridName, ".vdb files: the grid to read");
    cmd->callback([options] {
        printVolumeSummary(summarizeVolume(options->file, parseLoadOptions(options->text)));
    });
}

}  // namespace lobe
